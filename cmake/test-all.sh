#!/usr/bin/env bash
# Sets up, builds and runs every test: the README's second command, and what .ci/run runs.
#   1. cmake/install-dependencies.sh consumers (Debian packages, with the derivatives' consumers
#      Ipopt and PyTorch; nothing when all are present)
#   2. release-ci workflow: build/, the whole suite, the statistical tests on a tenth of their random
#      states (`cmake --workflow --preset release` runs the full counts)
#   3. sanitize-ci workflow: build-sanitize/, clang with AddressSanitizer + UndefinedBehaviorSanitizer:
#      the instrumented generator on every bundled scene, the solver and test (300 states) of seven
#      bundled scenes that cover each kind of generated code, the real-time and fuzz-regression tests, the suite's files that drive the
#      generator and the readers end to end, and each fuzzer for 5 s from the committed corpora.
#      The whole suite under the sanitizers: `cmake --workflow --preset sanitize` (README).
# Stops at the first failing stage; prints each stage's wall time at the end either way.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

stages=("setup:bash cmake/install-dependencies.sh consumers"
        "release:cmake --workflow --preset release-ci"
        "sanitize:cmake --workflow --preset sanitize-ci")
times=()
status=0
start_all=$(date +%s)
for stage in "${stages[@]}"; do
  name=${stage%%:*}
  command=${stage#*:}
  start=$(date +%s)
  echo "== test-all: $name: $command"
  $command || status=$?
  times+=("$name $(( $(date +%s) - start )) s")
  [ $status -eq 0 ] || { echo "== test-all: stage $name failed (exit $status)"; break; }
done
echo "== test-all: wall time per stage:"
for t in "${times[@]}"; do echo "   $t"; done
echo "   total $(( $(date +%s) - start_all )) s"
exit $status
