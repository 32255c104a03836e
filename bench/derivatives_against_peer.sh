#!/usr/bin/env bash
# The derivatives against the peer in one command: the derivatives of the lean Panda and iiwa14 scenes (the
# peer's problems: Nc = 0, ∂q̈/∂(q, q̇, τ); a 6-D contact at the hand, ∂q̈ and ∂ν) in instructions per
# call of derivatives_original_flat at `-O2` and at `-O3 -march=x86-64-v3`, beside Pinocchio 3.7 +
# CppADCodeGen's figures (measured outside this repository), and the ratio ours / peer's
# (bench/docs/generated-code.md, "Derivatives").
#
#   bash bench/derivatives_against_peer.sh [build dir, default build]     (CALLS, default 100)
#
# The Panda scenes are the bundled panda_lean_nc0_derivatives and panda_lean_nc6_fixed_derivatives;
# the iiwa14's are its lean scenes with the same key added (derivatives: [qdd] and [qdd, nu]), not
# bundled (each takes ~30 s to compile). All four are generated afresh by the build's sweepgen
# into a directory of their own and counted there by instructions_by_quantity.sh. Needs valgrind.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
build=${1:-build}
sweepgen=$build/generator/sweepgen
[ -x "$sweepgen" ] || { echo "derivatives_against_peer.sh: no $sweepgen (build the target sweepgen first)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir -p "$tmp/bench" "$tmp/generated" "$tmp/scenes"
cp "$here/instructions_by_quantity.sh" "$tmp/bench/"

cp "$root/robots/panda/panda_lean_nc0_derivatives.yaml" "$root/robots/panda/panda_lean_nc6_fixed_derivatives.yaml" "$tmp/scenes/"
sed -i "s|^urdf: panda.urdf|urdf: $root/robots/panda/panda.urdf|" "$tmp/scenes/"panda_*.yaml
for scene in nc0:qdd "nc6_fixed:qdd, nu"; do
  name=${scene%%:*}
  sed "s/^solver: iiwa14_lean_$name\$/solver: iiwa14_lean_${name}_derivatives/; s|^urdf: iiwa14.urdf|urdf: $root/robots/iiwa14/iiwa14.urdf|" \
    "$root/robots/iiwa14/iiwa14_lean_$name.yaml" > "$tmp/scenes/iiwa14_lean_${name}_derivatives.yaml"
  echo "derivatives: [${scene#*:}]" >> "$tmp/scenes/iiwa14_lean_${name}_derivatives.yaml"
done
for scene in "$tmp/scenes/"*.yaml; do "$sweepgen" generate --scene "$scene" --out "$tmp/generated" > /dev/null 2>&1; done

# scene | what the peer returns | the peer's -O2 and v3 figures
rows=(
  "panda_lean_nc0_derivatives|Panda Nc = 0, dqdd/d(q, qd, tau)|21306|13075"
  "panda_lean_nc6_fixed_derivatives|Panda 6-D, dqdd and dnu|35637|19898"
  "iiwa14_lean_nc0_derivatives|iiwa14 Nc = 0, dqdd/d(q, qd, tau)|20848|12621"
  "iiwa14_lean_nc6_fixed_derivatives|iiwa14 6-D, dqdd and dnu|34359|19540"
)
count() {  # <scene> <flags>: instructions per call of the whole program (its last line)
  FLAGS=$2 CALLS=${CALLS:-100} bash "$tmp/bench/instructions_by_quantity.sh" "$1" derivatives_original | tail -1 | awk '{print $1}'
}
printf '%-40s %9s %9s %7s %9s %9s %7s\n' "problem" "-O2" "peer" "ratio" "v3" "peer" "ratio"
for row in "${rows[@]}"; do
  IFS='|' read -r scene what peer_o2 peer_v3 <<< "$row"
  o2=$(count "$scene" "-O2")
  v3=$(count "$scene" "-O3 -march=x86-64-v3")
  awk -v what="$what" -v o2="$o2" -v p2="$peer_o2" -v v3="$v3" -v p3="$peer_v3" \
    'BEGIN { printf "%-40s %9d %9d %7.2f %9d %9d %7.2f\n", what, o2, p2, o2 / p2, v3, p3, v3 / p3 }'
done
