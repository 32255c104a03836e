#!/usr/bin/env bash
# bench/code_stats.sh and bench/instructions_by_quantity.sh on the smallest bundled scene: they run
# from a clean clone and print figures that add up (bench/README.md); bench/compile_time.sh and
# bench/batch_scene.sh with the generator built (the second argument).
set -euo pipefail
root=$1
sweepgen=${2:-$root/build/generator/sweepgen}
scene=planar_nc2
fail() { echo "bench scripts test: $*" >&2; exit 1; }

# code_stats: the operation count is the header's, and the object has instructions and spills.
line=$(RUNS=1 bash "$root/bench/code_stats.sh" "$scene" | awk -v s="$scene" '$1 == s')
echo "$line"
read -r _ ops seconds _ _ text instructions spills reloads <<<"$line"
header_ops=$(grep -m1 -F '//   f64: outward + decompose + solve_' "$root/generated/$scene.hpp" | sed -n 's/.*(total \([0-9]*\)).*/\1/p')
[ "$ops" = "$header_ops" ] || fail "code_stats ops $ops, header $header_ops"
for value in "$text" "$instructions" "$spills" "$reloads"; do
  [ "$value" -gt 0 ] || fail "code_stats: a count is not positive: $line"
done
awk -v t="$seconds" 'BEGIN { exit !(t > 0) }' || fail "code_stats: compile time $seconds"

# instructions_by_quantity: the rows printed add up to the total, within what rows under one
# instruction per call leave out (at most one per quantity: < 1 % of ~1 400 here).
out=$(CALLS=200 bash "$root/bench/instructions_by_quantity.sh" "$scene")
echo "$out"
grep -q ' outward / articulated_inertia$' <<<"$out" || fail "instructions_by_quantity: no articulated inertia row"
# And the total is the whole program's count but for the driver's loop (index, call, checksum:
# measured 24 instructions per call).
awk '/total per call/ { total = $1; next } /whole program/ { program = $1; next } { sum += $1 }
     END { if (total < 500 || sum > total || sum < 0.99 * total || program < total || program > total + 40) {
             print "sum", sum, "total", total, "program", program; exit 1 } }' <<<"$out" ||
  fail "instructions_by_quantity: rows, total and the whole program's count disagree"
# compile_time: a line per object (the baseline alone here), with a positive CPU time and a largest
# function.
out=$(SWEEPGEN=$sweepgen ISAS= bash "$root/bench/compile_time.sh" "$root/robots/planar/planar_nc2.yaml")
echo "$out"
awk '$1 == "baseline" { found = 1; if (!($2 > 0) || NF < 5) exit 1 } END { exit !found }' <<<"$out" ||
  fail "compile_time: no baseline object line with a CPU time and a function"

# batch_scene: the flat loop and the batch entry point of a default build's objects on the states
# asked for, each with a positive time per state.
out=$(SWEEPGEN=$sweepgen bash "$root/bench/batch_scene.sh" "$root/robots/planar/planar_nc2.yaml" 1001)
echo "$out"
tail -1 <<<"$out" | grep -qE '^[a-z_]+: 1001 states, [0-9]+ a vector, flat [0-9.]+ ns, batch [0-9.]+ ns a state, flat / batch [0-9.]+$' ||
  fail "batch_scene: no line with the states asked for, the flat and the batch time"
tail -1 <<<"$out" | awk '{ if (!($8 > 0) || !($11 > 0)) exit 1 }' || fail "batch_scene: a time is not positive"

echo "bench scripts test: ok"
