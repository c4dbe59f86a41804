#!/usr/bin/env python3
"""Joint compliance on the real UR5: does a deflection under gravity improve the held-out
error over the geometric calibration? (docs/calibrating-a-serial-arm.md, "Joint compliance")

    compliance.py DATASET_DIR [--kincal PATH] [--out DIR] [--folds 5]

DATASET_DIR holds the UR5 laser-tracker CSV files (see run.py: GitHub
pauljac7700/serial_robots_datasets, folder UR5, MIT licence; P. Jacobi's master's thesis).
With the user-facing commands only (kincal model --urdf [--compliance], calibrate, validate,
compensate), for three models of the same arm:
  geometric     the URDF import, no compliance (run.py's calibration)
  urdf masses   --compliance urdf: the URDF's inertials (UR's published masses and centres of
                mass), one compliance per joint
  fitted        --compliance fitted: no masses, a moment per pair of joints
it prints
  - the held-out 3-D error on the 20 random test poses (calibrated on the 1000 grid poses);
  - a 5-fold cross-validation on the grid (folds of consecutive rows: neighbouring grid
    points in one fold, so that a fold's poses are not interpolated from their neighbours);
  - corrected targets: `kincal compensate` on the test poses' commanded targets, and the
    calibrated model's prediction of the uncompensated error against the measured one.
Exit codes: 0 done; 1 a check failed (a compensated command off its target by more than
1e-6 mm, or a model's prediction of the measured error off by more than 0.5 mm); 2 bad
arguments; 77 the dataset is absent.
"""

import argparse
import csv
import json
import math
import os
import shutil
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run import (GRID, HERE, JOINTS, TEST, mean, read_dataset, run,  # noqa: E402
                 write_measurements)

MODELS = [("geometric", []), ("urdf masses", ["--compliance", "urdf"]),
          ("fitted", ["--compliance", "fitted"])]


