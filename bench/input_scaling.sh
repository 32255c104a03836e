#!/usr/bin/env bash
# Generator time and peak memory against robot and scene size (bench/README.md, "Generator time
# and memory against robot and scene size").
#
#   bash bench/input_scaling.sh [SWEEPGEN] [JOINTS...] [-- INSTANCES...] [-- MIB...]
#
# joints: a generated chain URDF of N revolute joints (axes z, y, x in turn, every link with a
# mass), `sweepgen info --urdf` and `sweepgen generate --urdf` (the default scene: one torque and
# one external-force instance, six run-time constraint directions on the tip, every policy).
# instances: the bundled Panda (robots/panda/panda.urdf) with N external-force instances spread
# over its seven moving links, six run-time constraint directions on the hand, decomposed (one
# track per instance), the original policy, `info --scene` and `generate --scene`.
# MiB: the two hostile shapes of that many MiB (less 64 bytes), refused by the readers' outline
# checks: a scene whose gravity is a sequence of zeros (`info --scene`, sizes up to the 8 MiB
# limit) and a URDF of one moving joint and `<a/>` elements (`info --urdf`, up to 32 MiB); exit 1
# is their expected end.
# Prints one line per run: what, size, command, CPU seconds (user + system: on a shared machine
# steadier than the wall time, which is printed beside), peak resident memory (MiB), exit code. A
# run is stopped after LIMIT seconds of wall time (default 600; printed as "timeout").
# Defaults: SWEEPGEN build/generator/sweepgen; without sizes, JOINTS 100 300 1000 3000, INSTANCES the
# same, MIB 1 2 4 8 16 32; with any, a group left empty is skipped (`-- -- 8 32`: the hostile shapes).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$here")
sweepgen=$root/build/generator/sweepgen
if [ $# -gt 0 ] && [ "$1" != "--" ] && ! [[ $1 =~ ^[0-9]+$ ]]; then sweepgen=$1; shift; fi
joints=() instances=()
while [ $# -gt 0 ] && [ "$1" != "--" ]; do joints+=("$1"); shift; done
[ $# -gt 0 ] && shift
while [ $# -gt 0 ] && [ "$1" != "--" ]; do instances+=("$1"); shift; done
[ $# -gt 0 ] && shift
mibs=("$@")
if [ ${#joints[@]} -eq 0 ] && [ ${#instances[@]} -eq 0 ] && [ ${#mibs[@]} -eq 0 ]; then
  joints=(100 300 1000 3000) instances=(100 300 1000 3000) mibs=(1 2 4 8 16 32)
fi
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

# hostile FILE BYTES HEAD UNIT TAIL: HEAD, then UNIT repeated, then TAIL, BYTES in all (give or take a unit).
hostile() {
  python3 -c 'import sys; n, head, unit, tail = int(sys.argv[1]), *sys.argv[2:5]
sys.stdout.write(head + unit * ((n - len(head) - len(tail)) // len(unit)) + tail)' "$2" "$3" "$4" "$5" >"$1"
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
# A robot of one moving joint, which the `<a/>` elements follow: valid, were it not for them.
two_links='<robot name="r"><link name="l0"/><link name="l1"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link><joint name="j" type="revolute"><parent link="l0"/><child link="l1"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
'
for mib in "${mibs[@]}"; do
  bytes=$((mib * 1048576 - 64))
  if [ "$mib" -le 8 ]; then
    hostile "$tmp/gravity.yaml" "$bytes" $'sweepgen_scene: 1\nsolver: s\nurdf: r.urdf\ngravity: [0' ',0' $']\n'
    run gravity "${mib}MiB" "$sweepgen" info --scene "$tmp/gravity.yaml"
  fi
  hostile "$tmp/elements.urdf" "$bytes" "$two_links" '<a/>' $'\n</robot>\n'
  run elements "${mib}MiB" "$sweepgen" info --urdf "$tmp/elements.urdf"
done
