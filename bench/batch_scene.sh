#!/usr/bin/env bash
# The batch entry point against the flat loop on any scene, a user's robot included, built as a
# default build builds it (bench/README.md, "The default build"):
#
#   bash bench/batch_scene.sh [SCENE.yaml] [STATES]   (default: robots/quadruped/quadruped_stance.yaml,
#                                                     16 384 states a batch call)
#
# Compiles the scene's generated solver per object with bench/compile_time.sh (the baseline, which
# hands each batch call to the widest ISA object the CPU runs, and one object per ISA of ISAS,
# default "x86-64-v3"), links bench/support/batch_scene_driver.cpp to them and runs it: the f64
# variant's first policy, per state, flat and batch (thread CPU time: on a loaded machine the
# ratio is what to read). Environment as compile_time.sh's (SWEEPGEN, CXX, FLAGS, ISAS).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
scene=${1:-$root/robots/quadruped/quadruped_stance.yaml}
cxx=${CXX:-c++}
flags=${FLAGS:--O2}
export ISAS=${ISAS-x86-64-v3}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

KEEP=$work bash "$here/compile_time.sh" "$scene"
# The scene's namespace: the header's first namespace.
namespace=$(grep -m1 -E '^namespace [A-Za-z_][A-Za-z0-9_]* \{$' "$work/solver.hpp" | awk '{ print $2 }')
grep -q '^namespace f64 {$' "$work/solver.hpp" ||
  { echo "batch_scene.sh: the scene has no double variant (scalars: [double])" >&2; exit 1; }
objects=("$work/baseline.o")
for isa in $ISAS; do objects+=("$work/${isa#x86-64-}.o"); done
# shellcheck disable=SC2086
"$cxx" $flags -std=c++17 -DSWEEPGEN_SCENE="$namespace" -I"$work" "$here/support/batch_scene_driver.cpp" "${objects[@]}" \
  -o "$work/driver"
"$work/driver" "${2:-16384}"
