#!/usr/bin/env bash
# The GPU's results against the binary128 referee: each OUT/<scene>.sample that bench/gpu/run.sh
# wrote (1 000 states of the double solve: flat input and the GPU's flat output) judged by
#   sweepgen report --scene robots/*/<scene>.yaml --judge OUT/<scene>.sample
# (report/flat_judgement.hpp: full-rank states within 100 eps κ, the referee's status bits,
# finite results). Needs the project built in BUILD (default build/); runs where OUT was copied.
#   bash bench/gpu/judge.sh OUT [BUILD]
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$(dirname "$here")")
out=${1:?usage: judge.sh OUT [BUILD]}
sweepgen=${2:-$root/build}/generator/sweepgen
[ -x "$sweepgen" ] || { echo "judge.sh: $sweepgen not built (cmake --build --preset release --target sweepgen sweepgen-report)" >&2; exit 1; }
status=0 judged=0
for sample in "$out"/*.sample; do
  [ -e "$sample" ] || break
  stem=$(basename "$sample" .sample)
  scene=$(ls "$root"/robots/*/"$stem".yaml 2>/dev/null | head -1)
  if [ -z "$scene" ]; then echo "binary128: $stem: no robots/*/$stem.yaml"; status=1; continue; fi
  echo "== binary128: $stem"
  "$sweepgen" report --scene "$scene" --judge "$sample" || status=1
  judged=$((judged + 1))
done
echo "binary128: $judged samples judged"
[ "$judged" -gt 0 ] || { echo "judge.sh: no OUT/*.sample in $out" >&2; exit 1; }
exit $status
