#!/usr/bin/env bash
# The installed kincal package, used as a project outside the tree would use it
# (cmake/KincalInstallTest.cmake registers the three steps as ctest tests).
#   installed_package.sh install|cmake|pkg-config|workflow|plugin WORK_DIR SOURCE_DIR BUILD_DIR
# Environment (set by the test): CMAKE_COMMAND, CXX, CMAKE_GENERATOR, KINCAL_LAUNCHER
# (the build's compiler launcher, e.g. ccache; may be empty), KINCAL_BUILD_TYPE.
set -euo pipefail
step=$1 work=$2 source=$3 build=$4
prefix=$work/prefix
cmake_cmd=${CMAKE_COMMAND:-cmake}

fail() {
  echo "installed_package $step: $*" >&2
  exit 1
}

case $step in
  install)
    # A fresh prefix each time, so that nothing left from an earlier install can hide a
    # missing file. (cmake --install keeps the files' times: the example is not rebuilt.)
    rm -rf "$prefix"
    mkdir -p "$work"
    "$cmake_cmd" --install "$build" --prefix "$prefix" >"$work/install.log"
    for f in include/kincal/version.hpp include/kincal/framework/least_squares/solver_registry.hpp \
      include/kincal/framework/extension/plugin.hpp include/kincal/models/conformance.hpp \
      lib*/cmake/kincal/KincalPlugin.cmake \
      include/kincal/cli/run.hpp lib*/cmake/kincal/kincalConfig.cmake \
      lib*/cmake/kincal/kincalConfigVersion.cmake lib*/pkgconfig/kincal.pc bin/kincal; do
      compgen -G "$prefix/$f" >/dev/null || fail "not installed: $f"
    done
    # The CLI's internals (which include Boost) are not public.
    [ ! -e "$prefix/include/kincal/cli/cli_util.hpp" ] || fail "cli/cli_util.hpp installed"
    "$prefix/bin/kincal" list solvers >/dev/null || fail "the installed kincal does not run"
    # The Python module, when this build has it (KINCAL_BUILD_PYTHON): installed and importable
    # from the prefix alone, not from the build tree.
    if compgen -G "$build/python/kincal/_kincal*.so" >/dev/null; then
      site=$prefix/lib/python3/dist-packages
      compgen -G "$site/kincal/_kincal*.so" >/dev/null || fail "not installed: the Python module"
      (cd "$work" && PYTHONPATH=$site /usr/bin/python3 -c \
        "import kincal, sys; assert kincal.__file__.startswith(sys.argv[1]); kincal.Model.preset('ur5')" \
        "$site") || fail "the installed Python module does not import"
    fi
    ;;

  cmake)
    example=$work/cmake-example
    args=(-S "$source/examples/custom_model" -B "$example" -G "$CMAKE_GENERATOR"
      -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE="${KINCAL_BUILD_TYPE:-Release}"
      -DCMAKE_PREFIX_PATH="$prefix")
    if [ -n "${KINCAL_LAUNCHER:-}" ]; then args+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$KINCAL_LAUNCHER"); fi
    "$cmake_cmd" "${args[@]}" >"$work/cmake-configure.log" ||
      { cat "$work/cmake-configure.log"; fail "configure failed"; }
    grep -q "^kincal_DIR:PATH=$prefix/" "$example/CMakeCache.txt" ||
      fail "find_package(kincal) did not find the scratch prefix: $(grep kincal_DIR "$example/CMakeCache.txt")"
    "$cmake_cmd" --build "$example" >"$work/cmake-build.log" ||
      { cat "$work/cmake-build.log"; fail "build failed"; }

    "$example/fit_circle"
    "$example/calibrate_custom_model" | tail -n 4

    # The example's own kincal program calibrates its own mechanism from files: a model
    # file, noise-free simulated measurements (and the true model beside them), a
    # calibration, which must find the true model.
    run=$work/cli-run
    rm -rf "$run" && mkdir -p "$run" && cd "$run"
    arm=$example/kincal-arm
    "$arm" list mechanisms >mechanisms.txt  # through a file: see the plug-in case below
    grep -q two-link-arm mechanisms.txt || fail "kincal-arm does not list two-link-arm"
    "$arm" model --preset two-link-demo --out arm.json
    "$arm" simulate --model arm.json --poses 30 --noise-half-width 0 --seed 11 --write-data data.csv
    "$arm" calibrate --model arm.json --data data.csv --out calibrated.json --json report.json
    python3 - calibrated.json data.truth.json <<'PY'
