#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), then configures and builds kincal in
# Release under build/. Idempotent: installed packages are skipped, the build is incremental.
# Extra arguments are passed to CMake's configure step (e.g. -DKINCAL_WITH_IPOPT=OFF).
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(
  build-essential cmake ninja-build ccache pkg-config git
  libeigen3-dev libceres-dev libgoogle-glog-dev libnlopt-cxx-dev coinor-libipopt-dev
  libboost-program-options-dev nlohmann-json3-dev
  liburdfdom-dev liburdfdom-tools  # URDF import/export; check_urdf in the tests
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib
  # the Python module (python/, docs/python.md), its tests and its studies on Dask
  pybind11-dev python3-dev python3-numpy python3-pytest mypy python3-distributed
  python3-scipy  # the real-data benchmark's independent calibration (ctest real_data_benchmark_agrees)
  chromium  # tests: the HTML report rendered headless (ctest html_report_renders_in_chromium)
)
# shellcheck source=scripts/install_packages.sh
source scripts/install_packages.sh
install_missing setup "${packages[@]}"

jobs=$(nproc)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
elif (($#)); then
  cmake -S . -B build "$@" >/dev/null
fi
cmake --build build --parallel "$jobs"
