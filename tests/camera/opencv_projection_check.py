#!/usr/bin/env python3
"""kincal's camera against OpenCV's cv2.projectPoints (ctest camera_projection_matches_opencv).

For both mountings (the presets ur5-urdf-camera and ur5-urdf-eye-in-hand, given distortion in
every coefficient), `kincal fk` predicts the pixels of every target point at a few
configurations; this script takes the flange pose it reports and the model file's frames, puts
the target in the camera's frame with numpy, and projects the points with OpenCV's pinhole and
distortion model (cameraMatrix, distCoeffs = k1, k2, p1, p2, k3). They must agree to 1e-6 px.
Exits 77 (skipped, with the reason) when cv2 or numpy is missing.

Usage: opencv_projection_check.py KINCAL
"""

import json
import math
import os
import subprocess
import sys
import tempfile

try:
    import cv2
    import numpy as np
except ImportError as e:  # ctest reports the test skipped, with this reason
    print(f"skipped: {e} (python3-opencv, python3-numpy)")
    sys.exit(77)

DISTORTION = {"k1": -0.11, "k2": 0.06, "k3": -0.02, "p1": 0.0012, "p2": -0.0008}


def rotation_zyx_deg(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx), angles in degrees (kincal's frames)."""
    a, b, c = (math.radians(v) for v in (rx, ry, rz))
    Rx = np.array([[1, 0, 0], [0, math.cos(a), -math.sin(a)], [0, math.sin(a), math.cos(a)]])
    Ry = np.array([[math.cos(b), 0, math.sin(b)], [0, 1, 0], [-math.sin(b), 0, math.cos(b)]])
    Rz = np.array([[math.cos(c), -math.sin(c), 0], [math.sin(c), math.cos(c), 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def frame(obj):
    return rotation_zyx_deg(*obj["rotation_zyx_deg"]), np.array(obj["position"], dtype=float)


def target_points(target):
    if "grid" in target:
        g = target["grid"]
        return np.array([[c * g["spacing"], r * g["spacing"], 0.0]
                         for r in range(g["rows"]) for c in range(g["columns"])])
    return np.array(target["points"], dtype=float)


def check(kincal, work, preset):
    model_path = os.path.join(work, preset + ".json")
    subprocess.run([kincal, "model", "--preset", preset, "--out", model_path], check=True,
                   capture_output=True)
    with open(model_path) as f:
        model = json.load(f)
    camera = model["sensors"][0]
    camera["distortion"] = DISTORTION
    camera["intrinsics"].update({"fx": 1210.5, "fy": 1190.25, "cx": 650.5, "cy": 500.75})
    with open(model_path, "w") as f:
        json.dump(model, f)
    joints = model["mechanism"]["joints"]
    configs = os.path.join(work, preset + ".csv")
    with open(configs, "w") as f:
        f.write(",".join(j["name"] + "_deg" for j in joints) + "\n")
        for k in range(5):
            f.write(",".join(str(j["home_deg"] + 6 * math.sin(1.3 * k + 0.7 * i))
                             for i, j in enumerate(joints)) + "\n")
    fk = subprocess.run([kincal, "fk", "--model", model_path, "--data", configs, "--json", "-"],
                        check=True, capture_output=True, text=True)
    rows = json.loads(fk.stdout)["rows"]

    R_c, t_c = frame(camera["frame"])
    R_t, t_t = frame(camera["target"]["frame"])
    points = target_points(camera["target"])
    K = np.array([[camera["intrinsics"]["fx"], 0, camera["intrinsics"]["cx"]],
                  [0, camera["intrinsics"]["fy"], camera["intrinsics"]["cy"]], [0, 0, 1]])
    dist = np.array([DISTORTION[k] for k in ("k1", "k2", "p1", "p2", "k3")])
    worst = 0.0
    for row in rows:
        assert row["status"] == "ok", row
        p = row["pose"]
        R = rotation_zyx_deg(p["rx_deg"], p["ry_deg"], p["rz_deg"])
        t = np.array([p["x_mm"], p["y_mm"], p["z_mm"]])
        # The target's frame in the camera's: through the base (eye-to-hand: target on the
        # flange, camera in the base) or through the flange (eye-in-hand).
        if camera["mounting"] == "eye-to-hand":
            R_ct = R_c.T @ R @ R_t
            t_ct = R_c.T @ (R @ t_t + t - t_c)
        else:
            R_ct = R_c.T @ R.T @ R_t
            t_ct = R_c.T @ (R.T @ (t_t - t) - t_c)
        rvec, _ = cv2.Rodrigues(R_ct)
        projected, _ = cv2.projectPoints(points, rvec, t_ct, K, dist)
        projected = projected.reshape(-1, 2)
        readings = row["readings"]
        for i, (u, v) in enumerate(projected):
            worst = max(worst, abs(readings[f"camera.p{i}.u"] - u),
                        abs(readings[f"camera.p{i}.v"] - v))
    print(f"{preset} ({camera['mounting']}): {len(rows)} configurations x {len(points)} "
          f"points, worst |kincal - OpenCV| {worst:.3g} px")
    return worst


def main():
    kincal = os.path.abspath(sys.argv[1])
    with tempfile.TemporaryDirectory() as work:
        worst = max(check(kincal, work, preset)
                    for preset in ("ur5-urdf-camera", "ur5-urdf-eye-in-hand"))
    if not worst < 1e-6:
        sys.exit(f"kincal's projection differs from OpenCV's by {worst} px")


if __name__ == "__main__":
    main()
