# The bundled scenes (robots/*/*.yaml), each generated at build time into one library
# <stem>_solver that tests/ and bench/ share, compiled warning-free under -Wall -Wextra
# -Wpedantic -Werror, and without exceptions or RTTI (-fno-exceptions -fno-rtti: what a
# real-time controller may build them with; tests/realtime/noexcept_solve.cpp runs two of them). Sets SWEEPGEN_BUNDLED_SCENES (the files) and, per scene stem,
# SWEEPGEN_SCENE_<stem>_NAMESPACE, SWEEPGEN_SCENE_<stem>_HAS_FLOAT and
# SWEEPGEN_SCENE_<stem>_HAS_DERIVATIVES, read from the one-line `solver:`, `scalars:` and
# `derivatives:` entries our scenes use.
# SWEEPGEN_BUNDLED_FROM_GENERATED (the sanitize preset): compile the committed generated/<stem>.cpp
# instead of generating each scene at build time. GeneratedFiles.MatchTheGeneratorByteForByte
# proves the two are the same bytes and runs the build's generator on every scene, so a sanitizer
# build need not run its instrumented generator over every scene once more in the build (about 95
# of its job-seconds on 2 cores).
option(SWEEPGEN_BUNDLED_FROM_GENERATED "Bundled scenes' solvers from the committed generated/ files" OFF)
set(SWEEPGEN_SOLVER_ARCH "" CACHE STRING
  "-march= for the bundled generated solvers (sweepgen_add_solver ARCH), e.g. x86-64-v3 or native; empty: the baseline")
# Sets `out` to 1 when `scene` has a line matching `regex`, else to 0.
function(sweepgen_scene_has_line out scene regex)
  file(STRINGS ${scene} lines REGEX "${regex}")
  if(lines)
    set(${out} 1 PARENT_SCOPE)
  else()
    set(${out} 0 PARENT_SCOPE)
  endif()
endfunction()
file(GLOB SWEEPGEN_BUNDLED_SCENES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/robots/*/*.yaml)
# The CUDA library <stem>_solver_cuda of the scenes in SWEEPGEN_CUDA_SCENES too, where the CUDA
# language is enabled (the top-level CMakeLists.txt enables it when CMake finds a CUDA compiler).
# One scene by default: it builds sweepgen_add_solver's CUDA path with nvcc, and every bundled
# scene's device code is checked by clang in the tests (tests/device_code); nvcc on all of them
# took ~400 job-seconds a build for nothing that runs without a GPU (bench/README.md, "Build and
# CI time"). bench/gpu/run.sh compiles every scene with nvcc itself.
get_property(sweepgen_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
foreach(scene ${SWEEPGEN_BUNDLED_SCENES})
  get_filename_component(stem ${scene} NAME_WE)
  set(sweepgen_cuda)
  if("CUDA" IN_LIST sweepgen_languages AND (SWEEPGEN_CUDA_SCENES STREQUAL "all" OR stem IN_LIST SWEEPGEN_CUDA_SCENES))
    set(sweepgen_cuda CUDA)
  endif()
  file(STRINGS ${scene} solver_line REGEX "^solver:")
  string(REGEX REPLACE "^solver:[ ]*([A-Za-z0-9_:]+).*" "\\1" SWEEPGEN_SCENE_${stem}_NAMESPACE "${solver_line}")
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_FLOAT ${scene} "^scalars:.*float")
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_DERIVATIVES ${scene} "^derivatives:[ ]*(true|\\[)")
  if(SWEEPGEN_BUNDLED_FROM_GENERATED)
    # The committed files are named after the scene's solver namespace.
    string(REPLACE "::" "_" committed_stem "${SWEEPGEN_SCENE_${stem}_NAMESPACE}")
    sweepgen_committed_solver(${stem}_solver GENERATED ${PROJECT_SOURCE_DIR}/generated/${committed_stem}
                              ARCH "${SWEEPGEN_SOLVER_ARCH}" ${sweepgen_cuda})
  else()
    sweepgen_add_solver(${stem}_solver SCENE ${scene} ARCH "${SWEEPGEN_SOLVER_ARCH}" ${sweepgen_cuda})
  endif()
  target_compile_options(${stem}_solver PRIVATE -Wall -Wextra -Wpedantic -Werror -fno-exceptions -fno-rtti)
endforeach()
