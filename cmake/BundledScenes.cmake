# The bundled scenes (robots/*/*.yaml), each generated at build time into one library
# <stem>_solver that tests/ and bench/ share, compiled warning-free under -Wall -Wextra
# -Wpedantic -Werror, and without exceptions or RTTI (-fno-exceptions -fno-rtti: what a
# real-time controller may build them with; tests/realtime/noexcept_solve.cpp runs two of them). Sets SWEEPGEN_BUNDLED_SCENES (the files) and, per scene stem,
# SWEEPGEN_SCENE_<stem>_NAMESPACE and SWEEPGEN_SCENE_<stem>_HAS_FLOAT, read from the one-line
# `solver:` and `scalars:` entries our scenes use.
set(SWEEPGEN_SOLVER_ARCH "" CACHE STRING
  "-march= for the bundled generated solvers (sweepgen_add_solver ARCH), e.g. x86-64-v3 or native; empty: the baseline")
file(GLOB SWEEPGEN_BUNDLED_SCENES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/robots/*/*.yaml)
foreach(scene ${SWEEPGEN_BUNDLED_SCENES})
  get_filename_component(stem ${scene} NAME_WE)
  file(STRINGS ${scene} solver_line REGEX "^solver:")
  string(REGEX REPLACE "^solver:[ ]*([A-Za-z0-9_:]+).*" "\\1" SWEEPGEN_SCENE_${stem}_NAMESPACE "${solver_line}")
  file(STRINGS ${scene} float_line REGEX "^scalars:.*float")
  if(float_line)
    set(SWEEPGEN_SCENE_${stem}_HAS_FLOAT 1)
  else()
    set(SWEEPGEN_SCENE_${stem}_HAS_FLOAT 0)
  endif()
  sweepgen_add_solver(${stem}_solver SCENE ${scene} ARCH "${SWEEPGEN_SOLVER_ARCH}")
  target_compile_options(${stem}_solver PRIVATE -Wall -Wextra -Wpedantic -Werror -fno-exceptions -fno-rtti)
endforeach()
