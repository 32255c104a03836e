#!/usr/bin/env bash
# Installs everything sweepgen needs from Debian 12 packages. Idempotent: when every package
# is already installed it changes nothing and does not touch the network.
#   install-dependencies.sh            the generator, its report, the tests and benchmarks (README, command 1)
#   install-dependencies.sh consumers  and the derivatives' consumers the tests drive: Ipopt
#                                      (examples/trajectory_optimisation) and PyTorch (README, "PyTorch");
#                                      cmake/test-all.sh (README, command 2) asks for them
set -euo pipefail

packages=(
  g++ cmake ninja-build make pkg-config # toolchain (the presets build with Ninja)
  libeigen3-dev liburdfdom-dev          # tool: linear algebra, URDF parsing
  libyaml-cpp-dev libcli11-dev nlohmann-json3-dev libkainjow-mustache-dev
  libgtest-dev libbenchmark-dev         # tests and benchmarks
  liborocos-kdl-dev libkdl-parser-dev   # test oracle and the optional KDL row of `sweepgen report`
  gnuplot-nox valgrind                  # reports, instruction counts
  pybind11-dev python3-dev python3-numpy # the Python modules (README, "Python")
  clang libclang-rt-14-dev              # second compiler, sanitizers and fuzzing
)
case "${1:-}" in
  "") ;;
  consumers) packages+=(coinor-libipopt-dev python3-torch) ;;
  *) echo "install-dependencies: unknown argument '$1' (none, or 'consumers')" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-dependencies: all ${#packages[@]} packages present"
  exit 0
fi
echo "install-dependencies: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
$SUDO apt-get update
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
