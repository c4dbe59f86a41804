#!/usr/bin/env bash
# Installs what is missing (Debian 12 packages), then configures and builds kincal in Release
# under build/. Idempotent: installed packages are skipped, the build is incremental.
#
#   scripts/setup.sh [--all] [CMAKE_ARGS...]
#
# Without --all: the packages the program needs and the program only (build/cli/kincal: the
# library and the CLI), so that a fresh machine runs its first command in minutes. With --all:
# also the test suite, the benchmarks, the examples, the Python module and the packages they
# need (GoogleTest, Google Benchmark, pybind11, pytest, mypy, Dask, Chromium for the rendered
# report): what `ctest --test-dir build` runs. Extra arguments go to CMake's configure step
# (e.g. -DKINCAL_WITH_IPOPT=OFF). docs/benchmarks.md#first-start gives the times.
set -euo pipefail
cd "$(dirname "$0")/.."

all=0
if [ "${1:-}" = "--all" ]; then
  all=1
  shift
fi

program_packages=(
  build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libceres-dev libgoogle-glog-dev libnlopt-cxx-dev coinor-libipopt-dev
  libboost-program-options-dev nlohmann-json3-dev
  liburdfdom-dev  # URDF import/export
  libyaml-cpp-dev  # project files (kincal run PROJECT.yaml)
)
development_packages=(
  git liburdfdom-tools  # check_urdf in the tests
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-matplotlib
  # the Python module (python/, docs/python.md), its tests and its studies on Dask
  pybind11-dev python3-dev python3-numpy python3-pytest mypy python3-distributed
  python3-scipy  # the real-data benchmark's independent calibration (ctest real_data_benchmark_agrees)
  python3-yaml  # the camera example reads the exported camera_info back (example_camera_hand_eye_*)
  python3-opencv  # the camera's projection against OpenCV's (ctest camera_projection_matches_opencv)
  # kincal detect (vision/: targets found in images) and its tests; without them the program is
  # built without it (KINCAL_WITH_OPENCV=AUTO)
  libopencv-dev libopencv-contrib-dev
  chromium  # tests: the HTML report rendered headless (ctest html_report_renders_in_chromium)
)
# shellcheck source=scripts/install_packages.sh
source scripts/install_packages.sh
if ((all)); then
  install_missing setup "${program_packages[@]}" "${development_packages[@]}"
else
  install_missing setup "${program_packages[@]}"
fi

# What only kincal's developers build: off for the program alone, on with --all.
parts=(KINCAL_BUILD_TESTS KINCAL_BUILD_BENCHMARKS KINCAL_BUILD_EXAMPLES KINCAL_BUILD_PYTHON)
part_options=()
for part in "${parts[@]}"; do
  if ((all)); then
    part_options+=("-D$part=ON")
  elif [ ! -f build/CMakeCache.txt ]; then
    part_options+=("-D$part=OFF")
  fi
done

if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${part_options[@]}" "$@" >/dev/null
elif ((all)) || (($#)); then
  cmake -S . -B build "${part_options[@]}" "$@" >/dev/null
fi
# Every core, each compilation through ccache (CMakeLists.txt): a second clone or a rebuild
# after a branch switch recompiles only what changed.
if ((all)); then
  cmake --build build --parallel "$(nproc)"
else
  cmake --build build --parallel "$(nproc)" --target kincal-cli
fi
