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
# The suite's references (the oracles, the reference solver in long double and over the dual
# scalar), the report and its measurement code: instrumented too unless this is OFF, as the
# sanitize-ci preset sets it (generator/CMakeLists.txt). Under the sanitizers they took about 230
# of that stage's 620 job-seconds, for code that checks the generator rather than being it; OFF,
# sanitize-ci links the release build's instead of compiling them again (cmake/References.cmake).
option(SWEEPGEN_SANITIZE_ORACLES "With SWEEPGEN_SANITIZE: instrument the oracles, the report and its measurement code too" ON)