import json, sys
def numbers(node, path=""):
    if isinstance(node, dict):
        for k, v in node.items():
            yield from numbers(v, f"{path}.{k}")
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from numbers(v, f"{path}[{i}]")
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        yield path, float(node)
calibrated = dict(numbers(json.load(open(sys.argv[1]))))
truth = dict(numbers(json.load(open(sys.argv[2]))))
assert calibrated.keys() == truth.keys(), (calibrated.keys() ^ truth.keys())
worst = max(abs(calibrated[k] - truth[k]) for k in truth)
print(f"calibrated model vs. true model: {len(truth)} numbers, largest difference {worst:.1e}")
sys.exit(0 if worst < 1e-6 else 1)
PY
    ;;

  pkg-config | workflow)
    # The complete examples of docs/library.md: the ```cpp block after the line
    # <!-- compiled by the test installed_package_pkg_config_example --> (the steps one by
    # one), or installed_package_workflow_example (the calibrate workflow), compiled with
    # pkg-config's flags only and run.
    name=$([ "$step" = workflow ] && echo workflow || echo pkg_config)
    example=$work/$name-example
    mkdir -p "$example"
    awk -v marker="<!-- compiled by the test installed_package_${name}_example -->" \
        '$0 == marker {found = 1; next}
         found == 1 && /^```cpp/ {found = 2; next}
         found == 2 && /^```/ {exit}
         found == 2 {print}' "$source/docs/library.md" >"$example/tour.cpp"
    [ -s "$example/tour.cpp" ] || fail "no example for installed_package_${name}_example in docs/library.md"
    pc_dir=$(dirname "$(compgen -G "$prefix/lib*/pkgconfig/kincal.pc" | head -n 1)")
    flags=$(PKG_CONFIG_PATH=$pc_dir pkg-config --cflags --libs kincal) ||
      fail "pkg-config --cflags --libs kincal failed"
    echo "pkg-config --cflags --libs kincal: $flags"
    launcher=()
    if [ -n "${KINCAL_LAUNCHER:-}" ]; then launcher=("$KINCAL_LAUNCHER"); fi
    # shellcheck disable=SC2086  # the flags are words
    "${launcher[@]}" "$CXX" -std=c++17 -O2 "$example/tour.cpp" -o "$example/tour" $flags
    cd "$example" && ./tour
    if [ "$step" = workflow ]; then
      # The calibration report's page, rendered by the library from the typed result.
      grep -q "</html>" report.html || fail "the workflow example wrote no report page"
      grep -q "<h2>Verdicts</h2>" report.html || fail "the report page has no verdicts"
    fi
    ;;

  plugin)
    # examples/plugin/ built with find_package(kincal) + kincal_add_plugin, and used by the
    # installed, stock kincal: the done-when of a plug-in.
    example=$work/plugin-example
    args=(-S "$source/examples/plugin" -B "$example" -G "$CMAKE_GENERATOR"
      -DCMAKE_CXX_COMPILER="$CXX" -DCMAKE_BUILD_TYPE="${KINCAL_BUILD_TYPE:-Release}"
      -DCMAKE_PREFIX_PATH="$prefix")
    if [ -n "${KINCAL_LAUNCHER:-}" ]; then args+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$KINCAL_LAUNCHER"); fi
    "$cmake_cmd" "${args[@]}" >"$work/plugin-configure.log" ||
      { cat "$work/plugin-configure.log"; fail "configure failed"; }
    "$cmake_cmd" --build "$example" >"$work/plugin-build.log" ||
      { cat "$work/plugin-build.log"; fail "build failed"; }
    plugin=$example/libkincal_five_bar.so
    [ -f "$plugin" ] || fail "no $plugin"
    kincal=$prefix/bin/kincal
    run=$work/plugin-run
    rm -rf "$run" && mkdir -p "$run" && cd "$run"
    # Through a file: grep -q stops reading at the match, and a list longer than one stdio
    # buffer then fails its next write (exit 2, which pipefail reports as no match).
    "$kincal" list --plugin "$plugin" >list.txt
    grep -q '^five-bar ' list.txt || fail "list shows no five-bar"
    "$kincal" simulate --plugin "$plugin" --preset five-bar-demo --noise-half-width 0 --json sim.json >/dev/null
    python3 -c 'import json, sys; r = json.load(open("sim.json")); e = max(r["parameter_rms_error_mm"], r["parameter_rms_error_rad"]); print(f"five-bar-demo, no noise: parameter RMS error {e:.1e}"); sys.exit(0 if e < 1e-6 else 1)' ||
      fail "simulate --noise-half-width 0 did not recover the truth"
    export KINCAL_PLUGIN_PATH=$plugin  # the other way to name it
    "$kincal" model --preset five-bar-demo --out five-bar.json
    "$kincal" simulate --model five-bar.json --noise-half-width 0 --seed 2 --write-data data.csv >/dev/null
    "$kincal" calibrate --model five-bar.json --data data.csv --out calibrated.json >/dev/null
    "$kincal" observability --model five-bar.json --data data.csv >/dev/null
    "$kincal" design --model five-bar.json --poses 12 --candidates 60 --noise-std 0.01mm \
      --out design.csv >/dev/null
    "$kincal" export --model calibrated.json --format json >exported.json
    grep -q '"mechanism": "five-bar"' exported.json || fail "export --format json"
    "$kincal" check | tail -n 1
    ;;

  *)
    fail "unknown step (expected install, cmake, pkg-config or plugin)"
    ;;
esac
