# The suite's references: the oracles, the tests' reference solvers, the measurement code and
# sweepgen-report (generator/CMakeLists.txt). Compiled in this build, or, with
# SWEEPGEN_REFERENCES_FROM, linked from a release build of the same tree.
#
# SWEEPGEN_REFERENCES_FROM is for a sanitizer build that leaves the references uninstrumented
# (SWEEPGEN_SANITIZE_ORACLES=OFF, the sanitize-ci preset): there the references would be the same
# uninstrumented code compiled a second time, about 170 of that stage's 745 job-seconds
# (bench/README.md, "Build and CI time"). That build first brings the release build's references
# up to date (`cmake --build <dir> --target ...`, nothing to do where CI has just built it), so a
# stale release build is never linked.
set(SWEEPGEN_REFERENCES_FROM "" CACHE PATH
  "With SWEEPGEN_SANITIZE and SWEEPGEN_SANITIZE_ORACLES=OFF: a release build directory of this source tree whose references this build links instead of compiling them")
if(SWEEPGEN_REFERENCES_FROM)
  if(NOT SWEEPGEN_SANITIZE OR SWEEPGEN_SANITIZE_ORACLES)
    message(FATAL_ERROR "SWEEPGEN_REFERENCES_FROM=${SWEEPGEN_REFERENCES_FROM} is for a sanitizer build whose references "
                        "are uninstrumented (-DSWEEPGEN_SANITIZE=ON -DSWEEPGEN_SANITIZE_ORACLES=OFF); here they would be "
                        "compiled differently from the release build's")
  endif()
  if(NOT EXISTS ${SWEEPGEN_REFERENCES_FROM}/CMakeCache.txt)
    message(FATAL_ERROR "SWEEPGEN_REFERENCES_FROM=${SWEEPGEN_REFERENCES_FROM} is not a configured build directory "
                        "(no CMakeCache.txt): configure and build the release preset first (cmake --workflow --preset release)")
  endif()
  file(STRINGS ${SWEEPGEN_REFERENCES_FROM}/CMakeCache.txt references_source REGEX "^sweepgen_SOURCE_DIR:")
  if(NOT references_source STREQUAL "sweepgen_SOURCE_DIR:STATIC=${PROJECT_SOURCE_DIR}")
    message(FATAL_ERROR "SWEEPGEN_REFERENCES_FROM=${SWEEPGEN_REFERENCES_FROM} was configured from another source tree "
                        "(${references_source}), not ${PROJECT_SOURCE_DIR}")
  endif()
  # Public usage requirements of an imported target are INTERFACE ones.
  set(SWEEPGEN_REFERENCE_USAGE INTERFACE)
  # Where that build makes them (generator/), and the libraries among them.
  set(references_dir ${SWEEPGEN_REFERENCES_FROM}/generator)
  set(reference_libraries sweepgen_oracle sweepgen_test_oracle sweepgen_test_solvers sweepgen_measure)
  list(TRANSFORM reference_libraries PREPEND ${references_dir}/lib OUTPUT_VARIABLE reference_archives)
  list(TRANSFORM reference_archives APPEND .a)
  add_custom_target(sweepgen_references_from_release
    COMMAND ${CMAKE_COMMAND} --build ${SWEEPGEN_REFERENCES_FROM} --target ${reference_libraries} sweepgen-report
    # `sweepgen report` runs the sweepgen-report beside it (cli/report_program.hpp).
    COMMAND ${CMAKE_COMMAND} -E copy_if_different ${references_dir}/sweepgen-report ${CMAKE_CURRENT_BINARY_DIR}/sweepgen-report
    BYPRODUCTS ${reference_archives} ${CMAKE_CURRENT_BINARY_DIR}/sweepgen-report
    COMMENT "The references from the release build ${SWEEPGEN_REFERENCES_FROM}"
    USES_TERMINAL)
else()
  set(SWEEPGEN_REFERENCE_USAGE PUBLIC)
endif()

# sweepgen_reference(<name> LIBRARY|PROGRAM <source>...): the reference <name>, a static library
# or a program, compiled from <source>... with the project's warnings, or the release build's.
# Its usage requirements are given with ${SWEEPGEN_REFERENCE_USAGE}; what only compiling it needs
# (definitions, unity batches) behind if(NOT SWEEPGEN_REFERENCES_FROM).
function(sweepgen_reference name kind)
  if(SWEEPGEN_REFERENCES_FROM AND kind STREQUAL "LIBRARY")
    add_library(${name} STATIC IMPORTED GLOBAL)
    set_target_properties(${name} PROPERTIES IMPORTED_LOCATION ${references_dir}/lib${name}.a)
    add_dependencies(${name} sweepgen_references_from_release)
  elseif(SWEEPGEN_REFERENCES_FROM)
    add_executable(${name} IMPORTED GLOBAL)
    set_target_properties(${name} PROPERTIES IMPORTED_LOCATION ${CMAKE_CURRENT_BINARY_DIR}/${name})
    add_dependencies(${name} sweepgen_references_from_release)
  else()
    if(kind STREQUAL "LIBRARY")
      add_library(${name} STATIC ${ARGN})
    else()
      add_executable(${name} ${ARGN})
    endif()
    target_compile_options(${name} PRIVATE -Wall -Wextra -Wpedantic ${SWEEPGEN_LARGE_UNIT_OPTIONS})
    # sanitize-ci's reduction (cmake/Sanitizers.cmake, SWEEPGEN_SANITIZE_ORACLES) where they are
    # compiled here (clang takes the last -f[no-]sanitize).
    if(SWEEPGEN_SANITIZE AND NOT SWEEPGEN_SANITIZE_ORACLES)
      target_compile_options(${name} PRIVATE -fno-sanitize=all)
    endif()
  endif()
endfunction()
