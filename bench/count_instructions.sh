#!/usr/bin/env bash
# Instructions per solver call, counted with callgrind (bench/README.md).
#
#   bash bench/count_instructions.sh [BUILD_DIR]
#
# BUILD_DIR defaults to build-bench at the repository root; it is configured (Release) if it
# does not exist yet, and the target bench_calls is (re)built in it. Runs
#   valgrind --tool=callgrind bench_calls <id> <policy> N <mode>
# for N = CALLS (default 1000) per case and N = 0 once per id and mode, and reports
# (Ir(CALLS) - Ir(0)) / CALLS ("summary:" line of the callgrind output): the set-up (dynamic
# linking, scene and URDF parsing, input preparation) is the same in both runs and cancels.
# Cases: every generated scene's f64 variant x policy, full flat solve (outward + decompose +
# solve), and outward + decompose; every f32 variant, full solve with the original policy; the
# Panda scenes' re-solves (solve_<policy> only, new setpoints); KDL's Vereshchagin solver on
# the Panda at Nc = 0, 3, 6 and the iiwa 14 and UR5 at Nc = 6 (bench/support/kdl_bench.hpp);
# ReferenceSolver<double> on every scene (original); the report's dense KKT solve on the trees,
# floating bases and panda_nc6; the derivative functions of the scenes with derivatives: true
# (derivatives_<policy>_flat: the solve and its Jacobians); the batch entry points of every f64
# variant (solve_<policy>_batch, derivatives_<policy>_batch: kStates = 64 states a call, so their
# N is CALLS rounded up to a multiple of 64, and a "call" there is one state).
# Prints a table with the floating-point operation counts the generator wrote into each header
# and the ratio instructions / operation, then ratios against KDL, re-solve / full, reference /
# generated; writes everything to BUILD_DIR/bench/instructions.csv.
# Environment: CALLS (default 1000), JOBS (parallel valgrind runs, default nproc), ONLY (a bash
# regular expression: only the ids it matches, e.g. 'lean'), ARCH (the
# generated solvers' -march, e.g. x86-64-v3; sets SWEEPGEN_SOLVER_ARCH in BUILD_DIR, whose default
# becomes build-bench-ARCH; valgrind 3.19 decodes AVX2 but not AVX-512, so not `native` here).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
arch=${ARCH:-}
build=${1:-$root/build-bench${arch:+-$arch}}
calls=${CALLS:-1000}
jobs=${JOBS:-$(nproc)}

command -v valgrind >/dev/null || { echo "count_instructions.sh: valgrind not found (Debian: apt-get install valgrind)" >&2; exit 1; }
if [ ! -f "$build/CMakeCache.txt" ] || [ -n "$arch" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DSWEEPGEN_SOLVER_ARCH="$arch" >/dev/null
fi
cmake --build "$build" -j"$jobs" --target bench_calls >/dev/null
driver=$build/bench/bench_calls
csv=$build/bench/instructions.csv
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# ---- the cases: "<id> <policy> <mode>" --------------------------------------------------------
cases=()
while read -r id policies; do
  case $id in
    kdl/* | dense_kkt/*) cases+=("$id - full") ;;
    reference/*) cases+=("$id original full") ;;
    */f32) cases+=("$id original full") ;;  # float: the original policy only (keeps the run short)
    *)
      for p in $policies; do cases+=("$id $p full" "$id $p batch"); done
      cases+=("$id - decompose")
      if [[ $id == panda_* ]]; then
        for p in $policies; do cases+=("$id $p resolve"); done
      fi
      ;;
  esac
done < <("$driver" --list)
while read -r id policies; do
  for p in $policies; do cases+=("$id $p derivatives"); [[ $id == */f64 ]] && cases+=("$id $p derivatives_batch"); done
done < <("$driver" --list-derivatives)
if [ -n "${ONLY:-}" ]; then
  kept=()
  for c in "${cases[@]}"; do [[ ${c%% *} =~ $ONLY ]] && kept+=("$c"); done
  cases=("${kept[@]}")
fi

# One run per case with N = CALLS, and one N = 0 baseline per id and mode: the set-up does not
# depend on the policy (the policy-name lookup differs by ~60 instructions in total, < 0.1 per call).
runs=()
declare -A baseline_seen
batch_calls=$(( (calls + 63) / 64 * 64 ))
for c in "${cases[@]}"; do
  read -r id policy mode <<<"$c"
  case $mode in *batch) runs+=("$batch_calls $c") ;; *) runs+=("$calls $c") ;; esac
  if [ -z "${baseline_seen[$id $mode]:-}" ]; then
    baseline_seen[$id $mode]=1
    runs+=("0 $c")
  fi
