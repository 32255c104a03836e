#!/usr/bin/env bash
# The PyTorch layer's CUDA path (README, "PyTorch") on a machine with an NVIDIA GPU (CI has none):
# builds the modules of test_torch.py's scenes with their CUDA kernels (tests/python/cuda/CMakeLists.txt:
# nvcc, a Python with NumPy, pybind11 and PyTorch; no other dependency) and runs test_torch_cuda.py,
# then bench/torch_overhead.py on the GPU.
#   bash tests/python/cuda/run.sh [BUILD] [MORE] [CMAKE ARGUMENTS...]
# BUILD: default build-torch-cuda/. MORE: a directory of the files `sweepgen generate` wrote for
# tests/python's own scenes (planar_floating_derivatives, gripper_coupled_derivatives); without it,
# they are generated into BUILD/more by build/generator/sweepgen where that is built, and on a
# machine without the generator MORE is made where it is built and copied over:
#   for s in planar_floating_derivatives gripper_coupled_derivatives; do
#     build/generator/sweepgen generate --scene tests/python/$s.yaml --out MORE; done
# PYTHON (default python3) is the interpreter, ARCH (default native) the GPU architecture.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../../.." && pwd)
build=$(realpath -m "${1:-$root/build-torch-cuda}")
more=${2:+$(cd "$2" && pwd)}
shift $(($# < 2 ? $# : 2))
python=$(command -v "${PYTHON:-python3}")
if [ -z "$more" ]; then
  sweepgen=$root/build/generator/sweepgen
  [ -x "$sweepgen" ] || { echo "run.sh: no MORE given and no $sweepgen to generate tests/python's scenes with" >&2; exit 1; }
  more=$build/more
  for s in planar_floating_derivatives gripper_coupled_derivatives; do
    "$sweepgen" generate --quiet --scene "$root/tests/python/$s.yaml" --out "$more"
  done
fi
scenes="$root/generated/panda_lean_nc6_fixed_derivatives;$root/generated/panda_lean_nc0_derivatives"
for hpp in "$more"/*.hpp; do scenes+=";${hpp%.hpp}"; done
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader || true
pybind11=()  # pip's pybind11 says where its CMake files are; Debian's are found as they are
if dir=$("$python" -m pybind11 --cmakedir 2>/dev/null); then pybind11=(-Dpybind11_DIR="$dir"); fi
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE="$python" \
  "${pybind11[@]}" -DCMAKE_CUDA_ARCHITECTURES="${ARCH:-native}" \
  -DSWEEPGEN_TORCH_CUDA_SCENES="$scenes" -DSWEEPGEN_TORCH_CPU_SCENES="$root/generated/panda_nc6" "$@"
start=$SECONDS
cmake --build "$build"
echo "build: $((SECONDS - start)) s"
PYTHONPATH="$build/python" "$python" -B "$here/test_torch_cuda.py"
PYTHONPATH="$build/python" "$python" -B "$root/bench/torch_overhead.py" --device cuda
