# The consumer_project test (cmake -P): a project outside the tree finds an installed sweepgen
# and generates a solver with sweepgen_add_solver().
#
#   cmake -DSWEEPGEN_BUILD_DIR=<build tree> -DSWEEPGEN_SOURCE_DIR=<source tree>
#         -DSCRATCH_DIR=<dir, emptied first> [-DCONSUMER_GENERATOR=<gen>]
#         [-DCONSUMER_MAKE_PROGRAM=<make>] [-DCONSUMER_CXX_COMPILER=<c++>]
#         [-DCONSUMER_BUILD_TYPE=<cfg>] -P run_consumer_test.cmake
#
# Steps, each fatal on a non-zero exit (printing its output):
#   1. cmake --install the built sweepgen into SCRATCH_DIR/prefix;
#   2. copy tests/consumer and robots/planar/planar_rpr.urdf into SCRATCH_DIR/project;
#   3. configure it with CMAKE_PREFIX_PATH=SCRATCH_DIR/prefix (and check that the installed
#      package is the one found), build it (the generator must run), run `consumer`;
#   4. regeneration: a no-op rebuild must not run the generator; touching the URDF (known to the
#      build only through the generator's depfile) and then the scene must each rerun it.
cmake_minimum_required(VERSION 3.25)

foreach(var SWEEPGEN_BUILD_DIR SWEEPGEN_SOURCE_DIR SCRATCH_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "run_consumer_test.cmake: pass -D${var}=...")
  endif()
endforeach()

set(prefix "${SCRATCH_DIR}/prefix")
set(project "${SCRATCH_DIR}/project")
set(build "${SCRATCH_DIR}/build")
set(generating_marker "sweepgen: generating consumer_solver")

# run_step(<name> <output var> COMMAND ...): runs the command, fails the test on a non-zero exit
# (or a failure to start) with the command's output; stores stdout+stderr in <output var>.
function(run_step name output_var)
  cmake_parse_arguments(PARSE_ARGV 2 arg "" "" "COMMAND")
  string(TIMESTAMP start "%s")
  execute_process(COMMAND ${arg_COMMAND}
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  string(TIMESTAMP stop "%s")
  math(EXPR seconds "${stop} - ${start}")
  if(NOT result STREQUAL "0")
    list(JOIN arg_COMMAND " " command_line)
    message(FATAL_ERROR "consumer_project: step '${name}' failed (${result})\n"
      "command: ${command_line}\n"
      "---- output ----\n${output}\n----------------")
  endif()
  message(STATUS "consumer_project: ${name}: ok (${seconds} s)")
  set(${output_var} "${output}" PARENT_SCOPE)
endfunction()

# expect_generator_run(<name> <output> TRUE|FALSE): whether the build output shows the
# generator's custom command.
function(expect_generator_run name output expected)
  string(FIND "${output}" "${generating_marker}" at)
  if(expected AND at EQUAL -1)
    message(FATAL_ERROR "consumer_project: ${name}: the generator did not run, but should have\n"
      "---- build output ----\n${output}\n----------------------")
  elseif(NOT expected AND NOT at EQUAL -1)
    message(FATAL_ERROR "consumer_project: ${name}: the generator ran, but should not have\n"
      "---- build output ----\n${output}\n----------------------")
  endif()
endfunction()

file(REMOVE_RECURSE "${SCRATCH_DIR}")
file(MAKE_DIRECTORY "${SCRATCH_DIR}")

# 1. Install.
set(install_command ${CMAKE_COMMAND} --install "${SWEEPGEN_BUILD_DIR}" --prefix "${prefix}")
if(CONSUMER_BUILD_TYPE)
  list(APPEND install_command --config "${CONSUMER_BUILD_TYPE}")
endif()
run_step(install out COMMAND ${install_command})

# 2. The project, self-contained: its scene names planar_rpr.urdf next to it.
file(COPY "${SWEEPGEN_SOURCE_DIR}/tests/consumer/" DESTINATION "${project}"
  PATTERN "run_consumer_test.cmake" EXCLUDE)
file(COPY "${SWEEPGEN_SOURCE_DIR}/robots/planar/planar_rpr.urdf" DESTINATION "${project}")

# 3. Configure, build, run.
set(configure_args -S "${project}" -B "${build}" "-DCMAKE_PREFIX_PATH=${prefix}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
if(CONSUMER_GENERATOR)
  list(APPEND configure_args -G "${CONSUMER_GENERATOR}")
endif()
if(CONSUMER_MAKE_PROGRAM)
  list(APPEND configure_args "-DCMAKE_MAKE_PROGRAM=${CONSUMER_MAKE_PROGRAM}")
endif()
if(CONSUMER_CXX_COMPILER)
  list(APPEND configure_args "-DCMAKE_CXX_COMPILER=${CONSUMER_CXX_COMPILER}")
endif()
if(CONSUMER_BUILD_TYPE)
  list(APPEND configure_args "-DCMAKE_BUILD_TYPE=${CONSUMER_BUILD_TYPE}")
endif()
run_step(configure out COMMAND ${CMAKE_COMMAND} ${configure_args})

# The package found must be the one just installed, not a build tree or a system copy.
file(STRINGS "${build}/CMakeCache.txt" found_dir REGEX "^sweepgen_DIR:")
string(REGEX REPLACE "^sweepgen_DIR:[A-Z]+=" "" found_dir "${found_dir}")
file(REAL_PATH "${found_dir}" found_dir)
file(REAL_PATH "${prefix}" real_prefix)
string(FIND "${found_dir}" "${real_prefix}/" at)
if(NOT at EQUAL 0)
  message(FATAL_ERROR "consumer_project: find_package(sweepgen) found '${found_dir}', not the install in '${real_prefix}'")
endif()

set(build_command ${CMAKE_COMMAND} --build "${build}")
if(CONSUMER_BUILD_TYPE)
  list(APPEND build_command --config "${CONSUMER_BUILD_TYPE}")
endif()
run_step(build out COMMAND ${build_command})
expect_generator_run(build "${out}" TRUE)

# The executable: in the build dir, or its per-configuration subdirectory (multi-config generators).
set(consumer_exe "")
foreach(candidate "${build}/consumer" "${build}/${CONSUMER_BUILD_TYPE}/consumer")
  if(NOT consumer_exe AND EXISTS "${candidate}" AND NOT IS_DIRECTORY "${candidate}")
    set(consumer_exe "${candidate}")
  endif()
endforeach()
if(NOT consumer_exe)
  message(FATAL_ERROR "consumer_project: no consumer executable under ${build}")
endif()
run_step(run out COMMAND "${consumer_exe}")
message(STATUS "consumer_project: consumer printed: ${out}")

# 4. Regeneration.
run_step("no-op rebuild" out COMMAND ${build_command})
expect_generator_run("no-op rebuild" "${out}" FALSE)

file(TOUCH "${project}/planar_rpr.urdf")
run_step("rebuild after touching the URDF" out COMMAND ${build_command})
expect_generator_run("rebuild after touching the URDF" "${out}" TRUE)

file(TOUCH "${project}/scene.yaml")
run_step("rebuild after touching the scene" out COMMAND ${build_command})
expect_generator_run("rebuild after touching the scene" "${out}" TRUE)

run_step("run after regeneration" out COMMAND "${consumer_exe}")
message(STATUS "consumer_project: passed")
