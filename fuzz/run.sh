#!/usr/bin/env bash
# Fuzzes sweepgen's input readers: fuzz/run.sh [SECONDS] [TARGET...]
#   SECONDS  how long each fuzzer runs (default 60)
#   TARGET   urdf, scene, solve_line (default: all three, one after the other)
# Configures build-fuzz/ through the `fuzz` preset (CMakePresets.json) with the given time,
# builds only the fuzzers, runs them through their ctest tests (so the flags are the ones in
# fuzz/CMakeLists.txt) and prints libFuzzer's final figures. Findings: build-fuzz/fuzz/findings/TARGET/.
set -euo pipefail

seconds=${1:-60}
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(urdf scene solve_line)
source_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$source_dir/build-fuzz
jobs=${SWEEPGEN_FUZZ_JOBS:-2}

(cd "$source_dir" && cmake --preset fuzz -DSWEEPGEN_FUZZ_SECONDS="$seconds" >/dev/null)
fuzzers=()
for t in "${targets[@]}"; do fuzzers+=("fuzz_$t"); done
cmake --build "$build_dir" --target "${fuzzers[@]}" -j "$jobs"

log=$build_dir/fuzz/last_run.log
status=0
ctest --test-dir "$build_dir" -j "$jobs" -L fuzz -R "^($(IFS='|'; echo "${fuzzers[*]}"))\$" -V >"$log" 2>&1 || status=$?
# libFuzzer's last coverage line and totals per target (ctest -V prefixes lines with "N: ").
for f in "${fuzzers[@]}"; do
  n=$(grep -a -m1 -E "^ *Start +[0-9]+: $f\$" "$log" | sed -E 's/^ *Start +([0-9]+):.*/\1/' || true)
  echo "== $f"
  [ -n "$n" ] || { echo "(did not run)"; continue; }
  { grep -a -E "^$n: #[0-9]+[[:space:]]+(INITED|NEW|REDUCE|pulse|DONE)" "$log" || true; } | tail -1 | sed "s/^$n: //"
  grep -a -E "^$n: (stat::(number_of_executed_units|average_exec_per_sec)|SUMMARY|.*Test unit written)" "$log" |
    sed "s/^$n: //" || true
done
grep -a -E "tests passed|tests failed" "$log" || true
echo "full log: $log; findings: $build_dir/fuzz/findings/<target>/"
exit $status