done

run_one() {  # <N> <id> <policy> <mode> -> "<N> <id> <policy> <mode> <Ir>"
  local n=$1 id=$2 policy=$3 mode=$4
  local out=$tmp/${id//\//_}.$policy.$mode.$n
  if ! valgrind --tool=callgrind -q --callgrind-out-file="$out.callgrind" \
      "$driver" "$id" "$policy" "$n" "$mode" >/dev/null 2>"$out.err"; then
    echo "count_instructions.sh: failed: bench_calls $id $policy $n $mode" >&2
    cat "$out.err" >&2
    return 1
  fi
  echo "$n $id $policy $mode $(sed -n 's/^summary: *//p' "$out.callgrind")"
}
export -f run_one
export driver tmp

echo "callgrind: ${#cases[@]} cases, ${#runs[@]} runs (N = $calls, and N = 0 per id and mode), $jobs in parallel ..." >&2
start=$SECONDS
printf '%s\n' "${runs[@]}" | xargs -P "$jobs" -L1 bash -c 'run_one "$@"' _ > "$tmp/runs"
echo "callgrind: done in $((SECONDS - start)) s" >&2
declare -A ir0
while read -r n id policy mode ir; do
  if [ "$n" = 0 ]; then ir0[$id $mode]=$ir; fi
done < "$tmp/runs"
while read -r n id policy mode ir; do
  if [ "$n" != 0 ]; then echo "$id $policy $mode ${ir0[$id $mode]} $ir $n"; fi
done < "$tmp/runs" > "$tmp/results"

# ---- operation counts from the generated headers ---------------------------------------------
# Header lines: "//   f64: outward + decompose + solve_original: add ..., (total 5564)",
#               "//   f64::solve_original: ... (total 588)", "//   f64::outward: ...".
ops() {  # <id> <policy> <mode>
  local id=$1 policy=$2 mode=$3
  case $id in kdl/* | reference/* | dense_kkt/*) return 0 ;; esac
  local stem=${id%/*} tag=${id#*/}
  local header=$build/sweepgen/${stem}_solver/${stem}_solver.hpp
  local total='s/.*(total \([0-9]*\)).*/\1/p'
  case $mode in
    full) grep -F "//   $tag: outward + decompose + solve_$policy:" "$header" | sed -n "$total" ;;
    resolve) grep -F "//   $tag::solve_$policy:" "$header" | sed -n "$total" ;;
    derivatives | derivatives_batch) grep -F "//   $tag::derivatives_$policy:" "$header" | sed -n "$total" ;;
    batch) grep -F "//   $tag: outward + decompose + solve_$policy:" "$header" | sed -n "$total" ;;
    decompose)
      { grep -F "//   $tag::outward:" "$header"; grep -F "//   $tag::decompose:" "$header"; } |
        sed -n "$total" | awk '{s += $1} END {print s}' ;;
  esac
}

sort -k1,1 -k3,3 -k2,2 "$tmp/results" > "$tmp/sorted"
echo "id,policy,mode,calls,ir_n0,ir_n,instructions_per_call,fp_ops,instructions_per_op" > "$csv"
declare -A per_call
while read -r id policy mode ir0 irn n; do
  pc=$(awk -v a="$ir0" -v b="$irn" -v n="$n" 'BEGIN {printf "%.1f", (b - a) / n}')
  per_call["$id $policy $mode"]=$pc
  f=$(ops "$id" "$policy" "$mode")
  ratio=""
  if [ -n "$f" ] && [ "$f" != 0 ]; then ratio=$(awk -v a="$pc" -v b="$f" 'BEGIN {printf "%.2f", a / b}'); fi
  echo "$id,$policy,$mode,$n,$ir0,$irn,$pc,$f,$ratio" >> "$csv"
done < "$tmp/sorted"

# ---- tables ----------------------------------------------------------------------------------
echo
echo "Instructions per call (callgrind Ir, (Ir(N) - Ir(N=0)) / N, N = $calls; batch modes: per state, N = $batch_calls); fp_ops: the generator's count of"
echo "floating-point operations (add/sub, mul, div, neg, sin/cos, compare) in the generated header."
echo
printf '%-26s %-20s %-10s %12s %8s %9s\n' id policy mode instr/call fp_ops instr/op
printf '%-26s %-20s %-10s %12s %8s %9s\n' -------------------------- -------------------- ---------- ------------ -------- ---------
tail -n +2 "$csv" | while IFS=, read -r id policy mode _ _ _ pc f ratio; do
  printf '%-26s %-20s %-10s %12s %8s %9s\n' "$id" "$policy" "$mode" "$pc" "${f:--}" "${ratio:--}"
