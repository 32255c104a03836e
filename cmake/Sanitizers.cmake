# SWEEPGEN_SANITIZE: AddressSanitizer + UndefinedBehaviorSanitizer for everything this project
# builds (generator, tests, benchmarks and the bundled scenes' generated solvers). Any finding
# aborts the process (-fno-sanitize-recover), so a test with a finding fails. Used by the
# `sanitize` preset (CMakePresets.json), which .ci/run runs after the release build.
option(SWEEPGEN_SANITIZE "Build with AddressSanitizer and UndefinedBehaviorSanitizer" OFF)
if(SWEEPGEN_SANITIZE)
  set(SWEEPGEN_SANITIZE_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer)
  add_compile_options(${SWEEPGEN_SANITIZE_FLAGS})
  add_link_options(${SWEEPGEN_SANITIZE_FLAGS})
endif()
