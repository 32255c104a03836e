#!/usr/bin/env bash
# The trajectory-optimisation example (examples/trajectory_optimisation) with the exact constraint
# Jacobian (the generated derivatives) against Ipopt's finite-difference one (jacobian_approximation
# finite-difference-values), the same problem otherwise: Ipopt's iterations, the wall time of its
# solve, and the CPU time Ipopt counts in the NLP's function evaluations (the rest is its own
# linear algebra, the same for both) (bench/README.md, "Trajectory optimisation"). RUNS pairs of
# runs, each pair one of each back to back (this machine's speed drifts between runs); the
# medians, and the median of the pairs' ratios.
#
#   bash bench/trajectory_optimisation.sh [PROGRAM]   (default build/tests/trajectory_optimisation/trajectory_optimisation)
#   RUNS=9 INTERVALS=40 bash bench/trajectory_optimisation.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
program=${1:-$root/build/tests/trajectory_optimisation/trajectory_optimisation}
runs=${RUNS:-5}
intervals=${INTERVALS:-30}
[ -x "$program" ] || { echo "trajectory_optimisation.sh: no $program (cmake --build build --target trajectory_optimisation)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# "<iterations> <wall s> <function-evaluation CPU s> <effort>" of one run.
run() {
  "$program" "$work" --intervals "$intervals" "$@" > "$work/out" 2>&1 || true
  local evaluations summary
  evaluations=$(sed -nE 's/^Total CPU secs in NLP function evaluations *= *([0-9.]+)$/\1/p' "$work/out")
  summary=$(sed -nE 's/.*: Solve_Succeeded \(0\) after ([0-9]+) iterations, ([0-9.]+) s \(CPU [0-9.]+ s\); effort ([0-9.e+-]+)$/\1 \2 \3/p' "$work/out")
  [ -n "$summary" ] && [ -n "$evaluations" ] || { echo "trajectory_optimisation.sh: a run with '$*' did not solve" >&2; exit 1; }
  read -r iterations seconds effort <<< "$summary"
  echo "$iterations $seconds $evaluations $effort"
}
for _ in $(seq "$runs"); do
  read -r a_it a_s a_ev a_eff < <(run)
  read -r b_it b_s b_ev b_eff < <(run --finite-difference)
  echo "$a_it $a_s $a_ev $a_eff $b_it $b_s $b_ev $b_eff"
done > "$work/pairs"
median() { sort -g | sed -n "$(( (runs + 1) / 2 ))p"; }
column() { awk -v c="$1" '{ print $c }' "$work/pairs" | median; }
ratio() { awk -v a="$1" -v b="$2" '{ print $a / $b }' "$work/pairs" | median; }
echo "Jacobian             iterations  wall time [s]  function evaluations CPU [s]  effort   ($intervals intervals, median of $runs pairs)"
printf "exact (generated)    %10d  %13.3f  %28.3f  %s\n" "$(column 1)" "$(column 2)" "$(column 3)" "$(column 4)"
printf "finite differences   %10d  %13.3f  %28.3f  %s\n" "$(column 5)" "$(column 6)" "$(column 7)" "$(column 8)"
printf "ratio (FD / exact)   %10s  %12.1fx  %27.1fx\n" "" "$(ratio 6 2)" "$(ratio 7 3)"
printf "wall-time ratios of the pairs: %s\n" "$(awk '{ printf "%.1f ", $6 / $2 }' "$work/pairs")"
