#!/usr/bin/env bash
# The trajectory-optimisation example (examples/trajectory_optimisation) with the exact constraint
# Jacobian (the generated derivatives) against Ipopt's finite-difference one (jacobian_approximation
# finite-difference-values), the same problem otherwise: Ipopt's iterations and the wall time of
# its solve, the median of RUNS runs each (bench/README.md, "Trajectory optimisation").
#
#   bash bench/trajectory_optimisation.sh [PROGRAM]   (default build/tests/trajectory_optimisation/trajectory_optimisation)
#   RUNS=5 INTERVALS=40 bash bench/trajectory_optimisation.sh
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
program=${1:-$root/build/tests/trajectory_optimisation/trajectory_optimisation}
runs=${RUNS:-3}
intervals=${INTERVALS:-30}
[ -x "$program" ] || { echo "trajectory_optimisation.sh: no $program (cmake --build build --target trajectory_optimisation)" >&2; exit 2; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# One line per run: "<iterations> <seconds> <effort>" from the program's summary line.
measure() {
  for _ in $(seq "$runs"); do
    "$program" "$work" --intervals "$intervals" "$@" 2>&1 |
      sed -nE 's/.*: Solve_Succeeded \(0\) after ([0-9]+) iterations, ([0-9.]+) s; effort ([0-9.e+-]+)$/\1 \2 \3/p' > "$work/line"
    [ -s "$work/line" ] || { echo "trajectory_optimisation.sh: a run with '$*' did not solve" >&2; exit 1; }
    cat "$work/line"
  done | sort -k2 -g | sed -n "$(( (runs + 1) / 2 ))p"
}
read -r exact_iterations exact_seconds exact_effort < <(measure)
read -r fd_iterations fd_seconds fd_effort < <(measure --finite-difference)
echo "Jacobian             iterations  wall time [s]  effort   ($intervals intervals, median of $runs)"
printf "exact (generated)    %10d  %13.3f  %s\n" "$exact_iterations" "$exact_seconds" "$exact_effort"
printf "finite differences   %10d  %13.3f  %s\n" "$fd_iterations" "$fd_seconds" "$fd_effort"
awk -v a="$fd_seconds" -v b="$exact_seconds" 'BEGIN { printf "time ratio           %.1fx\n", a / b }'
