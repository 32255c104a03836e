#!/usr/bin/env bash
# A consumer's compile time of one scene's generated solver, per object (bench/README.md,
# "Compile time of big robots").
#
#   bash bench/compile_time.sh [SCENE.yaml]      (default: robots/quadruped/quadruped_stance.yaml)
#
# Generates the scene's solver with SWEEPGEN (default build/generator/sweepgen; a user's scene
# and its URDF can lie anywhere) into a temporary directory and compiles its source as
# sweepgen_add_solver does in a default build (cmake/SweepgenAddSolver.cmake): the baseline
# object (every scalar function; the batch entry points hand over to the ISA objects) and one
# object per ISA of ISAS (only the batch entry points, -march=<isa> -ffp-contract=off), each
# with CXX (default c++) FLAGS (default -O2) -c, one at a time. Prints per object the CPU time
# of the compiler (user + sys: on a loaded machine the wall time says little), its peak memory
# and the largest functions of the object. TIME_REPORT=1 adds the compiler's passes that took
# the most time (g++'s -ftime-report).
# Environment: SWEEPGEN, CXX, FLAGS, ISAS (default "x86-64-v3 x86-64-v4"; "" for the baseline
# alone), TIME_REPORT, KEEP (a directory: the generated files and objects stay there).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
scene=${1:-$root/robots/quadruped/quadruped_stance.yaml}
sweepgen=${SWEEPGEN:-$root/build/generator/sweepgen}
cxx=${CXX:-c++}
flags=${FLAGS:--O2}
isas=${ISAS-x86-64-v3 x86-64-v4}
[ -x "$sweepgen" ] || { echo "compile_time.sh: no generator at $sweepgen (build the target sweepgen, or set SWEEPGEN)" >&2; exit 1; }
[ -f "$scene" ] || { echo "compile_time.sh: no scene file $scene" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "compile_time.sh: /usr/bin/time not found (Debian: apt-get install time)" >&2; exit 1; }
if [ -n "${KEEP:-}" ]; then
  tmp=$KEEP
  mkdir -p "$tmp"
else
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
fi

"$sweepgen" generate --quiet --scene "$scene" --out "$tmp" --file-stem solver
echo "scene: $scene ($(grep -c '' "$tmp/solver.cpp") lines of generated source)"
grep -m1 -F '//   f64: outward + decompose + solve_' "$tmp/solver.hpp" | sed 's|^//  *|operations: |' || true
fused=$(grep -m1 -o '[0-9]* operations in this file, at most [0-9]* fused' "$tmp/solver.cpp" || true)
echo "solve_<policy>_flat: ${fused:+fused (}${fused:-not fused: calls outward, decompose and the solve}${fused:+)}"
echo "parts (noinline lambdas) of long functions: $(grep -c 'SWEEPGEN_PART {' "$tmp/solver.cpp" || true); pivoted paths of (C4): $(grep -c 'pivoted = \[' "$tmp/solver.cpp" || true)"

# The defines a default build gives the baseline object: the ISA objects it dispatches to.
dispatch=()
for isa in $isas; do dispatch+=("-DSWEEPGEN_BATCH_$(echo "${isa//-/_}" | tr '[:lower:]' '[:upper:]')"); done

# compile <name> <extra flags...>: one object, timed.
compile() {
  local name=$1
  shift
  # shellcheck disable=SC2086
  /usr/bin/time -f '%U %S %M' -o "$tmp/$name.time" "$cxx" $flags -std=c++17 "${dispatch[@]}" "$@" \
    ${TIME_REPORT:+-ftime-report} -I"$tmp" -c "$tmp/solver.cpp" -o "$tmp/$name.o" 2>"$tmp/$name.log" ||
    { cat "$tmp/$name.log" >&2; exit 1; }
  read -r user sys kib <"$tmp/$name.time"
  printf '%-10s %8.2f %7.0f   ' "$name" "$(awk -v u="$user" -v s="$sys" 'BEGIN { print u + s }')" "$((kib / 1024))"
  # The three largest functions of the object (bytes of code), demangled, their names shortened.
  nm -C --size-sort -S -t d "$tmp/$name.o" | awk '$3 ~ /^[tTwW]$/' | sort -k2,2nr | awk 'NR <= 3' |
    awk '{ n = $0; sub(/^[0-9]+ [0-9]+ [tTwW] /, "", n); sub(/ \[clone.*/, "", n); gsub(/\(anonymous namespace\)/, "", n)
           while (n ~ /<[^<>]*>/) gsub(/<[^<>]*>/, "", n)  # template arguments
           sub(/\(.*/, "", n); sub(/^.*[ :]/, "", n); printf "%s%s %d", (NR > 1 ? ", " : ""), n, $2 + 0 }'
  echo
  if [ -n "${TIME_REPORT:-}" ]; then
    grep -E '^ [a-zA-Z].*: +[0-9.]+ \(' "$tmp/$name.log" | grep -vE 'TOTAL|phase |callgraph' |
      awk -F: '{ split($2, a, " "); printf "    %6.2f  %s\n", a[1], $1 }' | sort -rn | awk 'NR <= 6' 
  fi
}

printf '%-10s %8s %7s   %s\n' object cpu_s peak_MiB 'largest functions (bytes of code)'
compile baseline
for isa in $isas; do
  name=${isa//-/_}
  compile "${name#x86_64_}" -DSWEEPGEN_BATCH_ISA="$name" -march="$isa" -ffp-contract=off
done
