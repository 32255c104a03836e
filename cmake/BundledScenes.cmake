# The bundled scenes (robots/*/*.yaml), each generated at build time into one library
# <stem>_solver that tests/ and bench/ share, compiled warning-free under -Wall -Wextra
# -Wpedantic -Werror, and without exceptions or RTTI (-fno-exceptions -fno-rtti: what a
# real-time controller may build them with; tests/realtime/noexcept_solve.cpp runs two of them). Sets SWEEPGEN_BUNDLED_SCENES (the files) and, per scene stem,
# SWEEPGEN_SCENE_<stem>_NAMESPACE, SWEEPGEN_SCENE_<stem>_HAS_FLOAT and
# SWEEPGEN_SCENE_<stem>_HAS_DERIVATIVES, read from the one-line `solver:`, `scalars:` and
# `derivatives:` entries our scenes use.
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
foreach(scene ${SWEEPGEN_BUNDLED_SCENES})
  get_filename_component(stem ${scene} NAME_WE)
  file(STRINGS ${scene} solver_line REGEX "^solver:")
  string(REGEX REPLACE "^solver:[ ]*([A-Za-z0-9_:]+).*" "\\1" SWEEPGEN_SCENE_${stem}_NAMESPACE "${solver_line}")
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_FLOAT ${scene} "^scalars:.*float")
  sweepgen_scene_has_line(SWEEPGEN_SCENE_${stem}_HAS_DERIVATIVES ${scene} "^derivatives:[ ]*true")
  sweepgen_add_solver(${stem}_solver SCENE ${scene} ARCH "${SWEEPGEN_SOLVER_ARCH}")
  target_compile_options(${stem}_solver PRIVATE -Wall -Wextra -Wpedantic -Werror -fno-exceptions -fno-rtti)
endforeach()