def held_out(k, model, calibrate_on, test_on, out_json):
    """Calibrates `model` on one file, validates on another: the 3-D errors there."""
    calibrated = out_json.replace(".json", "-model.json")
    run([k, "calibrate", "--model", model, "--data", calibrate_on, "--out", calibrated,
         "--json", out_json], allowed=(0, 1))
    run([k, "validate", "--model", calibrated, "--data", test_on, "--json",
         out_json.replace(".json", "-validate.json")], allowed=(0, 1))
    with open(out_json.replace(".json", "-validate.json")) as f:
        v = json.load(f)
    with open(out_json) as f:
        report = json.load(f)
    errors = [math.sqrt(sum(row["tracker." + a] ** 2 for a in "xyz")) for row in v["residuals"]]
    return errors, report, calibrated


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", help="folder with the UR5 CSV files")
    ap.add_argument("--kincal", default=shutil.which("kincal") or "kincal")
    ap.add_argument("--out", default="ur5-compliance-out", help="folder for the files written")
    ap.add_argument("--folds", type=int, default=5)
    args = ap.parse_args()
    grid_csv, test_csv = (os.path.join(args.dataset, f) for f in (GRID, TEST))
    if not (os.path.isfile(grid_csv) and os.path.isfile(test_csv)):
        print("skipped: the UR5 dataset is not in %s" % args.dataset)
        return 77
    if args.folds < 2:
        ap.error("--folds must be at least 2")
    os.makedirs(args.out, exist_ok=True)
    k = args.kincal
    path = lambda name: os.path.join(args.out, name)
    grid, test = read_dataset(grid_csv), read_dataset(test_csv)
    write_measurements(grid, path("grid.csv"))
    write_measurements(test, path("test.csv"))
    models = {}
    for label, options in MODELS:
        name = path("ur5-%s.json" % label.replace(" ", "-"))
        run([k, "model", "--urdf", os.path.join(HERE, "ur5.urdf"), "--tip", "flange",
             "--out", name] + options)
        models[label] = name

    failures = []
    print("UR5, held-out 3-D position error, mm (calibrated on the 1000 grid poses)")
    print("  %-12s %9s %9s %9s %16s" % ("model", "test mean", "test max", "grid mean",
                                        "free parameters"))
    calibrated = {}
    for label, _ in MODELS:
        errors, report, calibrated[label] = held_out(
            k, models[label], path("grid.csv"), path("test.csv"),
            path("test-%s.json" % label.replace(" ", "-")))
        free = len([p for p in report["parameters"]])
        grid_mean = report["position_error_mm"]["after"]["mean"]
        print("  %-12s %9.4f %9.4f %9.4f %16d" % (label, mean(errors), max(errors), grid_mean,
                                                  free))

    # Cross-validation on the grid: folds of consecutive rows.
    n = len(grid)
    bounds = [round(i * n / args.folds) for i in range(args.folds + 1)]
    print("%d-fold cross-validation on the grid (consecutive rows), mean 3-D error, mm"
          % args.folds)
    print("  %-12s %s %9s" % ("model", " ".join("%8s" % ("fold %d" % (f + 1))
                                                   for f in range(args.folds)), "all"))
    for label, _ in MODELS:
        fold_means, all_errors = [], []
        for f in range(args.folds):
            held = grid[bounds[f]:bounds[f + 1]]
            kept = grid[:bounds[f]] + grid[bounds[f + 1]:]
            write_measurements(kept, path("fold-train.csv"))
            write_measurements(held, path("fold-test.csv"))
            errors, _, _ = held_out(k, models[label], path("fold-train.csv"),
                                    path("fold-test.csv"),
                                    path("fold-%d-%s.json" % (f, label.replace(" ", "-"))))
            fold_means.append(mean(errors))
            all_errors += errors
        print("  %-12s %s %9.4f" % (label, " ".join("%8.4f" % m for m in fold_means),
                                    mean(all_errors)))

    # Corrected targets: the test poses' commanded targets x_t, with the commands as starts.
    with open(test_csv, newline="") as f:
        raw = list(csv.DictReader(f))
    with open(path("targets.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([j + "_deg" for j in JOINTS] + ["tracker.x", "tracker.y", "tracker.z"])
        for r in raw:
            w.writerow([r["joint_%d" % (i + 1)] for i in range(6)] + [r[a + "_t"] for a in "xyz"])
    measured_error = [math.sqrt(sum(float(r[a + "_dif"]) ** 2 for a in "xyz")) for r in raw]
    print("corrected targets on the 20 test poses (kincal compensate)")
    print("  %-12s %14s %16s %14s %12s" % ("model", "measured error", "predicted error",
                                            "|difference|", "compensated"))
    for label, _ in MODELS:
        out = path("compensated-%s.csv" % label.replace(" ", "-"))
        summary = path("compensated-%s.json" % label.replace(" ", "-"))
        run([k, "compensate", "--model", calibrated[label], "--targets", path("targets.csv"),
             "--out", out, "--json", summary])
        with open(out, newline="") as f:
            rows = list(csv.DictReader(f))
        predicted = [[float(r["predicted.tracker." + a]) - float(r["wanted.tracker." + a])
                      for a in "xyz"] for r in rows]
        # What the calibrated model says the original commands miss by, row by row, against
        # what the tracker measured (x_dif).
        with open(summary) as f:
            s = json.load(f)
        starts = run([k, "fk", "--model", calibrated[label], "--data", path("test.csv"),
                      "--out", "-"]).stdout
        fk_rows = list(csv.DictReader(starts.splitlines()))
        diffs = []
        for fk, r in zip(fk_rows, raw):
            p = [float(fk["tracker." + a]) - float(r[a + "_t"]) for a in "xyz"]
            m = [float(r[a + "_dif"]) for a in "xyz"]
            diffs.append(math.sqrt(sum((x - y) ** 2 for x, y in zip(p, m))))
        reached = max(math.sqrt(sum(v * v for v in d)) for d in predicted)
        print("  %-12s %14.4f %16.4f %14.4f %12.2g" % (label, mean(measured_error),
                                                       s["mean_error_at_start"], mean(diffs),
                                                       reached))
        if reached > 1e-6:
            failures.append("%s: a compensated command misses its target by %.3g mm"
                            % (label, reached))
        if max(diffs) > 0.5:
            failures.append("%s: the predicted uncompensated error is %.3g mm off the measured "
                            "one" % (label, max(diffs)))
    print("  (measured: the tracker's x_dif at the original commands; predicted: the calibrated "
          "model's; |difference|: per pose, mean; compensated: the largest distance left in the "
          "model, mm)")
    for f in failures:
        print("FAILED: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
