#!/usr/bin/env bash
# Where a generated solver's instructions go: callgrind's instruction count per source line of
# the committed generated/<scene>.cpp, summed per function and per quantity (the `// <quantity>:`
# line under each banner), per call of the flat full solve (bench/README.md, "The
# figures").
#
#   bash bench/instructions_by_quantity.sh <scene> [policy]     (policy default: original)
#   bash bench/instructions_by_quantity.sh <scene> derivatives_<policy>   (scene key derivatives)
#
# Builds a small driver with the scene's source (CXX, default c++; FLAGS, default -O3; -g is
# added, and SWEEPGEN_BATCH_STATE_BY_STATE: the batch lanes, which the driver does not call, left
# out; the counts are the same, the compile a fifth of the time) that calls solve_<policy>_flat (or derivatives_<policy>_flat) on 64 inputs drawn uniformly from [-1, 1] (joint
# positions in radians; run-time directions are then not unit vectors, which changes no
# instruction count: the code is branch-free except where the compiler turns a select into a
# branch), runs it under callgrind with CALLS (default 1000) calls and with none, and prints
# (count with CALLS − count without) / CALLS per quantity, largest first. The joint angles' sin and
# cos are the runtime's (sincos_lanes, in the file); libm's sincos, for angles beyond its range, is
# listed apart; the last line is the whole program's count per call, the driver's loop included,
# as a check on the sum. Needs valgrind (callgrind_annotate).
set -euo pipefail

scene=${1:?usage: instructions_by_quantity.sh <scene> [policy]}
policy=${2:-original}
entry=solve_${policy}_flat out_size=flat_out_size
if [[ $policy == derivatives_* ]]; then entry=${policy}_flat out_size=derivative_flat_out_size; fi
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
cxx=${CXX:-c++}
flags=${FLAGS:--O3}
calls=${CALLS:-1000}
source=$root/generated/$scene.cpp
[ -f "$source" ] || { echo "instructions_by_quantity.sh: no generated/$scene.cpp" >&2; exit 1; }
command -v callgrind_annotate >/dev/null || { echo "instructions_by_quantity.sh: valgrind not found" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

cat >"$tmp/driver.cpp" <<EOF
#include "$scene.hpp"
#include <cstdio>
#include <cstdlib>
#include <random>
namespace solver = $scene::f64;
static double in[64][solver::flat_in_size];
static double out[solver::${out_size}];
int main(int argc, char** argv) {
  const int calls = std::atoi(argv[1]);
  std::mt19937_64 random(1);
  std::uniform_real_distribution<double> uniform(-1, 1);
  for (auto& problem : in)
    for (double& x : problem) x = uniform(random);
  double checksum = 0;
  for (int c = 0; c < calls; ++c) {
    solver::${entry}(in[c % 64], out);
    checksum += out[0];
  }
  std::printf("%g\n", checksum);
}
EOF
# shellcheck disable=SC2086
"$cxx" $flags -g -std=c++17 -DSWEEPGEN_BATCH_STATE_BY_STATE -I"$root/generated" "$tmp/driver.cpp" "$source" -o "$tmp/driver"
for n in 0 "$calls"; do
  valgrind --tool=callgrind -q --dump-line=yes --callgrind-out-file="$tmp/out.$n" "$tmp/driver" "$n" >/dev/null
done

# The annotated generated source (every line: --context covers the file), "<count> <text>" per
# line, and libm's sincos from the per-function table; for CALLS calls minus for none.
# (callgrind_annotate names the file relative to the working directory where it can.)
annotate() {  # <callgrind file> -> "<line number>\t<count>\t<text>" per line of the generated source
  callgrind_annotate --auto=yes --show-percs=no --context=1000000 "$1" 2>/dev/null |
    awk -v file="generated/$scene.cpp" '
      /^-- Auto-annotated source: / { inside = substr($0, length($0) - length(file) + 1) == file; line = 0; next }
      inside && /^Ir/ { line = 1; getline; next }
      inside && /^-- line [0-9]+ -/ { line = $3; next }
      inside && /^-----/ { if (line) inside = 0; next }
      inside && / => / && match($0, /^ *[0-9,]+  => /) { next }  # a call'"'"'s inclusive cost, not a line
      inside && line && match($0, /^ *([0-9,]+|\.) /) {
        n = substr($0, 1, RLENGTH); gsub(/[ ,]/, "", n); if (n == ".") n = 0
        print line "\t" n "\t" substr($0, RLENGTH + 2); ++line }'
}
libm() {  # instructions in libm's sincos (its self cost, in the per-function table)
  callgrind_annotate --auto=no --show-percs=no "$1" 2>/dev/null |
    awk '/^ *[0-9,]+ +[^ ]*:__sincos/ { n = $1; gsub(",", "", n); s += n } END { print s + 0 }'
}
annotate "$tmp/out.0" >"$tmp/lines.0"
annotate "$tmp/out.$calls" >"$tmp/lines.n"
sincos=$(( $(libm "$tmp/out.$calls") - $(libm "$tmp/out.0") ))
program() { sed -n 's/^summary: *//p' "$1"; }  # the whole program's count
program=$(( $(program "$tmp/out.$calls") - $(program "$tmp/out.0") ))

awk -F'\t' -v calls="$calls" -v sincos="$sincos" -v program="$program" '
  FILENAME == ARGV[1] { base[$1] = $2; next }  # (empty where no line of the file ran: N = 0)
  {
    text = $3
    # A function definition begins a function (the sweeps are templates, <stage>_of, over the value
    # type: their rows read <stage>); the runtime'"'"'s (sincos_lanes, equilibration_scale, ...) keep
    # their names.
    if (text !~ /^(using|typedef) / && match(text, /^[A-Za-z][^(]* [a-z_0-9]+\(/)) {
      fn = substr(text, 1, RLENGTH - 1); sub(/.* /, "", fn); sub(/_of$/, "", fn); quantity = "(loads, stores, call)" }
    if (match(text, /^  \/\/ [a-z_0-9]+: /)) { quantity = substr(text, 6, RLENGTH - 7) }
    n = $2 - base[$1]
    if (n > 0) { total[fn " / " quantity] += n; all += n }
  }
  END {
    for (k in total) if (total[k] / calls >= 1) printf "%9.0f  %s\n", total[k] / calls, k | "sort -rn"
    close("sort -rn")
    printf "%9.0f  libm sincos\n", sincos / calls
    printf "%9.0f  total per call (the generated file and libm sincos)\n", (all + sincos) / calls
    printf "%9.0f  the whole program per call (with the driver loop)\n", program / calls
  }' "$tmp/lines.0" "$tmp/lines.n"
