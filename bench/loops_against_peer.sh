#!/usr/bin/env bash
# Closed chains against the peer in one command (bench/README.md, "Closed chains against the peer"):
# the dual Panda with one 6-D set between its hands and the delta robot with its three 3-D ball
# loops, lean (one torque track, composed, original, double, no NaN checks), in instructions per
# call of solve_original_flat at `-O2` and at `-O3 -march=x86-64-v3`, beside Pinocchio 3.7 +
# CppADCodeGen's constraintDynamics with RigidConstraintModels between two joints (CONTACT_6D, three
# CONTACT_3D; figures measured outside this repository on the same states for both sides), each
# with every output of a solve and with the peer's outputs only (outputs: [qdd, nu]); and the dual
# Panda with the same six directions as a world set on the left hand, what a loop set adds.
#
#   bash bench/loops_against_peer.sh [build dir, default build]     (CALLS, default 300)
#   KEEP=DIR keeps the scenes and their generated files in DIR (bench/ and generated/ there), so that
#   `FLAGS=-O2 bash DIR/bench/instructions_by_quantity.sh <scene>` splits a row by quantity.
#
# The scenes are generated afresh by the build's sweepgen into a directory of their own and counted
# there by instructions_by_quantity.sh (its own 64 inputs uniform in [-1, 1], so the figures differ
# from the peer harness's, which draws the joints within their limits, by 1-2 %). Needs valgrind.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
build=${1:-build}
sweepgen=$build/generator/sweepgen
[ -x "$sweepgen" ] || { echo "loops_against_peer.sh: no $sweepgen (build the target sweepgen first)" >&2; exit 1; }
if [ -n "${KEEP:-}" ]; then tmp=$KEEP; else tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT; fi
mkdir -p "$tmp/bench" "$tmp/generated" "$tmp/scenes"
cp "$here/instructions_by_quantity.sh" "$tmp/bench/"

identity='[[1, 0, 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 1]]'
lean='decomposition: composed
policies: [original]
scalars: [double]
expose: outputs
check_inputs: false'
dual_panda() {  # <solver> <the set's keys after link and at>
  printf 'sweepgen_scene: 1\nsolver: %s\nurdf: %s\nroot: station\ntips: [left_panda_hand, right_panda_hand]\n' \
    "$1" "$root/robots/dual_panda/dual_panda.urdf"
  printf 'drivers:\n  torques: [tau_ff]\n  constraints:\n'
  printf '    - {link: left_panda_hand, at: {xyz: [0, 0, 0.1034]}, %sdirections: %s}\n%s\n' "$2" "$identity" "$lean"
}
loop='relative_to: right_panda_hand, relative_at: {xyz: [0, 0, 0.5034], rpy: [3.141592653589793, 0, 0]}, '
dual_panda dual_panda_loop6 "$loop" > "$tmp/scenes/dual_panda_loop6.yaml"
dual_panda dual_panda_world6 "" > "$tmp/scenes/dual_panda_world6.yaml"
# The delta: robots/delta/delta_loops.yaml's model and sets, lean.
sed -n '/^drivers:/,/^policies:/p' "$root/robots/delta/delta_loops.yaml" | sed '$d' > "$tmp/delta_drivers"
{ printf 'sweepgen_scene: 1\nsolver: delta_loop3x3\nurdf: %s\nroot: base\ntips: [platform, forearm_0, forearm_1, forearm_2]\n' \
    "$root/robots/delta/delta.urdf"
  cat "$tmp/delta_drivers"; echo "$lean"; } > "$tmp/scenes/delta_loop3x3.yaml"
for s in dual_panda_loop6 delta_loop3x3; do  # the peer's outputs only
  sed "s/^solver: $s\$/solver: ${s}_qdd_nu/" "$tmp/scenes/$s.yaml" > "$tmp/scenes/${s}_qdd_nu.yaml"
  echo "outputs: [qdd, nu]" >> "$tmp/scenes/${s}_qdd_nu.yaml"
done
for scene in "$tmp/scenes/"*.yaml; do "$sweepgen" generate --scene "$scene" --out "$tmp/generated" > /dev/null; done

# scene | problem | the peer's -O2 and v3 figures (- where none)
rows=(
  "dual_panda_loop6|dual Panda, 6-D loop, every output|20829|13142"
  "dual_panda_loop6_qdd_nu|dual Panda, 6-D loop, qdd and nu|20829|13142"
  "dual_panda_world6|dual Panda, 6-D world set (no peer)|-|-"
  "delta_loop3x3|delta, 3 x 3-D loops, every output|7547|4923"
  "delta_loop3x3_qdd_nu|delta, 3 x 3-D loops, qdd and nu|7547|4923"
)
count() {  # <scene> <flags>: instructions per call of the whole program (its last line)
  FLAGS=$2 CALLS=${CALLS:-300} bash "$tmp/bench/instructions_by_quantity.sh" "$1" | tail -1 | awk '{print $1}'
}
printf '%-40s %9s %9s %7s %9s %9s %7s\n' "problem" "-O2" "peer" "ratio" "v3" "peer" "ratio"
for row in "${rows[@]}"; do
  IFS='|' read -r scene what peer_o2 peer_v3 <<< "$row"
  o2=$(count "$scene" "-O2")
  v3=$(count "$scene" "-O3 -march=x86-64-v3")
  awk -v what="$what" -v o2="$o2" -v p2="$peer_o2" -v v3="$v3" -v p3="$peer_v3" \
    'BEGIN { r2 = p2 == "-" ? "-" : sprintf("%.2f", o2 / p2); r3 = p3 == "-" ? "-" : sprintf("%.2f", v3 / p3);
             printf "%-40s %9d %9s %7s %9d %9s %7s\n", what, o2, p2, r2, v3, p3, r3 }'
done
