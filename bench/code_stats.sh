#!/usr/bin/env bash
# Per generated solver: compile time, static instruction count and register spills (bench/README.md,
# "Instructions per operation").
#
#   bash bench/code_stats.sh [SCENE...]      (default: every generated/<scene>.cpp)
#
# Reads the committed generated/<scene>.{cpp,hpp} (no build directory needed), compiles each
# RUNS times with CXX FLAGS -c and keeps the fastest wall time (the least disturbed run), then
# reads the object with objdump: its instructions, and those that store to or load from the
# stack frame (%rsp), which in straight-line code of plain `const` locals are the spills and
# reloads of values that did not fit the 16 XMM registers (loads include the arithmetic that
# takes a spilled operand from memory). BASELINE=<git revision> also compiles that revision's
# generated/<scene>.cpp (the same way) and prints the compile-time ratio now / then.
# Environment: CXX (default c++), FLAGS (default -O2), RUNS (default 3), BASELINE (default none).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
cxx=${CXX:-c++}
flags=${FLAGS:--O2}
runs=${RUNS:-3}
baseline=${BASELINE:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

command -v objdump >/dev/null || { echo "code_stats.sh: objdump not found (Debian: apt-get install binutils)" >&2; exit 1; }

if [ $# -gt 0 ]; then scenes=("$@"); else
  scenes=()
  for f in "$root"/generated/*.cpp; do scenes+=("$(basename "$f" .cpp)"); done
fi

# compile_seconds <dir with scene.cpp and scene.hpp> <scene>: fastest of RUNS compiles.
compile_seconds() {
  local dir=$1 scene=$2 best=""
  for ((r = 0; r < runs; ++r)); do
    local start end
    start=$(date +%s.%N)
    # shellcheck disable=SC2086
    "$cxx" $flags -std=c++17 -I"$dir" -c "$dir/$scene.cpp" -o "$dir/$scene.o"
    end=$(date +%s.%N)
    best=$(awk -v a="$best" -v s="$start" -v e="$end" 'BEGIN { t = e - s; if (a == "" || t < a) a = t; printf "%.2f", a }')
  done
  echo "$best"
}

printf '%-24s %8s %10s %10s %7s %9s %8s %7s %8s\n' scene ops compile_s baseline_s ratio text_bytes instr spills reloads
for scene in "${scenes[@]}"; do
  [ -f "$root/generated/$scene.cpp" ] || { echo "code_stats.sh: no generated/$scene.cpp" >&2; exit 1; }
  now=$tmp/now/$scene
  mkdir -p "$now"
  cp "$root/generated/$scene.cpp" "$root/generated/$scene.hpp" "$now/"
  seconds=$(compile_seconds "$now" "$scene")
  then_seconds=- ratio=-
  if [ -n "$baseline" ]; then
    old=$tmp/old/$scene
    mkdir -p "$old"
    if git -C "$root" show "$baseline:generated/$scene.cpp" >"$old/$scene.cpp" 2>/dev/null &&
       git -C "$root" show "$baseline:generated/$scene.hpp" >"$old/$scene.hpp" 2>/dev/null; then
      then_seconds=$(compile_seconds "$old" "$scene")
      ratio=$(awk -v a="$seconds" -v b="$then_seconds" 'BEGIN { printf "%.2f", a / b }')
    fi
  fi
  # The first full-solve line of the header: "//   f64: outward + decompose + solve_<policy>: ... (total N)".
  ops=$(grep -m1 -F '//   f64: outward + decompose + solve_' "$now/$scene.hpp" | sed -n 's/.*(total \([0-9]*\)).*/\1/p')
  text=$(size -A "$now/$scene.o" | awk '$1 == ".text" { print $2 }')
  objdump -d --no-show-raw-insn "$now/$scene.o" | awk -F'\t' '/^ +[0-9a-f]+:\t/ { print $2 }' >"$now/insns"
  instructions=$(wc -l <"$now/insns")
  # AT&T syntax: the destination is the last operand.
  spills=$(grep -cE ',-?(0x[0-9a-f]+)?\(%rsp\)$' "$now/insns" || true)
  reloads=$(grep -cE '(0x[0-9a-f]+)?\(%rsp\),' "$now/insns" || true)
  printf '%-24s %8s %10s %10s %7s %9s %8s %7s %8s\n' "$scene" "${ops:--}" "$seconds" "$then_seconds" "$ratio" "$text" \
    "$instructions" "$spills" "$reloads"
done
