# The bundled scenes (robots/*/*.yaml), each generated at build time into one library
# <stem>_solver that tests/ and bench/ share, compiled warning-free under -Wall -Wextra
# -Wpedantic -Werror, and without exceptions or RTTI (-fno-exceptions -fno-rtti: what a
# real-time controller may build them with; tests/realtime/noexcept_solve.cpp runs two of them). Sets
# SWEEPGEN_SCENE_FILES (every bundled scene's file), SWEEPGEN_BUNDLED_SCENES and
# SWEEPGEN_BATCH_LANE_SOURCES (below) and, per scene stem,
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
file(GLOB SWEEPGEN_SCENE_FILES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/robots/*/*.yaml)
# Three lists name bundled scenes by stem, or `all` for every one: SWEEPGEN_BUNDLED_SCENE_STEMS,
# SWEEPGEN_BATCH_ISA_SCENES (below) and SWEEPGEN_CUDA_SCENES (top-level CMakeLists.txt).
# Sets `out` to whether the list in the variable `list_name` holds `stem`.
function(sweepgen_scene_listed out list_name stem)
  if("${${list_name}}" STREQUAL "all" OR stem IN_LIST ${list_name})
    set(${out} ON PARENT_SCOPE)
  else()
    set(${out} OFF PARENT_SCOPE)
  endif()
endfunction()
# The scenes this build makes a solver and a test of: every one by default. The sanitize-ci preset
# lists a few that cover each kind of generated code (CMakePresets.json): its instrumented solvers
# at -O0 took ~100 job-seconds for all 28, and the release stage and `cmake --workflow --preset
# sanitize` build and test every one.
set(SWEEPGEN_BUNDLED_SCENE_STEMS all CACHE STRING
  "Bundled scenes (robots/*/<stem>.yaml) whose solver and tests the build makes, or all")
# The bundled scenes whose solvers carry batch lanes: the ISA objects of SWEEPGEN_BATCH_ISAS
# (top-level CMakeLists.txt), or the source's own lanes where that is empty. Six scenes by default,
# `all` for every one; the others' batch entry points solve state by state through their flat calls
# (SWEEPGEN_BATCH_STATE_BY_STATE, templates/lanes.mustache). The lanes are each scene's generated
# functions compiled once more, over a vector type: 165 of a clean clone's 1 187 release-build
# job-seconds for all 28 scenes' x86-64-v3 objects, and as much again in the baseline's two-double
# lanes where a scene has none (bench/README.md, "Build and CI time"). The six call every math
# and lane helper of the runtime that any bundled scene calls (GeneratedSources.
# TheLaneScenesCallEveryHelperAnySceneCalls), so every operation in lanes is still compiled and
# held to the flat calls on every build; tests/test_batch.cpp builds a scene's v3 and v4 objects.
set(SWEEPGEN_BATCH_ISA_SCENES
  "planar_nc2;four_bar_loop;quadruped_lean_nc0;parallel_gripper_pinch;panda_nc6;panda_lean_nc6_fixed_derivatives"
  CACHE STRING "Bundled scenes (stems) whose solvers carry batch lanes (the SWEEPGEN_BATCH_ISAS objects), or all")
