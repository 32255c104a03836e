#!/usr/bin/env bash
# The GPU figures of bench/README.md, "GPU", on a machine with an NVIDIA GPU and nvcc (CI has
# neither). Needs only the committed generated/ files and nvcc, no other dependency:
#   bash bench/gpu/run.sh [OUT]        (OUT: default build-gpu/; 156 s on an H200 machine's 16 cores)
#   SCENES="panda_nc6 ur5_nc6" bash bench/gpu/run.sh [OUT]   (those scenes only)
# 1. prints the device, driver and nvcc versions;
# 2. compiles bench/gpu/gpu_bench.cu once per bundled scene with nvcc -O3 -arch=native (ARCH), warnings as
#    errors, ptxas -v (registers, spill stores and loads, stack frame of each kernel), in parallel;
# 3. runs each: the original policy's solve (and derivatives where the scene has them; float
#    where it has float) at n = 128, 4 096, 65 536 and 1 048 576 states: the kernel alone, and with
#    the copies from pinned memory and back, in states per second; then the GPU against the same
#    generated code on the CPU on 100 000 states (largest relative difference, status words that
#    differ: the run fails on one), and the first 1 000 of those states of the double solve written
#    to OUT/<scene>.sample (flat input and the GPU's flat output, hex floats);
# 4. where the project is built in BUILD (default build/, `sweepgen report`): judges each sample
#    against the binary128 referee (bash bench/gpu/judge.sh OUT BUILD; a machine without the
#    project's dependencies skips this step and says so: run judge.sh where OUT is copied to).
# Everything it prints is also in OUT/gpu.txt; ptxas's lines in OUT/<scene>.ptxas.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(dirname "$(dirname "$here")")
out=${1:-$root/build-gpu}
nvcc=${NVCC:-$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)}
[ -x "$nvcc" ] || { echo "run.sh: nvcc not found (set NVCC)" >&2; exit 1; }
mkdir -p "$out"
exec > >(tee "$out/gpu.txt") 2>&1

nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader || echo "nvidia-smi: not found"
"$nvcc" --version | tail -2

scenes=()
for hpp in "$root"/generated/*.hpp; do scenes+=("$(basename "$hpp" .hpp)"); done
if [ -n "${SCENES:-}" ]; then read -r -a scenes <<< "$SCENES"; fi

build() {  # <scene>: the scene's benchmark, and its ptxas report
  local stem=$1 header=$root/generated/$1.hpp flags=()
  local ns
  ns=$(sed -n 's/^namespace \([A-Za-z0-9_:]*\) {$/\1/p' "$header" | head -1)
  grep -q '^namespace f32 {' "$header" && flags+=(-DSWEEPGEN_GPU_HAS_F32)
  grep -q 'derivatives_original_flat' "$header" && flags+=(-DSWEEPGEN_GPU_HAS_DERIVATIVES)
  "$nvcc" -std=c++17 -O3 -arch="${ARCH:-native}" -Werror all-warnings -Xptxas -v -I "$root/generated" \
    -DSWEEPGEN_GPU_SOURCE="\"$stem.cu\"" -DSWEEPGEN_GPU_NAMESPACE="$ns" "${flags[@]}" \
    "$here/gpu_bench.cu" -o "$out/bench_$stem" 2> "$out/$stem.ptxas" || { cat "$out/$stem.ptxas"; return 1; }
}
export -f build
export nvcc root here out ARCH
start=$SECONDS
printf '%s\n' "${scenes[@]}" | xargs -P "$(nproc)" -I{} bash -c 'build {}'
echo "nvcc: ${#scenes[@]} scenes in $((SECONDS - start)) s"

status=0
for stem in "${scenes[@]}"; do
  echo "== $stem"
  # ptxas: each kernel's registers, stack frame and spills
  awk '/Compiling entry function/ { match($0, /_ZN[0-9A-Za-z_]*kernel/); kernel = substr($0, RSTART, RLENGTH) }
       /bytes stack frame/ && kernel { frame = $0 }
       /Used [0-9]+ registers/ && kernel { gsub(/^ +/, "", frame); print "ptxas: " kernel ": " $5 " registers, " frame; kernel = "" }' \
    "$out/$stem.ptxas"
  "$out/bench_$stem" 100000 1000 "$out/$stem.sample" 128 4096 65536 1048576 || status=1
done
echo "total $((SECONDS - start)) s"
build=${BUILD:-$root/build}
if [ -x "$build/generator/sweepgen" ]; then
  bash "$here/judge.sh" "$out" "$build" || status=1
else
  echo "binary128: no sweepgen built in $build: judge the samples where the project is built: bash bench/gpu/judge.sh $out"
fi
exit $status
