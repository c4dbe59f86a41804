#!/usr/bin/env python3
"""Calibrate a UR5 from its URDF and laser-tracker data, validate it on held-out poses and
export the calibrated URDF (docs/calibrating-a-serial-arm.md walks through it); then the same
with project.yaml beside this script (kincal run), which must write the same files.

    run.py DATASET_DIR [--kincal PATH] [--out DIR] [--max-test-mean-mm 0.11]

DATASET_DIR holds the two CSV files of the UR5 folder of the public repository
pauljac7700/serial_robots_datasets (MIT licence; P. Jacobi's master's thesis "A Hybrid Error
Compensation Method for Enhancing the Pose Accuracy of Serial Industrial Robots"):
3D_UR5_uncalibrated_grid_cleaned.csv (1000 poses, calibration) and
3D_UR5_uncalibrated_random_cleaned.csv (20 poses, test). Their columns: x_t, y_t, z_t (the
commanded target, mm, robot base frame), x_dif, y_dif, z_dif (measured minus target, mm) and
joint_1 ... joint_6 (degrees).

Steps: import ur5.urdf (kincal model --urdf), convert the CSVs to kincal measurement files
(joint columns in radians named as the URDF's joints, readings tracker.x/y/z = x_t + x_dif),
calibrate on the grid with the default mask, calibrate a registration-only baseline (base
frame and measured point only), validate both on the test poses, export the URDF, and check
the exported URDF's world -> tcp chain with the independent forward kinematics below (plain
Python, no kincal code): it must reproduce kincal's predictions at every measured
configuration within 1e-6 mm. Last, `kincal run project.yaml --set data=OUT --set
out=OUT/project` (the grid and test files above as its data) must write the files of the
command sequence, the same (examples/project_check.py).

Exit codes: 0 done and the test-set mean within --max-test-mean-mm; 1 a check failed;
2 bad arguments; 77 the dataset folder is missing (reported as skipped by ctest).
"""

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))
import project_check  # noqa: E402

GRID = "3D_UR5_uncalibrated_grid_cleaned.csv"
TEST = "3D_UR5_uncalibrated_random_cleaned.csv"
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint"]


def read_dataset(path):
    """Rows of (joints in rad, measured position in mm, |x_dif| in mm)."""
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            q = [math.radians(float(r["joint_%d" % (i + 1)])) for i in range(6)]
            measured = [float(r[a + "_t"]) + float(r[a + "_dif"]) for a in "xyz"]
            dif = math.sqrt(sum(float(r[a + "_dif"]) ** 2 for a in "xyz"))
            rows.append((q, measured, dif))
    return rows


def write_measurements(rows, path):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(JOINTS + ["tracker.x", "tracker.y", "tracker.z"])
        for q, measured, _ in rows:
            w.writerow(["%.17g" % v for v in q + measured])


def run(cmd, allowed=(0,)):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode not in allowed:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit("run.py: '%s' failed with exit code %d" % (" ".join(cmd), p.returncode))
    return p


def residuals(kincal, model, report, data, out_json):
    """kincal's residuals (predicted - measured) per row, from `kincal validate`."""
    run([kincal, "validate", "--model", model, "--data", data, "--report", report,
         "--json", out_json], allowed=(0, 1))
    with open(out_json) as f:
        v = json.load(f)
    return [[row["tracker." + a] for a in "xyz"] for row in v["residuals"]]


# ---- forward kinematics of a URDF, independent of kincal ---------------------------------

def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(4)) for j in range(4)] for i in range(4)]


def rpy_xyz(xyz, rpy):
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = (math.cos(r), math.sin(r), math.cos(p), math.sin(p),
                              math.cos(y), math.sin(y))
    # R = Rz(y) Ry(p) Rx(r), URDF's fixed-axis roll-pitch-yaw.
    return [[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr, xyz[0]],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr, xyz[1]],
            [-sp, cp * sr, cp * cr, xyz[2]],
            [0, 0, 0, 1]]


def axis_angle(axis, angle):
    n = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / n for a in axis)
    c, s, t = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return [[t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0],
            [0, 0, 0, 1]]