done

ratio() {  # <numerator key> <denominator key>: prints num/den or "-"
  local a=${per_call[$1]:-} b=${per_call[$2]:-}
  if [ -n "$a" ] && [ -n "$b" ]; then awk -v a="$a" -v b="$b" 'BEGIN {printf "%.2f", a / b}'; else echo -; fi
}

echo
echo "KDL ChainHdSolver_Vereshchagin (root -> last moving link) / generated f64 full solve, original policy"
echo "(how many times the instructions KDL needs):"
for pair in "panda_nc0 panda/nc0" "panda_nc3 panda/nc3" "panda_nc6 panda/nc6" "panda_bias_only panda/nc6" \
  "panda_composed panda/nc6" "iiwa14_nc6 iiwa14/nc6" "ur5_nc6 ur5/nc6"; do
  set -- $pair
  printf '  %-18s vs KDL %-11s: %8s / %8s = %s\n' "$1" "$2" "${per_call[kdl/$2 - full]:--}" \
    "${per_call[$1/f64 original full]:--}" "$(ratio "kdl/$2 - full" "$1/f64 original full")"
done

echo
echo "Re-solve (solve_<policy> only) / full solve, f64:"
for id in panda_nc0 panda_nc3 panda_nc6 panda_bias_only panda_composed; do
  while read -r vid policies; do
    [ "$vid" = "$id/f64" ] || continue
    for p in $policies; do
      printf '  %-18s %-20s %s\n' "$id" "$p" "$(ratio "$id/f64 $p resolve" "$id/f64 $p full")"
    done
  done < <("$driver" --list)
done

echo
echo "outward + decompose / full solve (original), f64:"
while read -r vid _; do
  [[ $vid == */f64 ]] || continue
  printf '  %-18s %s\n' "${vid%/f64}" "$(ratio "$vid - decompose" "$vid original full")"
done < <("$driver" --list)

against_generated() {  # <id prefix> <policy>: "<prefix>/<scene> <policy> full" / "<scene>/f64 original full", per scene
  local prefix=$1 policy=$2 vid stem
  while read -r vid _; do
    [[ $vid == $prefix/* ]] || continue
    stem=${vid#"$prefix"/}
    printf '  %-18s %10s / %8s = %s\n' "$stem" "${per_call[$vid $policy full]:--}" "${per_call[$stem/f64 original full]:--}" \
      "$(ratio "$vid $policy full" "$stem/f64 original full")"
  done < <("$driver" --list)
}

echo
echo "ReferenceSolver<double> / generated f64, full solve (original):"
against_generated reference original

echo
echo "Dense KKT (the report's row: M(q), Jacobians, one LDL^T) / generated f64, full solve (original):"
against_generated dense_kkt -

echo
echo "Derivatives (derivatives_<policy>_flat: the solve and its Jacobians) / full solve, f64:"
while read -r vid policies; do
  for p in $policies; do
    printf '  %-26s %-20s %10s / %8s = %s\n' "$vid" "$p" "${per_call[$vid $p derivatives]:--}" "${per_call[$vid $p full]:--}" \
      "$(ratio "$vid $p derivatives" "$vid $p full")"
  done
done < <("$driver" --list-derivatives)

echo
echo "Batch (solve_<policy>_batch, per state) / flat call (solve_<policy>_flat), f64, original policy:"
while read -r vid _; do
  [[ $vid == */f64 ]] || continue
  printf '  %-26s %10s / %8s = %s\n' "$vid" "${per_call[$vid original batch]:--}" "${per_call[$vid original full]:--}" \
    "$(ratio "$vid original batch" "$vid original full")"
done < <("$driver" --list)
while read -r vid policies; do
  [[ $vid == */f64 ]] || continue
  for p in $policies; do
    printf '  %-26s %10s / %8s = %s (derivatives)\n' "$vid" "${per_call[$vid $p derivatives_batch]:--}" \
      "${per_call[$vid $p derivatives]:--}" "$(ratio "$vid $p derivatives_batch" "$vid $p derivatives")"
  done
done < <("$driver" --list-derivatives)

echo
echo "panda_bias_only / panda_nc6 (f64 full, original): $(ratio "panda_bias_only/f64 original full" "panda_nc6/f64 original full")"
echo
echo "CSV: $csv"
