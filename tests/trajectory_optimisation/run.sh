#!/usr/bin/env bash
# The trajectory-optimisation example's tests (tests/CMakeLists.txt):
#   run.sh PROGRAM OUT_DIR converges           it solves (Solve_Succeeded) with Ipopt's derivative
#                                              checker (derivative_test first-order) flagging no
#                                              entry, its --check asserts pass, and it writes the
#                                              table and the figure
#   run.sh PROGRAM OUT_DIR unreachable_plane   a plane above the hand's reach: exit 2 and a message
#   run.sh PROGRAM OUT_DIR end_off_plane       an end pose off the plane: Ipopt's status, exit 1
#   run.sh PROGRAM OUT_DIR bench_script        bench/trajectory_optimisation.sh at 10 intervals, one
#                                              pair: both Jacobians reach the same optimum
set -uo pipefail
program=$1 out=$2/$3 mode=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL ($mode): $*" >&2; echo "--- output:" >&2; cat "$out/log" >&2; exit 1; }

case "$mode" in
  converges)
    "$program" "$out" --derivative-test --check >"$out/log" 2>&1
    rc=$?
    grep -q "^No errors detected by derivative checker" "$out/log" ||
      fail "Ipopt's derivative checker flagged entries: $(grep -m1 'Derivative checker detected' "$out/log")"
    [ $rc -eq 0 ] || fail "exit $rc"
    grep -q "exact Jacobian, .*: Solve_Succeeded" "$out/log" || fail "no Solve_Succeeded"
    [ "$(grep -c '^check: .* ok$' "$out/log")" -eq 5 ] || fail "not every check passed"
    [ -s "$out/trajectory.csv" ] && [ -s "$out/trajectory.png" ] || fail "no trajectory.csv or trajectory.png"
    # A row per node (30 intervals: 31), header included.
    [ "$(wc -l <"$out/trajectory.csv")" -eq 32 ] || fail "trajectory.csv has not 31 rows"
    ;;
  unreachable_plane)
    "$program" "$out" --plane-height 1.5 >"$out/log" 2>&1
    rc=$?
    [ $rc -eq 2 ] || fail "exit $rc, not 2"
    grep -q "the plane z = 1.5 m is out of the hand's reach" "$out/log" || fail "no message naming the plane"
    ;;
  end_off_plane)
    "$program" "$out" --end-lift 0.05 >"$out/log" 2>&1
    rc=$?
    [ $rc -eq 1 ] || fail "exit $rc, not 1"
    grep -q "Ipopt did not solve the problem: .* (the end pose is off the plane" "$out/log" || fail "no status message"
    ;;
  bench_script)
    RUNS=1 INTERVALS=10 bash "$(dirname "${BASH_SOURCE[0]}")/../../bench/trajectory_optimisation.sh" "$program" >"$out/log" 2>&1 ||
      fail "the script failed"
    exact=$(awk '/^exact \(generated\)/ { print $3, $NF }' "$out/log")
    fd=$(awk '/^finite differences/ { print $3, $NF }' "$out/log")
    # The same optimum: Ipopt's tol 1e-8 on both, the objective printed to 6 digits.
    [ -n "$exact" ] && [ "${exact#* }" = "${fd#* }" ] || fail "no rows, or different optima: '$exact' and '$fd'"
    grep -qE '^ratio \(FD / exact\) +[0-9.]+x +[0-9.]+x$' "$out/log" || fail "no ratio row"
    ;;
  *) echo "run.sh: unknown mode $mode" >&2; exit 2 ;;
esac
echo "PASS ($mode)"
