# The configure_checks test (cmake -P): what a consumer's configure step says, checked without
# building anything (README.md, "Install" and "Python"):
#   - a project that add_subdirectory()s the repository gets only the generator (subdirectory/);
#   - sweepgen_add_solver() with a scene file that does not exist stops the configure, naming it;
#   - sweepgen_find_python() says which interpreter the modules are built for and which it passed
#     over, and sweepgen_add_python_module() names what is missing (python_finding/);
#   - this repository's own configure names a bundled scene its lists (SWEEPGEN_BATCH_ISA_SCENES,
#     SWEEPGEN_BUNDLED_SCENE_STEMS) do not have, and a scene that a test needs and the list leaves out.
#
#   cmake -DSWEEPGEN_SOURCE_DIR=<source tree> -DSCRATCH_DIR=<dir, emptied first>
#         [-DCONSUMER_GENERATOR=<gen>] [-DCONSUMER_MAKE_PROGRAM=<make>] [-DCONSUMER_CXX_COMPILER=<c++>]
#         -P run_configure_checks.cmake
cmake_minimum_required(VERSION 3.25)

foreach(var SWEEPGEN_SOURCE_DIR SCRATCH_DIR)
  if(NOT ${var})
    message(FATAL_ERROR "run_configure_checks.cmake: pass -D${var}=...")
  endif()
endforeach()
file(REMOVE_RECURSE "${SCRATCH_DIR}")
file(MAKE_DIRECTORY "${SCRATCH_DIR}")
include("${CMAKE_CURRENT_LIST_DIR}/configure_options.cmake")
consumer_configure_options(common)

# configure(<name> <project> SUCCEEDS|FAILS CONTAINS <text...> [LACKS <text...>] [ENV <VAR=value...>] ARGS <args...>):
# configures tests/consumer/<project> (an absolute <project>: that directory) in a directory of its
# own and checks the outcome and output.
function(configure name project outcome)
  cmake_parse_arguments(PARSE_ARGV 3 arg "" "" "CONTAINS;LACKS;ENV;ARGS")
  set(source "${SWEEPGEN_SOURCE_DIR}/tests/consumer/${project}")
  if(IS_ABSOLUTE "${project}")
    set(source "${project}")
  endif()
  execute_process(COMMAND ${CMAKE_COMMAND} -E env ${arg_ENV} ${CMAKE_COMMAND} ${common}
                          -S "${source}" -B "${SCRATCH_DIR}/${name}"
                          "-DSWEEPGEN_SOURCE=${SWEEPGEN_SOURCE_DIR}" ${arg_ARGS}
    RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE output)
  string(REGEX REPLACE "[ \n]+" " " flat "${output}")  # CMake wraps long messages
  set(problem "")
  if(outcome STREQUAL "SUCCEEDS" AND NOT result EQUAL 0)
    set(problem "the configure failed (${result})")
  elseif(outcome STREQUAL "FAILS" AND result EQUAL 0)
    set(problem "the configure succeeded")
  endif()
  foreach(text ${arg_CONTAINS})
    string(FIND "${flat}" "${text}" at)
    if(at EQUAL -1)
      string(APPEND problem " no '${text}' in the output;")
    endif()
  endforeach()
  foreach(text ${arg_LACKS})
    string(FIND "${flat}" "${text}" at)
    if(NOT at EQUAL -1)
      string(APPEND problem " '${text}' in the output;")
    endif()
  endforeach()
  if(problem)
    message(FATAL_ERROR "configure_checks: ${name}: ${problem}\n---- output ----\n${output}\n----------------")
  endif()
  message(STATUS "configure_checks: ${name}: ok")
endfunction()

configure(subdirectory subdirectory SUCCEEDS CONTAINS "subdirectory: only the generator")
configure(missing_scene subdirectory FAILS
  CONTAINS "sweepgen_add_solver(arm_solver): no scene file ${SCRATCH_DIR}/no_such_scene.yaml"
  ARGS "-DSCENE=${SCRATCH_DIR}/no_such_scene.yaml")

# An interpreter without NumPy: the system's, with its site-packages (where Debian's NumPy is) off.
set(fake "${SCRATCH_DIR}/bin")
file(MAKE_DIRECTORY "${fake}")
file(WRITE "${SCRATCH_DIR}/python3" "#!/bin/sh\nexec /usr/bin/python3 -S \"$@\"\n")
file(COPY "${SCRATCH_DIR}/python3" DESTINATION "${fake}"
  FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
# PATH is the system's alone, or with the interpreter without NumPy first (as a pyenv shim may be).
configure(python_found python_finding SUCCEEDS CONTAINS "sweepgen: Python modules are built for /usr/bin/python3 (Python 3."
  LACKS "passed over" ENV "PATH=/usr/bin:/bin")
configure(python_passed_over python_finding SUCCEEDS
  CONTAINS "sweepgen: Python modules are built for /usr/bin/python3" "passed over ${fake}/python3, which cannot import NumPy"
  ENV "PATH=${fake}:/usr/bin:/bin")
configure(python_without_numpy python_finding FAILS
  CONTAINS "sweepgen: no Python modules: NumPy for ${fake}/python3 (Debian: python3-numpy) not found"
           "sweepgen_add_python_module(arm): cannot build a Python module: NumPy for ${fake}/python3"
  LACKS "call sweepgen_find_python() first"
  ARGS "-DPython3_EXECUTABLE=${fake}/python3" -DADD_MODULE=ON)
configure(python_without_pybind11 python_finding FAILS
  CONTAINS "sweepgen: no Python modules: pybind11 (Debian: pybind11-dev) not found"
           "sweepgen_add_python_module(arm): cannot build a Python module: pybind11 (Debian: pybind11-dev) not found"
  LACKS "call sweepgen_find_python() first"
  ARGS -DCMAKE_DISABLE_FIND_PACKAGE_pybind11=ON -DADD_MODULE=ON)
configure(python_not_searched python_finding FAILS CONTAINS "call sweepgen_find_python() first"
  ARGS -DFIND=OFF -DADD_MODULE=ON)
# The repository itself (no CUDA: the checks stop before anything CUDA would add; without the
# Python modules, whose scenes the same check asks for, and whose search takes seconds).
configure(isa_scene_unknown "${SWEEPGEN_SOURCE_DIR}" FAILS
  CONTAINS "SWEEPGEN_BATCH_ISA_SCENES: panda_nc7 is not a bundled scene (robots/*/panda_nc7.yaml)"
  ARGS -DSWEEPGEN_CUDA=OFF -DSWEEPGEN_BATCH_ISA_SCENES=panda_nc7)
configure(scene_stem_unknown "${SWEEPGEN_SOURCE_DIR}" FAILS
  CONTAINS "SWEEPGEN_BUNDLED_SCENE_STEMS: no_such_scene is not a bundled scene"
  ARGS -DSWEEPGEN_CUDA=OFF -DSWEEPGEN_BUNDLED_SCENE_STEMS=no_such_scene)
configure(scene_stems_without_realtime_scenes "${SWEEPGEN_SOURCE_DIR}" FAILS
  CONTAINS "test_realtime needs the bundled scene panda_nc6, which SWEEPGEN_BUNDLED_SCENE_STEMS (planar_nc2) leaves out"
  ARGS -DSWEEPGEN_CUDA=OFF -DSWEEPGEN_BUILD_PYTHON=OFF -DSWEEPGEN_BUNDLED_SCENE_STEMS=planar_nc2)
message(STATUS "configure_checks: passed")
