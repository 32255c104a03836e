# The consumer_project test (cmake -P): README.md's "Install" section, tried. A project outside the
# tree finds an installed sweepgen and generates a solver with sweepgen_add_solver() from the
# README's first scene; the installed `sweepgen report` finds its data in the installation.
#
#   cmake -DSWEEPGEN_BUILD_DIR=<build tree> -DSWEEPGEN_SOURCE_DIR=<source tree>
#         -DSCRATCH_DIR=<dir, emptied first> [-DCONSUMER_GENERATOR=<gen>]
#         [-DCONSUMER_MAKE_PROGRAM=<make>] [-DCONSUMER_CXX_COMPILER=<c++>]
#         [-DCONSUMER_BUILD_TYPE=<cfg>] -P run_consumer_test.cmake
#
# Steps, each fatal on a non-zero exit (printing its output):
#   1. cmake --install the built sweepgen into SCRATCH_DIR/prefix;
#   2. copy tests/consumer and robots/planar/planar_rpr.urdf into SCRATCH_DIR/project, and write
#      README.md's first scene (the yaml block under "### A first scene") as its scene.yaml;
#   3. configure it with CMAKE_PREFIX_PATH=SCRATCH_DIR/prefix (and check that the installed
#      package is the one found), build it (the generator must run), run `consumer`;
#   4. regeneration: a no-op rebuild must not run the generator; touching the URDF (known to the
#      build only through the generator's depfile) and then the scene must each rerun it and, the
#      output being the same, recompile nothing; a changed scene must recompile the solver;
#   5. the installed report, moved to another prefix: `sweepgen report --quick` names the bundled
#      scene of that prefix and, given a compiler that does not exist, stops at once (exit 3)
#      saying so.
cmake_minimum_required(VERSION 3.25)

foreach(var SWEEPGEN_BUILD_DIR SWEEPGEN_SOURCE_DIR SCRATCH_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "run_consumer_test.cmake: pass -D${var}=...")
  endif()
endforeach()

set(prefix "${SCRATCH_DIR}/prefix")
set(project "${SCRATCH_DIR}/project")
set(build "${SCRATCH_DIR}/build")
set(generating_marker "sweepgen: generating planar_arm_solver")
# What the build prints when it compiles the solver library's generated source.
set(compiling_marker "planar_arm_solver.dir/")

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

# expect_in_output(<name> <output> <marker> <what> TRUE|FALSE): whether the build output shows
# `marker` (`what` for the message).
function(expect_in_output name output marker what expected)
  string(FIND "${output}" "${marker}" at)
  if(expected AND at EQUAL -1)
    message(FATAL_ERROR "consumer_project: ${name}: ${what} did not happen, but should have\n"
      "---- build output ----\n${output}\n----------------------")
  elseif(NOT expected AND NOT at EQUAL -1)
    message(FATAL_ERROR "consumer_project: ${name}: ${what} happened, but should not have\n"
      "---- build output ----\n${output}\n----------------------")
  endif()
endfunction()
# An edit right after a build that restat'ed the generator's outputs waits a second, as a person's
# edit would: the file system stamps times from a clock that ticks every few milliseconds, and
# ninja's record of those outputs may be later than an edit made at once (seen: 2 runs in 12 left
# one solver out of the rebuild).
function(pause_before_edit)
  execute_process(COMMAND ${CMAKE_COMMAND} -E sleep 1)
endfunction()
function(expect_generator_run name output expected)
  expect_in_output("${name}" "${output}" "${generating_marker}" "the generator's run" ${expected})
endfunction()
function(expect_solver_compiled name output expected)
  expect_in_output("${name}" "${output}" "${compiling_marker}" "the solver's compile" ${expected})
endfunction()

file(REMOVE_RECURSE "${SCRATCH_DIR}")
file(MAKE_DIRECTORY "${SCRATCH_DIR}")

# 1. Install.
set(install_command ${CMAKE_COMMAND} --install "${SWEEPGEN_BUILD_DIR}" --prefix "${prefix}")
if(CONSUMER_BUILD_TYPE)
  list(APPEND install_command --config "${CONSUMER_BUILD_TYPE}")
endif()
run_step(install out COMMAND ${install_command})

