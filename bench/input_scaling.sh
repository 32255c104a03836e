#!/usr/bin/env bash
# Generator time and peak memory against robot and scene size (bench/README.md, "Generator time
# and memory against robot and scene size").
#
#   bash bench/input_scaling.sh [SWEEPGEN] [JOINTS...] [-- INSTANCES...]
#
# joints: a generated chain URDF of N revolute joints (axes z, y, x in turn, every link with a
# mass), `sweepgen info --urdf` and `sweepgen generate --urdf` (the default scene: one torque and
# one external-force instance, six run-time constraint directions on the tip, every policy).
# instances: the bundled Panda (robots/panda/panda.urdf) with N external-force instances spread
# over its seven moving links, six run-time constraint directions on the hand, decomposed (one
# track per instance), the original policy, `info --scene` and `generate --scene`.
# Prints one line per run: what, size, command, CPU seconds (user + system: on a shared machine
# steadier than the wall time, which is printed beside), peak resident memory (MiB), exit code. A
# run is stopped after LIMIT seconds of wall time (default 600; printed as "timeout").
# Defaults: SWEEPGEN build/generator/sweepgen, JOINTS 100 300 1000 3000, INSTANCES the same.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
sweepgen=$root/build/generator/sweepgen
if [ $# -gt 0 ] && [ "$1" != "--" ] && ! [[ $1 =~ ^[0-9]+$ ]]; then sweepgen=$1; shift; fi
joints=() instances=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do joints+=("$1"); shift; done
[ $# -gt 0 ] && shift
instances=("$@")
[ ${#joints[@]} -gt 0 ] || joints=(100 300 1000 3000)
[ ${#instances[@]} -gt 0 ] || instances=(100 300 1000 3000)
limit=${LIMIT:-600}
[ -x "$sweepgen" ] || { echo "input_scaling.sh: $sweepgen not built (cmake --build build --target sweepgen)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "input_scaling.sh: /usr/bin/time not found (Debian: apt-get install time)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

chain_urdf() {  # chain_urdf N FILE
  local n=$1 i axes=("0 0 1" "0 1 0" "1 0 0")
  {
    echo '<robot name="chain">'
    echo '  <link name="l0"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>'
    for ((i = 1; i <= n; ++i)); do
      echo "  <link name=\"l$i\"><inertial><origin xyz=\"0 0 0.05\"/><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>"
      echo "  <joint name=\"j$i\" type=\"revolute\"><parent link=\"l$((i - 1))\"/><child link=\"l$i\"/><origin xyz=\"0 0 0.1\"/><axis xyz=\"${axes[$((i % 3))]}\"/><limit lower=\"-3\" upper=\"3\" effort=\"100\" velocity=\"1\"/></joint>"
    done
    echo '</robot>'
  } >"$2"
}

instances_scene() {  # instances_scene N FILE
  local n=$1 i
  {
    echo "sweepgen_scene: 1"
    echo "solver: instances_$n"
    echo "urdf: $root/robots/panda/panda.urdf"
    echo "root: panda_link0"
    echo "tip: panda_hand"
    echo "drivers:"
    echo "  constraints: 6"
    echo "  external_forces:"
    for ((i = 0; i < n; ++i)); do echo "    - {name: f$i, link: panda_link$((i % 7 + 1))}"; done
  } >"$2"
}

run() {  # run WHAT SIZE COMMAND...
  local what=$1 size=$2 rc=0
  shift 2
  timeout "$limit" /usr/bin/time -f '%U %S %e %M' -o "$tmp/time" "$@" >"$tmp/out" 2>"$tmp/err" || rc=$?
  if [ "$rc" = 124 ]; then
    printf '%-10s %6s %-9s %9s %9s %9s %4s\n' "$what" "$size" "$2" "> $limit" - - "$rc"
  else
    read -r user system wall kib < <(tail -1 "$tmp/time")
    printf '%-10s %6s %-9s %9.2f %9.2f %9d %4s\n' "$what" "$size" "$2" "$(awk -v u="$user" -v s="$system" 'BEGIN { print u + s }')" "$wall" \
      $((kib / 1024)) "$rc"
  fi
  [ "$rc" = 0 ] || [ "$rc" = 124 ] || sed 's/^/    /' "$tmp/err" | head -3
}

printf '%-10s %6s %-9s %9s %9s %9s %4s\n' input size command cpu_s wall_s peak_MiB exit
for n in "${joints[@]}"; do
  chain_urdf "$n" "$tmp/chain_$n.urdf"
  run joints "$n" "$sweepgen" info --urdf "$tmp/chain_$n.urdf"
  run joints "$n" "$sweepgen" generate --urdf "$tmp/chain_$n.urdf" --out "$tmp/out_$n"
done
for n in "${instances[@]}"; do
  instances_scene "$n" "$tmp/instances_$n.yaml"
  run instances "$n" "$sweepgen" info --scene "$tmp/instances_$n.yaml"
  run instances "$n" "$sweepgen" generate --scene "$tmp/instances_$n.yaml" --out "$tmp/out_i$n"
done
