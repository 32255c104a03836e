# Shared by fuzz/CMakeLists.txt (the libFuzzer targets) and tests/CMakeLists.txt (the regression
# test test_fuzz_regressions, built in every configuration): the fuzz targets' entry functions
# and their seed inputs, so that both run the same code on the same seeds.

if(NOT TARGET sweepgen_fuzz_entries)
  # The bundled URDFs are compiled in (fuzz_entries.hpp: bundled_urdfs), so that a fuzzer runs
  # wherever its build is moved or mounted.
  file(GLOB bundled_urdfs CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/robots/*/*.urdf)
  add_custom_command(
    OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/embedded_robots.cpp
    COMMAND ${CMAKE_COMMAND} -DDIR=${PROJECT_SOURCE_DIR}/robots -DGLOB=*/*.urdf -DHEADER=fuzz_entries.hpp
            -DNAMESPACE=sweepgen::fuzz -DFUNCTION=bundled_urdfs
            -DOUTPUT=${CMAKE_CURRENT_BINARY_DIR}/embedded_robots.cpp -P ${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake
    DEPENDS ${bundled_urdfs} ${PROJECT_SOURCE_DIR}/cmake/embed_files.cmake
    COMMENT "Embedding robots/*/*.urdf for the fuzzers")
  add_library(sweepgen_fuzz_entries STATIC
    ${PROJECT_SOURCE_DIR}/fuzz/fuzz_entries.cpp
    ${CMAKE_CURRENT_BINARY_DIR}/embedded_robots.cpp)
  target_include_directories(sweepgen_fuzz_entries PUBLIC ${PROJECT_SOURCE_DIR}/fuzz)
  # The solve-line reader is the sweepgen program's (generator/CMakeLists.txt).
  target_link_libraries(sweepgen_fuzz_entries PUBLIC sweepgen_core sweepgen_solve_line nlohmann_json::nlohmann_json)
  target_compile_options(sweepgen_fuzz_entries PRIVATE -Wall -Wextra -Wpedantic)
  if(SWEEPGEN_FUZZ)
    target_compile_options(sweepgen_fuzz_entries PRIVATE -fsanitize=fuzzer-no-link)  # coverage feedback
  endif()
endif()

# sweepgen_fuzz_seeds(TARGET DIR): writes the seed inputs of fuzz target TARGET (urdf, scene or
# solve_line) into DIR: what robots/ bundles for that reader (every URDF; every scene; each line of
# robots/panda/example_states.jsonl as a file) and the hand-written seeds in fuzz/corpus/TARGET/.
# Runs at configure time; a change to any of those files reconfigures.
function(sweepgen_fuzz_seeds target dir)
  set(robots ${PROJECT_SOURCE_DIR}/robots)
  file(MAKE_DIRECTORY ${dir})
  if(target STREQUAL "urdf")
    file(GLOB bundled CONFIGURE_DEPENDS ${robots}/*/*.urdf)
  elseif(target STREQUAL "scene")
    file(GLOB bundled CONFIGURE_DEPENDS ${robots}/*/*.yaml)
  elseif(target STREQUAL "solve_line")
    set(bundled)
    set(states ${robots}/panda/example_states.jsonl)
    file(READ ${states} text)
    # Split by hand rather than through a CMake list: JSON's brackets and ';' confuse lists.
    set(number 0)
    while(NOT text STREQUAL "")
      string(FIND "${text}" "\n" newline)
      if(newline EQUAL -1)
        set(line "${text}")
        set(text "")
      else()
        string(SUBSTRING "${text}" 0 ${newline} line)
        math(EXPR next "${newline} + 1")
        string(SUBSTRING "${text}" ${next} -1 text)
      endif()
      math(EXPR number "${number} + 1")
      if(NOT line MATCHES "^[ \t\r]*$")  # `sweepgen solve` skips blank lines
        file(WRITE ${dir}/example_states_${number}.json "${line}")
      endif()
    endwhile()
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${states})
  else()
    message(FATAL_ERROR "sweepgen_fuzz_seeds: unknown fuzz target '${target}' (urdf, scene, solve_line)")
  endif()
  file(GLOB handwritten CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/fuzz/corpus/${target}/*)
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${bundled} ${handwritten})
  if(bundled OR handwritten)
    file(COPY ${bundled} ${handwritten} DESTINATION ${dir})
  endif()
endfunction()
