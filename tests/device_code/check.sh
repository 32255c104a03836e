#!/usr/bin/env bash
# Device code of generated CUDA sources, checked with Debian's clang alone (no CUDA SDK, no GPU):
#   bash tests/device_code/check.sh CLANG FILE.cu...
# checks each FILE.cu (its .cpp and .hpp beside it) as device code for an sm_80 GPU, with clang's
# CUDA mode and this folder's stand-ins for what CUDA's headers provide (prelude.hpp,
# include/cuda_runtime.h). A call from device code to a host-only function is an error there,
# as it is for nvcc; clang reports it at the end of its semantic analysis, for every function a
# kernel reaches, so -fsyntax-only finds it (the planted call below shows it) in a fifth of the
# time of compiling to PTX (every bundled scene: 6 s against 32 s of CPU). nvcc also rejects GCC's vector types in device code, which clang accepts, so
# the device pass's preprocessed source must hold none (both compilers define __CUDA_ARCH__ in it).
#   bash tests/device_code/check.sh --planted CLANG FILE.cu
# plants a host-only call (std::strlen) into a copy of FILE.cu's outward() and expects the check
# to fail: the check can fail.
set -uo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
planted=0
if [ "${1:-}" = "--planted" ]; then planted=1; shift; fi
clang=${1:?usage: check.sh [--planted] CLANG FILE.cu...}; shift
flags=(-x cuda --cuda-device-only --cuda-gpu-arch=sm_80 -nocudainc -nocudalib -std=c++17
       -Wno-unknown-cuda-version -I "$here/include" -include "$here/prelude.hpp")
check() {  # FILE.cu: 0 when its device code compiles and holds no vector type
  local log
  if ! log=$("$clang" "${flags[@]}" -fsyntax-only "$1" 2>&1); then echo "$log" | grep -m 5 'error'; return 1; fi
  if "$clang" "${flags[@]}" -E "$1" 2>/dev/null | grep -q 'vector_size'; then
    echo "$1: a GCC vector type in device code (nvcc rejects it)"; return 1
  fi
}
if [ $planted -eq 1 ]; then
  tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
  cu=$1; stem=$(basename "$cu" .cu); dir=$(dirname "$cu")
  cp "$dir/$stem.cu" "$dir/$stem.cpp" "$dir/$stem.hpp" "$tmp/"
  sed -i 's|{ outward_of<Scalar>(q, qd, state); }|{ outward_of<Scalar>(q, qd, state); static_cast<void>(std::strlen("")); }|' "$tmp/$stem.cpp"
  grep -q 'std::strlen' "$tmp/$stem.cpp" || { echo "planting failed: outward() of $stem.cpp has another shape"; exit 2; }
  if check "$tmp/$stem.cu"; then echo "FAIL: a host-only call in device code passed the check"; exit 1; fi
  echo "ok: the planted host-only call fails the check"
  exit 0
fi
failed=0
for cu in "$@"; do
  if check "$cu"; then echo "ok: $cu"; else echo "FAIL: $cu"; failed=1; fi
done
exit $failed