# SWEEPGEN_BUNDLED_SCENES: the files of the scenes the build makes. SWEEPGEN_BATCH_LANE_SOURCES: the
# committed sources (generated/, named after the solver namespace) of the scenes with lanes, for
# the test that checks what they cover.
set(SWEEPGEN_BUNDLED_SCENES)
set(SWEEPGEN_BATCH_LANE_SOURCES)
set(sweepgen_scene_stems)
foreach(scene ${SWEEPGEN_SCENE_FILES})
  get_filename_component(stem ${scene} NAME_WE)
  list(APPEND sweepgen_scene_stems ${stem})
  file(STRINGS ${scene} solver_line REGEX "^solver:")
  string(REGEX REPLACE "^solver:[ ]*([A-Za-z0-9_:]+).*" "\\1" SWEEPGEN_SCENE_${stem}_NAMESPACE "${solver_line}")
  sweepgen_scene_listed(built SWEEPGEN_BUNDLED_SCENE_STEMS ${stem})
  if(built)
    list(APPEND SWEEPGEN_BUNDLED_SCENES ${scene})
  endif()
  sweepgen_scene_listed(lanes SWEEPGEN_BATCH_ISA_SCENES ${stem})
  if(lanes)
    string(REPLACE "::" "_" committed_stem "${SWEEPGEN_SCENE_${stem}_NAMESPACE}")
    list(APPEND SWEEPGEN_BATCH_LANE_SOURCES ${committed_stem}.cpp)
  endif()
endforeach()
foreach(list_name SWEEPGEN_BUNDLED_SCENE_STEMS SWEEPGEN_BATCH_ISA_SCENES SWEEPGEN_CUDA_SCENES)
  foreach(stem ${${list_name}})
    if(NOT stem STREQUAL "all" AND NOT stem IN_LIST sweepgen_scene_stems)
      message(FATAL_ERROR "${list_name}: ${stem} is not a bundled scene (robots/*/${stem}.yaml)")
    endif()
  endforeach()
endforeach()
# Stops the configure where `what` needs a bundled scene's solver that SWEEPGEN_BUNDLED_SCENE_STEMS
# leaves out (the stems after `what`).
function(sweepgen_require_bundled_scenes what)
  foreach(stem ${ARGN})
    if(NOT TARGET ${stem}_solver)
      message(FATAL_ERROR "${what} needs the bundled scene ${stem}, which SWEEPGEN_BUNDLED_SCENE_STEMS "
                          "(${SWEEPGEN_BUNDLED_SCENE_STEMS}) leaves out")
    endif()
  endforeach()
endfunction()
# The solver library <stem>_solver of the bundled scene `scene`, with batch lanes where
# SWEEPGEN_BATCH_ISA_SCENES lists it (a function: its SWEEPGEN_BATCH_ISAS is its own).
function(sweepgen_bundled_solver stem scene cuda)
  sweepgen_scene_listed(lanes SWEEPGEN_BATCH_ISA_SCENES ${stem})
  if(NOT lanes)
    set(SWEEPGEN_BATCH_ISAS "")
  endif()
  if(SWEEPGEN_BUNDLED_FROM_GENERATED)
    # The committed files are named after the scene's solver namespace.
    string(REPLACE "::" "_" committed_stem "${SWEEPGEN_SCENE_${stem}_NAMESPACE}")
    sweepgen_committed_solver(${stem}_solver GENERATED ${PROJECT_SOURCE_DIR}/generated/${committed_stem}
                              ARCH "${SWEEPGEN_SOLVER_ARCH}" ${cuda})
  else()
    sweepgen_add_solver(${stem}_solver SCENE ${scene} ARCH "${SWEEPGEN_SOLVER_ARCH}" ${cuda})
  endif()
  target_compile_options(${stem}_solver PRIVATE -Wall -Wextra -Wpedantic -Werror -fno-exceptions -fno-rtti)
  if(NOT lanes)
    target_compile_definitions(${stem}_solver PRIVATE SWEEPGEN_BATCH_STATE_BY_STATE)
  endif()
endfunction()
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
  sweepgen_scene_listed(cuda_listed SWEEPGEN_CUDA_SCENES ${stem})
  if("CUDA" IN_LIST sweepgen_languages AND cuda_listed)
    set(sweepgen_cuda CUDA)
  endif()
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_FLOAT ${scene} "^scalars:.*float")
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_DERIVATIVES ${scene} "^derivatives:[ ]*(true|\\[)")
  sweepgen_bundled_solver(${stem} ${scene} "${sweepgen_cuda}")
endforeach()
