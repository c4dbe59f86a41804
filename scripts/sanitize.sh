#!/usr/bin/env bash
# The sanitizer suite and the fuzzers (docs/reliability.md). Installs what they need on
# Debian 12 (clang 14 and its runtime libraries; gcc's come with build-essential), then:
#   clang  build-asan-clang/: clang++-14 with KINCAL_SANITIZE=address,undefined minus
#          UBSan's pointer checks (NO_SANITIZE, default null,alignment,object-size,
#          pointer-overflow: they make Eigen's kernels about 50 times slower, and
#          AddressSanitizer catches what they would) and the libFuzzer targets; the whole
#          ctest suite, each fuzzer's seed corpus included;
#   gcc    build-asan-gcc/: g++ with address,undefined, every check; the whole ctest suite;
#   fuzz   each fuzzer for FUZZ_SECONDS seconds (default 60) from its seed corpus, with the
#          clang build (stage clang builds it if needed), from libFuzzer's random seed
#          FUZZ_SEED (default 1, so that CI repeats a run checked before landing; 0 draws
#          one, to explore: docs/reliability.md). New inputs go to a scratch corpus;
#          a crash leaves its input under build-asan-clang/fuzz-findings/;
#   thread build-tsan/: clang++-14 with KINCAL_SANITIZE=thread; the whole ctest suite (not
#          in the default stages: another full build).
# Usage: scripts/sanitize.sh [clang] [gcc] [fuzz] [thread]   (no argument: clang gcc fuzz)
# Every stage prints its wall time. Extra CMake arguments: SANITIZE_CMAKE_ARGS.
set -euo pipefail
cd "$(dirname "$0")/.."

stages=("$@")
if ((${#stages[@]} == 0)); then stages=(clang gcc fuzz); fi

packages=(clang-14 libclang-rt-14-dev llvm-14)
# shellcheck source=scripts/install_packages.sh
source scripts/install_packages.sh
install_missing sanitize "${packages[@]}"

jobs=$(nproc)
# Every report stops the program; symbolized stacks (llvm-symbolizer from llvm-14).
export ASAN_OPTIONS="abort_on_error=1:detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export ASAN_SYMBOLIZER_PATH=/usr/bin/llvm-symbolizer-14
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1"

# -O2 -g1 and no NDEBUG: line numbers in reports, and Eigen's and our assertions on. -O2,
# not -O1: Eigen's fixed-size kernels left as calls cost the suite its time (the UR5
# calibrate took 8.6 s at -O1 and 3.1 s at -O2, docs/reliability.md). Without the Python module: a sanitized extension module needs the
# sanitizer runtimes preloaded into python3 (docs/reliability.md).
configure() {  # dir, compiler, extra args...
  local dir=$1 compiler=$2
  shift 2
  if [ ! -f "$dir/CMakeCache.txt" ]; then
    cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER="$compiler" \
      -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1" \
      -DKINCAL_SANITIZE="${SANITIZERS:-address,undefined}" -DKINCAL_BUILD_BENCHMARKS=OFF \
      -DKINCAL_BUILD_EXAMPLES=OFF -DKINCAL_BUILD_PYTHON=OFF "$@" ${SANITIZE_CMAKE_ARGS:-} >/dev/null
  fi
}

timed() {  # label, command...
  local label=$1 start=$SECONDS
  shift
  echo "== $label" >&2
  "$@"
  echo "== $label: $((SECONDS - start)) s" >&2
}

build_clang() {
  configure build-asan-clang clang++-14 -DKINCAL_BUILD_FUZZERS=ON \
    -DKINCAL_NO_SANITIZE="${NO_SANITIZE-null,alignment,object-size,pointer-overflow}"
  cmake --build build-asan-clang --parallel "$jobs"
}

build_gcc() {
  configure build-asan-gcc g++
  cmake --build build-asan-gcc --parallel "$jobs"
}

build_thread() {
  SANITIZERS=thread configure build-tsan clang++-14
  cmake --build build-tsan --parallel "$jobs"
}

# Fuzzes fuzz_<target> for `seconds` from its seed corpus; new inputs go to a scratch
# corpus. Prints libFuzzer's first and last status lines and its final statistics.
fuzz() {  # target, seconds
  local target=$1 seconds=$2 findings=$PWD/build-asan-clang/fuzz-findings
  local log=build-asan-clang/fuzz-logs/$target.log scratch status=0
  mkdir -p "$findings" build-asan-clang/fuzz-logs
  scratch=$(mktemp -d)
  local dict=()
  if [ -f "fuzz/$target.dict" ]; then dict=(-dict="$PWD/fuzz/$target.dict"); fi
  # Absolute paths: fuzz_cli_options works in a directory of its own.
  "$PWD/build-asan-clang/fuzz/fuzz_$target" "$scratch" "$PWD/fuzz/corpus/$target" \
    -seed="${FUZZ_SEED:-1}" -max_total_time="$seconds" -max_len=4096 -timeout=10 -rss_limit_mb=4096 \
    -artifact_prefix="$findings/$target-" -print_final_stats=1 "${dict[@]}" >"$log" 2>&1 ||
    status=$?
  rm -rf "$scratch"
  grep -E "^#[0-9]+[[:space:]]+(INITED|DONE)|^stat::(number_of_executed_units|average_exec_per_sec|new_units_added|peak_rss_mb)" "$log" >&2 || true
  if ((status != 0)); then
    tail -n 60 "$log" >&2
    echo "sanitize: fuzz_$target failed (exit $status); input under $findings/" >&2
    return 1
  fi
}

for stage in "${stages[@]}"; do
  case $stage in
    clang)
      timed "clang sanitizer build" build_clang
      timed "clang sanitizer tests" ctest --test-dir build-asan-clang --output-on-failure -j"$jobs"
      ;;
    gcc)
      timed "gcc sanitizer build" build_gcc
      timed "gcc sanitizer tests" ctest --test-dir build-asan-gcc --output-on-failure -j"$jobs"
      ;;
    fuzz)
      [ -x build-asan-clang/fuzz/fuzz_cli_options ] || timed "clang sanitizer build" build_clang
      targets=(measurement_file model_file project_file cli_options command_inputs urdf_file)
      # kincal detect's inputs, when OpenCV was there to build it (KINCAL_WITH_OPENCV=AUTO)
      if [ -x build-asan-clang/fuzz/fuzz_detect_inputs ]; then targets+=(detect_inputs); fi
      for target in "${targets[@]}"; do
        timed "fuzz $target (${FUZZ_SECONDS:-60} s)" fuzz "$target" "${FUZZ_SECONDS:-60}"
      done
      ;;
    thread)
      timed "thread sanitizer build" build_thread
      timed "thread sanitizer tests" ctest --test-dir build-tsan --output-on-failure -j"$jobs"
      ;;
    *)
      echo "sanitize: unknown stage '$stage' (expected clang, gcc, fuzz or thread)" >&2
      exit 2
      ;;
  esac
done
