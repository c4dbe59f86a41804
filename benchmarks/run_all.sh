#!/usr/bin/env bash
# Builds kincal in Release, runs the accuracy study, the micro-benchmarks and the solver test
# suite (Moré-Garbow-Hillstrom), draws the plots into docs/generated/img/ and refreshes the
# generated tables of docs/benchmarks.md and docs/generated/benchmark-results/.
#
#   benchmarks/run_all.sh [--trials N] [--repetitions N] [--build DIR] [--no-docs]
#
# Extra CMake arguments (e.g. -DKINCAL_WITH_IPOPT=OFF) go in the CMAKE_ARGS variable.
# Takes about 10 minutes on 2 cores with every backend built.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build="$root/build-bench"
trials=200
repetitions=5
update_docs=1
while [ $# -gt 0 ]; do
  case "$1" in
    --trials) trials=$2; shift 2 ;;
    --repetitions) repetitions=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    --no-docs) update_docs=0; shift ;;
    -h|--help) sed -n '2,9p' "$0"; exit 0 ;;
    *) echo "run_all.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
results="$build/benchmark-results"
# Debian's python3-matplotlib lives under /usr/bin/python3, which a pyenv or venv shim in PATH
# would hide.
python=python3
if ! python3 -c 'import matplotlib' 2>/dev/null && [ -x /usr/bin/python3 ]; then
  python=/usr/bin/python3
fi

generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
# shellcheck disable=SC2086 # CMAKE_ARGS is a list of words on purpose
cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
  -DKINCAL_BUILD_BENCHMARKS=ON ${CMAKE_ARGS:-}
cmake --build "$build" --target accuracy_study micro_benchmarks solver_suite_benchmark -j "$(nproc)"
mkdir -p "$results"

{
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- commit: $(git -C "$root" rev-parse --short HEAD)$(git -C "$root" diff --quiet HEAD -- framework models solvers benchmarks || echo ' (with local changes)')"
  echo "- machine: $(nproc) hardware threads, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
  echo "- compiler: $(${CXX:-c++} --version | head -1), CMake build type Release"
  echo "- command: \`benchmarks/run_all.sh --trials $trials --repetitions $repetitions\`"
} > "$results/machine.md"

"$build/benchmarks/kincal-accuracy-study" --trials "$trials" --out "$results"
"$build/benchmarks/kincal-micro-benchmarks" --benchmark_repetitions="$repetitions" \
  --benchmark_report_aggregates_only=true --benchmark_out="$results/micro.json" \
  --benchmark_out_format=json
"$build/benchmarks/kincal-solver-suite-benchmark" --out "$results/solver-suite"
"$python" "$root/benchmarks/plot_results.py" "$results" "$root/docs/generated/img"
"$python" "$root/benchmarks/plot_solver_suite.py" "$results/solver-suite" "$root/docs/generated/img"

if [ "$update_docs" = 1 ]; then
  mkdir -p "$root/docs/generated/benchmark-results"
  cp "$results"/{accuracy.md,micro.md,machine.md,summary.csv,summary.json,bounds.csv,traces.csv,micro.json} \
    "$root/docs/generated/benchmark-results/"
  mkdir -p "$root/docs/generated/benchmark-results/solver-suite"
  cp "$results"/solver-suite/{suite_table.md,suite.csv,dimension.csv} \
    "$root/docs/generated/benchmark-results/solver-suite/"
  "$python" "$root/benchmarks/update_docs.py" "$root/docs/benchmarks.md" "$results"
fi
echo "results in $results; plots in $root/docs/generated/img"
