#!/usr/bin/env python3
"""Calibrate a camera's intrinsics and both hand-eye mounts from raw images and the robot's
reported flange poses, and check the result against OpenCV's own solution of the same
detections (docs/calibrating-with-a-camera.md walks through it).

    run.py DATASET_DIR [--set 10x10|charuco] [--kincal PATH] [--out DIR]

DATASET_DIR holds the example data of ROS-Industrial's industrial_calibration (Apache-2.0;
github.com/ros-industrial/industrial_calibration, folder examples/data): test_set_10x10/ (a
640 x 480 camera, a 10 x 10 modified circle grid, 25.4 mm) and test_set_charuco/ (a 1600 x 1200
camera, a 7 x 5 ChArUco board, 36.195 mm squares), each with cal_data.yaml (image/pose pairs)
and poses/N.yaml (the flange's pose in the robot's base: x, y, z in m, a quaternion). In the
10 x 10 set the camera is on the robot and the grid fixed (eye-in-hand; its cal_data.yaml says
static_camera: false); in the ChArUco set a static camera sees a board on the robot
(eye-to-hand).

Steps: the poses to a CSV (flange.x_m, ..., the quaternion as a rotation vector), `kincal
detect` (the target's points per image and a starting model: OpenCV's intrinsics, or the
set's given ones, and the closed-form hand-eye mounts), `kincal calibrate` (intrinsics with
distortion and both mounts from the pixels), then two checks with code nobody here wrote:
  1. an independent maximum-likelihood fit of the same model to the same detections: scipy's
     least_squares on OpenCV's projectPoints; it must agree with kincal to a small fraction of
     kincal's reported standard deviations;
  2. OpenCV's two-step solution (calibrateCamera, then calibrateHandEye, Tsai-Lenz): a
     different estimator, compared in units of kincal's standard deviations and printed;
and the leave-one-image-out reprojection error (each image predicted by a calibration of the
others).

Exit codes: 0 done and check 1 passed; 1 a check failed; 2 bad arguments; 77 the dataset
folder (or numpy, scipy, cv2) is missing (reported as skipped by ctest).
"""

import argparse
import csv
import json
import math
import os
import shutil
import subprocess
import sys

SETS = {
    # The camera on the robot, the grid on the table (cal_data.yaml: static_camera: false).
    "10x10": {"folder": "test_set_10x10", "target": "modified-circle-grid:10x10:25.4mm",
              "mounting": "eye-in-hand", "intrinsics": None, "gate": "1px"},
    # A static camera, the board on the robot (static_camera: true); calibrated intrinsics.
    "charuco": {"folder": "test_set_charuco",
                "target": "charuco:7x5:36.195mm:18.256mm:DICT_6X6_250",
                "mounting": "eye-to-hand", "gate": "2px",
                "intrinsics": "1352.02747,1356.14287,789.67065,627.2995"},
}


def run(cmd, allowed=(0,)):
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if p.returncode not in allowed:
        sys.stderr.write(p.stdout + p.stderr)
        raise SystemExit("run.py: '%s' failed with exit code %d" % (" ".join(cmd), p.returncode))
    return p


def read_pairs(cal_data):
    """(image, pose file) pairs of cal_data.yaml's `data` list (its simple YAML subset)."""
    pairs, item, in_data = [], {}, False
    with open(cal_data) as f:
        for line in f:
            text = line.split("#", 1)[0].rstrip()
            if not text:
                continue
            if not text.startswith(" ") and not text.startswith("-"):
                in_data = text.startswith("data:")
                continue
            if not in_data:
                continue
            stripped = text.strip()
            if stripped.startswith("- "):
                if item:
                    pairs.append(item)
                item = {}
                stripped = stripped[2:]
            key, value = (s.strip() for s in stripped.split(":", 1))
            item[key] = value
    if item:
        pairs.append(item)
    return [(p["image"], p["pose"]) for p in pairs]


def read_pose(path):
    values = {}
    with open(path) as f:
        for line in f:
            if ":" in line:
                key, value = line.split(":", 1)
                values[key.strip()] = float(value)
    return values


