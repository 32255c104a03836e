#!/usr/bin/env bash
# The constrained solve beside its peer, in one command: the lean scenes of the peer's problems
# (Pinocchio 3.7 + CppADCodeGen's ABA and constraintDynamics: the Panda with no constraint, with
# a 6-D contact at the hand, its six directions fixed or run-time inputs; the quadruped on a
# free-flyer with no constraint and with its four point feet, 4 x 3-D, refined) in instructions
# per call of solve_original_flat at `-O2` and at `-O3 -march=x86-64-v3`, each beside the peer's
# figure, the ratio ours / peer's, and the target it is held to: an upper bound ("must") and the
# aim, 1.5x ahead of the peer; for the unconstrained rows the bound is the figure they had when
# the targets were set (bench/README.md, "The constraint part of a solve against the peer").
#
#   bash bench/constrained_against_peer.sh          (CALLS, default 300; FLAGS_V3 to change the second flag set)
#
# Counts the committed generated/ files with instructions_by_quantity.sh (the whole program per
# call: its own 64 inputs uniform in [-1, 1], so the figures differ from the peer harness's, which
# draws the joints within their limits, by 1-2 %). Needs valgrind.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
v3=${FLAGS_V3:--O3 -march=x86-64-v3}

# scene | problem | peer -O2 | peer v3 | must -O2 | must v3 | aim -O2 | aim v3 (- where none)
rows=(
  "panda_lean_nc0|Panda ABA|7498|4908|4464|2884|-|-"
  "panda_lean_nc6_fixed|Panda 6-D tip, fixed directions|8773|5537|7000|4400|5800|3690"
  "panda_lean_nc6|Panda 6-D tip, run-time directions|8773|5537|8000|4900|6500|4000"
  "quadruped_lean_nc0|quadruped free-flyer ABA|18007|11353|9852|6583|-|-"
  "quadruped_lean_nc12_fixed|quadruped 4 point feet, refined|24940|15323|20000|13300|16600|10200"
)
count() {  # <scene> <flags>: instructions per call of the whole program (the script's last line)
  FLAGS=$2 CALLS=${CALLS:-300} bash "$here/instructions_by_quantity.sh" "$1" | tail -1 | awk '{print $1}'
}
printf '%-36s %-6s %8s %8s %6s %8s %8s %s\n' problem flags ours peer ratio must aim met
for row in "${rows[@]}"; do
  IFS='|' read -r scene what peer_o2 peer_v3 must_o2 must_v3 aim_o2 aim_v3 <<< "$row"
  for set in "-O2|$peer_o2|$must_o2|$aim_o2" "$v3|$peer_v3|$must_v3|$aim_v3"; do
    IFS='|' read -r flags peer must aim <<< "$set"
    ours=$(count "$scene" "$flags")
    awk -v what="$what" -v f="$([ "$flags" = -O2 ] && echo O2 || echo v3)" -v o="$ours" -v p="$peer" -v m="$must" -v a="$aim" \
      'BEGIN { met = o <= m ? (a != "-" && o <= a ? "must, aim" : "must") : "no";
               printf "%-36s %-6s %8d %8d %6.2f %8s %8s %s\n", what, f, o, p, o / p, m, a, met }'
  done
done