def urdf_chain(path, root, tip):
    """The joints from `root` to `tip` as (name, type, origin matrix, axis)."""
    robot = ET.parse(path).getroot()
    by_child = {}
    for j in robot.findall("joint"):
        o = j.find("origin")
        xyz = [float(v) for v in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
        rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
        a = j.find("axis")
        axis = [float(v) for v in (a.get("xyz") if a is not None else "1 0 0").split()]
        by_child[j.find("child").get("link")] = (j.get("name"), j.get("type"), rpy_xyz(xyz, rpy),
                                                 axis, j.find("parent").get("link"))
    chain, link = [], tip
    while link != root:
        name, kind, origin, axis, parent = by_child[link]
        chain.append((name, kind, origin, axis))
        link = parent
    return list(reversed(chain))


def urdf_point(chain, joint_values):
    """Position of the chain's last frame (mm) for joint values by name (rad, m for prismatic)."""
    T = [[1 if i == j else 0 for j in range(4)] for i in range(4)]
    for name, kind, origin, axis in chain:
        T = matmul(T, origin)
        if kind in ("revolute", "continuous"):
            T = matmul(T, axis_angle(axis, joint_values[name]))
        elif kind == "prismatic":
            d = joint_values[name]
            n = math.sqrt(sum(a * a for a in axis))
            T = matmul(T, [[1, 0, 0, axis[0] / n * d], [0, 1, 0, axis[1] / n * d],
                           [0, 0, 1, axis[2] / n * d], [0, 0, 0, 1]])
    return [T[i][3] * 1000.0 for i in range(3)]


def distance(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def mean(values):
    return sum(values) / len(values)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", help="folder with the UR5 CSV files")
    ap.add_argument("--kincal", default=shutil.which("kincal") or "kincal")
    ap.add_argument("--out", default="ur5-out", help="folder for the files written (created)")
    ap.add_argument("--max-test-mean-mm", type=float, default=0.11)
    args = ap.parse_args()
    grid_csv, test_csv = (os.path.join(args.dataset, f) for f in (GRID, TEST))
    if not (os.path.isfile(grid_csv) and os.path.isfile(test_csv)):
        print("skipped: the UR5 dataset is not in %s (expected %s and %s; get them from GitHub "
              "pauljac7700/serial_robots_datasets, folder UR5)" % (args.dataset, GRID, TEST))
        return 77
    args.out = os.path.abspath(args.out)  # the paths the outputs record: the project's, too
    os.makedirs(args.out, exist_ok=True)
    k = args.kincal
    path = lambda name: os.path.join(args.out, name)

    grid, test = read_dataset(grid_csv), read_dataset(test_csv)
    write_measurements(grid, path("grid.csv"))
    write_measurements(test, path("test.csv"))

    run([k, "model", "--urdf", os.path.join(HERE, "ur5.urdf"), "--tip", "flange",
         "--sensor", "point-tracker", "--out", path("ur5.json")])
    calibration = run([k, "calibrate", "--model", path("ur5.json"), "--data", path("grid.csv"),
                       "--out", path("calibrated.json"), "--json", path("report.json")])
    # Registration only: where the robot stands and where the reflector is on the flange;
    # the joints keep their nominal geometry.
    run([k, "model", "--urdf", os.path.join(HERE, "ur5.urdf"), "--tip", "flange",
         "--sensor", "point-tracker", "--fix", "*", "--out", path("ur5-fixed.json")])
    run([k, "calibrate", "--model", path("ur5-fixed.json"), "--data", path("grid.csv"),
         "--free", "base.*", "--free", "tool.x", "--free", "tool.y", "--free", "tool.z",
         "--out", path("registration.json"), "--json", path("registration-report.json")])
    run([k, "export", "--model", path("calibrated.json"), "--format", "urdf",
         "--out", path("ur5-calibrated.urdf")])

    failures = []
    summary = {}
    for label, model, report in (("calibrated", "calibrated.json", "report.json"),
                                 ("registration only", "registration.json",
                                  "registration-report.json")):
        for data_name, rows in (("grid", grid), ("test", test)):
            predicted = residuals(k, path(model), path(report), path(data_name + ".csv"),
                                    path("validate-%s-%s.json" % (model[:-5], data_name)))
            measured = [r[1] for r in rows]
            predicted = [[m + r for m, r in zip(mm, rr)] for mm, rr in zip(measured, predicted)]
            errors = [distance(p, m) for p, m in zip(predicted, measured)]
            summary[(label, data_name)] = (predicted, errors)

    before = [r[2] for r in test]
    _, after = summary[("calibrated", "test")]
    _, registration = summary[("registration only", "test")]
    print("UR5, %d calibration poses (grid), %d test poses (random)" % (len(grid), len(test)))
    print("test-set 3-D position error, mm:      mean      max")
    print("  nominal (the data's x_dif)        %7.4f  %7.4f" % (mean(before), max(before)))
    print("  registration only (base + point)  %7.4f  %7.4f" % (mean(registration),
                                                               max(registration)))
    print("  calibrated (default mask)         %7.4f  %7.4f" % (mean(after), max(after)))
    _, grid_after = summary[("calibrated", "grid")]
    print("calibration-set mean after: %.4f mm" % mean(grid_after))

    # The exported URDF, read by the independent forward kinematics above.
    chain = urdf_chain(path("ur5-calibrated.urdf"), "world", "tcp")
    worst = 0.0
    urdf_test_errors = []
    for data_name, rows in (("grid", grid), ("test", test)):
        predicted, _ = summary[("calibrated", data_name)]
        for (q, measured, _), p in zip(rows, predicted):
            point = urdf_point(chain, dict(zip(JOINTS, q)))
            worst = max(worst, distance(point, p))
            if data_name == "test":
                urdf_test_errors.append(distance(point, measured))
    print("exported URDF (world -> tcp, independent FK): test mean %.4f mm; largest difference "
          "from kincal's predictions over all %d configurations %.3g mm"
          % (mean(urdf_test_errors), len(grid) + len(test), worst))
    if worst > 1e-6:
        failures.append("the exported URDF differs from the calibrated model by %.3g mm" % worst)
    if abs(mean(urdf_test_errors) - mean(after)) > 0.005:
        failures.append("the exported URDF's test-set mean differs from kincal's")
    if not mean(after) <= args.max_test_mean_mm:
        failures.append("test-set mean %.4f mm above %.3f mm" % (mean(after),
                                                                   args.max_test_mean_mm))
    # The same calibration as one project file.
    project_out = path("project")
    failures += project_check.check(
        k, os.path.join(HERE, "project.yaml"), {"data": args.out, "out": project_out}, args.out,
        project_out, ["ur5.json", "calibrated.json", "report.json", "ur5-fixed.json",
                      "registration.json", "registration-report.json", "ur5-calibrated.urdf",
                      "validate-calibrated-test.json", "validate-registration-test.json"],
        [(project_out + "/", args.out + "/")])
    checker = shutil.which("check_urdf")
    if checker:
        run([checker, path("ur5-calibrated.urdf")])
        print("check_urdf accepts %s" % path("ur5-calibrated.urdf"))
    else:
        failures.append("check_urdf is not installed (apt-get install liburdfdom-tools)")
    for f in failures:
        print("FAILED: " + f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