def rotation_vector(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    qx, qy, qz, qw = qx / n, qy / n, qz / n, qw / n
    if qw < 0:
        qx, qy, qz, qw = -qx, -qy, -qz, -qw
    s = math.sqrt(qx * qx + qy * qy + qz * qz)
    if s < 1e-15:
        return [0.0, 0.0, 0.0]
    angle = 2 * math.atan2(s, qw)
    return [qx / s * angle, qy / s * angle, qz / s * angle]


def write_poses(set_dir, path):
    pairs = read_pairs(os.path.join(set_dir, "cal_data.yaml"))
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["image", "flange.x_m", "flange.y_m", "flange.z_m", "flange.rotvec_x",
                    "flange.rotvec_y", "flange.rotvec_z"])
        for image, pose in pairs:
            p = read_pose(os.path.join(set_dir, pose))
            w.writerow([image] + ["%.17g" % v for v in [p["x"], p["y"], p["z"]] +
                                  rotation_vector(p["qx"], p["qy"], p["qz"], p["qw"])])
    return len(pairs)


def check_camera_info(path, report):
    """The exported camera_info, read by a YAML parser, holds the report's estimates."""
    import yaml
    with open(path) as f:
        info = yaml.safe_load(f)
    p = {q["name"]: q["estimate"] for q in report["parameters"]}
    k = info["camera_matrix"]["data"]
    d = info["distortion_coefficients"]["data"]
    expected = [(k[0], "fx"), (k[4], "fy"), (k[2], "cx"), (k[5], "cy"), (d[0], "k1"),
                (d[1], "k2"), (d[2], "p1"), (d[3], "p2")]
    wrong = [name for value, name in expected if abs(value - p["camera." + name]) >
             1e-12 * max(1.0, abs(value))]
    print("camera_info.yaml: %d x %d, fx %.3f, fy %.3f, cx %.3f, cy %.3f px, %s" %
          (info["image_width"], info["image_height"], k[0], k[4], k[2], k[5],
           "as the report" if not wrong else "differs from the report in " + ", ".join(wrong)))
    return ["camera_info.yaml: " + ", ".join(wrong)] if wrong else []


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("dataset")
    parser.add_argument("--set", choices=sorted(SETS), default="10x10")
    parser.add_argument("--kincal", default="kincal")
    parser.add_argument("--out", default="camera-hand-eye-out")
    args = parser.parse_args()
    spec = SETS[args.set]
    set_dir = os.path.join(args.dataset, spec["folder"])
    if not os.path.isdir(set_dir):
        print("skipped: %s is missing (the industrial_calibration example data)" % set_dir)
        return 77
    try:
        import numpy  # noqa: F401
        import scipy  # noqa: F401
        import cv2  # noqa: F401
        import yaml  # noqa: F401
    except ImportError as e:
        print("skipped: %s (python3-numpy, python3-scipy, python3-opencv, python3-yaml)" % e)
        return 77
    import opencv_check

    if os.path.isdir(args.out):
        shutil.rmtree(args.out)
    os.makedirs(args.out)
    path = lambda name: os.path.join(args.out, name)
    k = args.kincal

    n = write_poses(set_dir, path("poses.csv"))
    detect = [k, "detect", "--target", spec["target"], "--poses", path("poses.csv"),
              "--images", set_dir, "--out", path("readings.csv"), "--start-model",
              path("start.json"), "--json", path("detect.json"), "--mounting", spec["mounting"],
              "--gate", spec["gate"]]
    if spec["intrinsics"]:
        detect += ["--intrinsics", spec["intrinsics"]]
    print(run(detect).stdout, end="")
    calibration = run([k, "calibrate", "--model", path("start.json"), "--data",
                       path("readings.csv"), "--out", path("calibrated.json"), "--json",
                       path("report.json"), "--html", path("report.html"), "--images", set_dir])
    print(calibration.stdout, end="")

    with open(path("report.json")) as f:
        report = json.load(f)
    run([k, "export", "--model", path("calibrated.json"), "--format", "camera-info", "--out",
         path("camera_info.yaml")])
    failures = check_camera_info(path("camera_info.yaml"), report)
    failures += opencv_check.compare(path("readings.csv"), report, n, k, path, run,
                                      spec["mounting"] == "eye-in-hand")
    if failures:
        for f in failures:
            print("FAILED: " + f)
        return 1
    return 0


if __name__ == "__main__":
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    sys.exit(main())
