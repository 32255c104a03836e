#!/usr/bin/env bash
# Fuzzes sweepgen's input readers and keeps what a run learned (fuzz/README.md):
#   fuzz/run.sh [--minutes N | SECONDS] [--no-merge] [TARGET...]
#   --minutes N  how long each fuzzer runs, in minutes (or SECONDS as a bare number; default 60 s)
#   --no-merge   leave fuzz/corpus/ and fuzz/regressions/ as they are
#   TARGET       urdf, scene, solve_line (default: all three, SWEEPGEN_FUZZ_JOBS at a time, default 2)
# 1. Configures build-fuzz/ through the `fuzz` preset with that time, builds only the fuzzers and
#    runs them through their ctest tests (so the flags are the ones in fuzz/CMakeLists.txt); prints
#    each target's executions, coverage (cov: edges, ft: features) and findings.
# 2. Merges the inputs that reached new coverage into the committed seed corpus fuzz/corpus/TARGET/:
#    libFuzzer's -merge=1 of the run's working corpus over the run's starting set (seeds/TARGET:
#    robots/, fuzz/corpus/, fuzz/regressions/), so only inputs that add coverage to what every run
#    starts from are kept (a minimised set, named by content hash).
# 3. Copies every finding (crash-*, leak-*, timeout-*, oom-*) to fuzz/regressions/TARGET/ as
#    finding-*: test_fuzz_regressions then fails on it until the reader is fixed and the file
#    renamed for what it must do (reject_... or accepted).
# Exits non-zero when a fuzzer found something.
set -euo pipefail

seconds=60
merge=1
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    --minutes) seconds=$(( $2 * 60 )); shift 2 ;;
    --no-merge) merge=0; shift ;;
    [0-9]*) seconds=$1; shift ;;
    urdf|scene|solve_line) targets+=("$1"); shift ;;
    *) echo "fuzz/run.sh: unknown argument '$1' (see the top of this script)" >&2; exit 2 ;;
  esac
done
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

[ $merge -eq 1 ] || exit $status
for t in "${targets[@]}"; do
  seeds=$build_dir/fuzz/seeds/$t
  merged=$(mktemp -d)
  cp "$seeds"/* "$merged"/
  read -r -a flags < "$build_dir/fuzz/$t.flags"
  "$build_dir/fuzz/fuzz_$t" -merge=1 "${flags[@]}" "$merged" "$build_dir/fuzz/corpus/$t" >"$build_dir/fuzz/merge_$t.log" 2>&1
  added=0
  for f in "$merged"/*; do
    name=$(basename "$f")
    [ -e "$seeds/$name" ] && continue
    cp "$f" "$source_dir/fuzz/corpus/$t/$name"
    added=$((added + 1))
  done
  rm -r "$merged"
  found=0
  for f in "$build_dir/fuzz/findings/$t"/*; do
    [ -e "$f" ] || continue
    cp "$f" "$source_dir/fuzz/regressions/$t/finding-$(basename "$f")"
    found=$((found + 1))
  done
  echo "== $t: $added new-coverage inputs merged into fuzz/corpus/$t/, $found findings copied to fuzz/regressions/$t/"
done
exit $status
