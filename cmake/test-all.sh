#!/usr/bin/env bash
# Sets up, builds and runs every test: the README's second command, and what .ci/run runs.
#   1. cmake/install-dependencies.sh (Debian packages; nothing when all are present)
#   2. release workflow: build/, the whole suite
#   3. sanitize workflow: build-sanitize/, clang with AddressSanitizer + UndefinedBehaviorSanitizer,
#      the whole suite and each fuzzer for SWEEPGEN_FUZZ_SECONDS (15) from the committed corpora
# Stops at the first failing stage; prints each stage's wall time at the end either way.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

stages=("setup:bash cmake/install-dependencies.sh"
        "release:cmake --workflow --preset release"
        "sanitize:cmake --workflow --preset sanitize")
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
