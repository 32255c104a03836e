#!/usr/bin/env bash
# Wall time per state of the batch entry point against the flat call (bench/README.md, "Batches of
# states"): bench_calls runs N states through solve_original_flat (full) and through
# solve_original_batch (batch), five runs each; the median of the five, less the median of five
# runs with N = 0 (set-up: dynamic linking, scene and URDF parsing, input preparation), over N.
#   bash bench/batch_time.sh [BUILD_DIR] [ID...]
# BUILD_DIR: a build with the target bench_calls (default build-bench-x86-64-v3, as
# `ARCH=x86-64-v3 bash bench/count_instructions.sh` leaves it); ID: bench_calls ids (default the
# Panda's lean scenes, panda_nc6 and quadruped_stance, f64). N (default 524288) a multiple of 64.
# A wall-clock figure: run it on an otherwise idle machine.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${1:-$root/build-bench-x86-64-v3}
shift || true
ids=("$@")
[ ${#ids[@]} -gt 0 ] || ids=(panda_lean_nc6_fixed/f64 panda_lean_nc0/f64 panda_nc6/f64 quadruped_stance/f64)
calls=$build/bench/bench_calls
[ -x "$calls" ] || { echo "batch_time.sh: no $calls (build the target bench_calls)" >&2; exit 1; }
n=${N:-524288}
run() {  # ID N MODE: nanoseconds of wall time
  local start end
  start=$(date +%s%N); "$calls" "$1" original "$2" "$3" > /dev/null; end=$(date +%s%N)
  echo $((end - start))
}
median() { printf '%s\n' "$@" | sort -n | sed -n 3p; }
printf '%-28s %12s %12s %8s\n' id "flat ns" "batch ns" ratio
for id in "${ids[@]}"; do
  declare -A per_state=()
  for mode in full batch; do
    setup=(); times=()
    for _ in 1 2 3 4 5; do setup+=("$(run "$id" 0 "$mode")"); done
    for _ in 1 2 3 4 5; do times+=("$(run "$id" "$n" "$mode")"); done
    per_state[$mode]=$(awk -v t="$(median "${times[@]}")" -v s="$(median "${setup[@]}")" -v n="$n" 'BEGIN { printf "%.1f", (t - s) / n }')
  done
  printf '%-28s %12s %12s %8s\n' "$id" "${per_state[full]}" "${per_state[batch]}" \
    "$(awk -v f="${per_state[full]}" -v b="${per_state[batch]}" 'BEGIN { printf "%.2f", f / b }')"
  unset per_state
done