# 2. The project, self-contained: README.md's first scene names planar_rpr.urdf next to it.
file(COPY "${SWEEPGEN_SOURCE_DIR}/tests/consumer/" DESTINATION "${project}"
  PATTERN "*.cmake" EXCLUDE PATTERN "subdirectory" EXCLUDE PATTERN "python_finding" EXCLUDE)
file(COPY "${SWEEPGEN_SOURCE_DIR}/robots/planar/planar_rpr.urdf" DESTINATION "${project}")
file(READ "${SWEEPGEN_SOURCE_DIR}/README.md" readme)
string(FIND "${readme}" "### A first scene" at)
if(at EQUAL -1)
  message(FATAL_ERROR "consumer_project: README.md has no section '### A first scene'")
endif()
string(SUBSTRING "${readme}" ${at} -1 readme)
string(REGEX MATCH "```yaml\n([^`]*)```" block "${readme}")
if(NOT CMAKE_MATCH_1)
  message(FATAL_ERROR "consumer_project: no ```yaml block under README.md's '### A first scene'")
endif()
file(WRITE "${project}/scene.yaml" "${CMAKE_MATCH_1}")

# 3. Configure, build, run.
include("${CMAKE_CURRENT_LIST_DIR}/configure_options.cmake")
consumer_configure_options(configure_args)
list(APPEND configure_args -S "${project}" -B "${build}" "-DCMAKE_PREFIX_PATH=${prefix}"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF -DCMAKE_FIND_USE_SYSTEM_PACKAGE_REGISTRY=OFF)
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

# 4. Regeneration: an unchanged output is left untouched, so nothing recompiles.
run_step("no-op rebuild" out COMMAND ${build_command})
expect_generator_run("no-op rebuild" "${out}" FALSE)

file(TOUCH "${project}/planar_rpr.urdf")
run_step("rebuild after touching the URDF" out COMMAND ${build_command})
expect_generator_run("rebuild after touching the URDF" "${out}" TRUE)
expect_solver_compiled("rebuild after touching the URDF" "${out}" FALSE)

pause_before_edit()
file(TOUCH "${project}/scene.yaml")
run_step("rebuild after touching the scene" out COMMAND ${build_command})
expect_generator_run("rebuild after touching the scene" "${out}" TRUE)
expect_solver_compiled("rebuild after touching the scene" "${out}" FALSE)

pause_before_edit()
file(READ "${project}/scene.yaml" scene)
string(REPLACE "gravity: [0, -9.81, 0]" "gravity: [0, -9.80665, 0]" changed "${scene}")
if(changed STREQUAL scene)
  message(FATAL_ERROR "consumer_project: README.md's first scene has no 'gravity: [0, -9.81, 0]' to change")
endif()
file(WRITE "${project}/scene.yaml" "${changed}")
run_step("rebuild after changing the scene" out COMMAND ${build_command})
expect_solver_compiled("rebuild after changing the scene" "${out}" TRUE)

run_step("run after regeneration" out COMMAND "${consumer_exe}")

# 5. The installed report finds its bundled scene beside the program, wherever the installation
# is moved, and says at once what it lacks (here the compiler), before any work.
set(moved "${SCRATCH_DIR}/moved-prefix")
file(RENAME "${prefix}" "${moved}")
execute_process(COMMAND "${moved}/bin/sweepgen" report --quick --cxx "${SCRATCH_DIR}/no-such-c++"
                        --out "${SCRATCH_DIR}/report"
  RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
set(expected_scene "${moved}/share/sweepgen/robots/panda/panda_nc6.yaml")
string(FIND "${err}" "${expected_scene}" scene_at)
string(FIND "${err}" "no-such-c++" compiler_at)
if(NOT result EQUAL 3 OR scene_at EQUAL -1 OR compiler_at EQUAL -1)
  message(FATAL_ERROR "consumer_project: the installed `sweepgen report --quick` should name ${expected_scene} "
    "and stop with exit 3 on the missing compiler; exit ${result}\n---- stderr ----\n${err}\n---- stdout ----\n${out}")
endif()
message(STATUS "consumer_project: installed report: ok")
message(STATUS "consumer_project: passed")
