"""The checks of run.py with code nobody here wrote: OpenCV's projection and calibration,
scipy's least squares. A target point p (target frame) is seen at X = C^-1 F T p by a static
camera (eye-to-hand: C the camera in the base, T the target on the flange) and at
X = C^-1 F^-1 T p by a camera on the robot (eye-in-hand: C on the flange, T in the base), F the
flange's pose in the base."""

import csv
import json
import math

import cv2
import numpy as np
from scipy.optimize import least_squares
from scipy.spatial.transform import Rotation

INTRINSICS = ["fx", "fy", "cx", "cy", "k1", "k2", "p1", "p2"]
FRAME = ["x", "y", "z", "rx", "ry", "rz"]


def read_table(path):
    """Flange poses (4 x 4, mm), detected pixels (n x 2, NaN when missing), image names."""
    flanges, pixels, images = [], [], []
    with open(path) as f:
        rows = [line for line in f if not line.startswith("#")]
    reader = csv.DictReader(rows)
    points = sorted({int(c.split(".")[1][1:]) for c in reader.fieldnames if c.endswith(".u")})
    for r in reader:
        T = np.eye(4)
        T[:3, :3] = Rotation.from_rotvec([float(r["flange.rotvec_" + a]) for a in "xyz"]).as_matrix()
        T[:3, 3] = [1000 * float(r["flange.%s_m" % a]) for a in "xyz"]
        flanges.append(T)
        uv = [[float(r["camera.p%d.%s" % (i, c)]) if r["camera.p%d.%s" % (i, c)] else math.nan
               for c in "uv"] for i in points]
        pixels.append(np.array(uv))
        images.append(r["image"])
    return flanges, pixels, images


def frame_matrix(values):
    """kincal's frame parameters [x, y, z, rx, ry, rz]: R = Rz(rz) Ry(ry) Rx(rx)."""
    T = np.eye(4)
    T[:3, :3] = Rotation.from_euler("ZYX", [values[5], values[4], values[3]]).as_matrix()
    T[:3, 3] = values[:3]
    return T


def frame_values(T):
    rz, ry, rx = Rotation.from_matrix(T[:3, :3]).as_euler("ZYX")
    return list(T[:3, 3]) + [rx, ry, rz]


EYE_IN_HAND = [False]


def project(camera, target, intrinsics, flange, grid):
    """Pixels of the grid's points through cv2.projectPoints."""
    F = np.linalg.inv(flange) if EYE_IN_HAND[0] else flange
    V = np.linalg.inv(camera) @ F @ target
    rvec = Rotation.from_matrix(V[:3, :3]).as_rotvec()
    K = np.array([[intrinsics[0], 0, intrinsics[2]], [0, intrinsics[1], intrinsics[3]], [0, 0, 1]])
    dist = np.array([intrinsics[4], intrinsics[5], intrinsics[6], intrinsics[7], 0.0])
    uv, _ = cv2.projectPoints(grid, rvec, V[:3, 3], K, dist)
    return uv.reshape(-1, 2)


def unpack(x):
    camera = np.eye(4)
    camera[:3, :3] = Rotation.from_rotvec(x[3:6]).as_matrix()
    camera[:3, 3] = x[0:3]
    target = np.eye(4)
    target[:3, :3] = Rotation.from_rotvec(x[9:12]).as_matrix()
    target[:3, 3] = x[6:9]
    return camera, target, x[12:20]


def pack(camera, target, intrinsics):
    return np.concatenate([camera[:3, 3], Rotation.from_matrix(camera[:3, :3]).as_rotvec(),
                           target[:3, 3], Rotation.from_matrix(target[:3, :3]).as_rotvec(),
                           intrinsics])


def fit(flanges, pixels, grid, x0):
    """The maximum-likelihood fit: every detected pixel, equal weights (scipy, OpenCV)."""
    def residuals(x):
        camera, target, intrinsics = unpack(x)
        out = []
        for F, uv in zip(flanges, pixels):
            seen = ~np.isnan(uv[:, 0])
            out.append((project(camera, target, intrinsics, F, grid) - uv)[seen].ravel())
        return np.concatenate(out)
    result = least_squares(residuals, x0, method="lm", xtol=1e-15, ftol=1e-15, gtol=1e-15,
                           max_nfev=20000)
    return result.x, residuals(result.x)


def two_step(flanges, pixels, grid, size):
    """OpenCV's own: calibrateCamera (k3 fixed), then calibrateHandEye (Park-Martin; its
    Tsai-Lenz leaves the ChArUco set's camera 190 mm apart from view to view)."""
    obj, img = [], []
    for uv in pixels:
        seen = ~np.isnan(uv[:, 0])
        obj.append(grid[seen].astype(np.float32))
        img.append(uv[seen].astype(np.float32))
    rms, K, dist, rvecs, tvecs = cv2.calibrateCamera(obj, img, size, None, None,
                                                     flags=cv2.CALIB_FIX_K3)
    # A static camera: OpenCV's recipe inverts the robot's poses (its output is then the
    # camera in the base); a camera on the robot takes them as they are.
    motions = flanges if EYE_IN_HAND[0] else [np.linalg.inv(F) for F in flanges]
    R, t = cv2.calibrateHandEye([T[:3, :3] for T in motions], [T[:3, 3] for T in motions],
                                [cv2.Rodrigues(r)[0] for r in rvecs], list(tvecs),
                                method=cv2.CALIB_HAND_EYE_PARK)
    camera = np.eye(4)
    camera[:3, :3], camera[:3, 3] = R, t.ravel()
    targets = []
    for F, r, tv in zip(flanges, rvecs, tvecs):
        V = np.eye(4)
        V[:3, :3], V[:3, 3] = cv2.Rodrigues(r)[0], tv.ravel()
        targets.append(F @ camera @ V if EYE_IN_HAND[0] else np.linalg.inv(F) @ camera @ V)
    target = np.eye(4)
    u, _, vt = np.linalg.svd(sum(T[:3, :3] for T in targets))
    target[:3, :3] = u @ np.diag([1, 1, np.linalg.det(u @ vt)]) @ vt
    target[:3, 3] = np.mean([T[:3, 3] for T in targets], axis=0)
    intrinsics = [K[0, 0], K[1, 1], K[0, 2], K[1, 2], dist[0, 0], dist[0, 1], dist[0, 2],
                  dist[0, 3]]
    return camera, target, np.array(intrinsics), rms


def kincal_values(report):
    by_name = {p["name"]: p for p in report["parameters"]}
    names = (["camera.frame." + a for a in FRAME] + ["camera.target." + a for a in FRAME] +
             ["camera." + a for a in INTRINSICS])
    return names, [by_name[n]["estimate"] for n in names], [by_name[n]["std"] for n in names]


def values_of(camera, target, intrinsics):
    return frame_values(camera) + frame_values(target) + list(intrinsics)


def rms(residuals):
    return math.sqrt(float(np.mean(np.square(residuals)))) if len(residuals) else math.nan


def compare(table, report, images_total, kincal, path, run, eye_in_hand):
    EYE_IN_HAND[0] = eye_in_hand
    flanges, pixels, images = read_table(table)
    n_points = pixels[0].shape[0]
    # The grid as kincal numbers it: point (r, c) at (c, r) x spacing (the model file's grid).
    with open(path("start.json")) as f:
        camera_json = json.load(f)["sensors"][0]
    g = camera_json["target"]["grid"]
    grid = np.array([[c * g["spacing"], r * g["spacing"], 0.0]
                     for r in range(g["rows"]) for c in range(g["columns"])])
    size = (int(camera_json["image"]["width"]), int(camera_json["image"]["height"]))

    names, estimate, std = kincal_values(report)
    failures = []
    print("\n%d of %d images with the target, %d points each at most" %
          (len(flanges), images_total, n_points))

    # Check 1: the same estimator, written independently.
    camera0, target0, intrinsics0, cv_rms = two_step(flanges, pixels, grid, size)
    x, residuals = fit(flanges, pixels, grid, pack(camera0, target0, intrinsics0))
    independent = values_of(*unpack(x))
    print("\nkincal against an independent maximum-likelihood fit (scipy + cv2.projectPoints), "
          "and OpenCV's two-step solution (calibrateCamera, calibrateHandEye Park-Martin):")
    print("%-22s %14s %11s %14s %8s %14s %8s" % ("parameter", "kincal", "std", "independent",
                                                  "diff/std", "OpenCV 2-step", "diff/std"))
    opencv = values_of(camera0, target0, intrinsics0)
    worst = 0.0
    for name, e, s, i, o in zip(names, estimate, std, independent, opencv):
        d_i = (i - e) / s
        worst = max(worst, abs(d_i))
        print("%-22s %14.6f %11.6f %14.6f %8.3f %14.6f %8.2f" % (name, e, s, i, d_i, o, (o - e) / s))
    # Reprojection error per point (the distance between a point measured and predicted, as
    # OpenCV's calibrateCamera reports it), per view and overall, from the independent fit.
    camera_i, target_i, intrinsics_i = unpack(x)
    per_view = []
    for F, uv in zip(flanges, pixels):
        seen = ~np.isnan(uv[:, 0])
        d = np.linalg.norm((project(camera_i, target_i, intrinsics_i, F, grid) - uv)[seen], axis=1)
        per_view.append(d)
    all_d = np.concatenate(per_view)
    point_rms = rms(all_d)
    print("independent fit: reprojection RMS %.4f px per coordinate, %.4f px per point "
          "(kincal's report: %.4f and %.4f); OpenCV's calibrateCamera alone (a free pose per "
          "view): %.4f px per point" % (rms(residuals), point_rms, report["residual_rms"],
                                        report["camera_views"][0]["rms_px"], cv_rms))
    views = report["camera_views"][0]["views"]
    if len(views) != len(per_view):
        failures.append("the report has %d camera views, the table %d" % (len(views), len(per_view)))
    else:
        worst_view = max(abs(v["rms_px"] - rms(d)) / rms(d) for v, d in zip(views, per_view))
        print("per-view reprojection RMS, kincal's report against the independent fit: largest "
              "relative difference %.1e" % worst_view)
        if worst_view > 1e-3:
            failures.append("per-view reprojection RMS differs by %.1e relative" % worst_view)
    print("largest |kincal - independent| / std: %.4f" % worst)
    if worst > 0.1:
        failures.append("kincal and the independent fit differ by %.3f std" % worst)

    # Leave one image out: calibrate on the others, predict its pixels.
    print("\nleave one image out (calibrated on the others, reprojection of the one left out):")
    loo = []
    with open(table) as f:
        lines = f.readlines()
    header = [i for i, line in enumerate(lines) if not line.startswith("#")][0]
    for k, image in enumerate(images):
        kept = lines[:header + 1] + [l for j, l in enumerate(lines[header + 1:]) if j != k]
        data = path("loo.csv")
        with open(data, "w") as f:
            f.writelines(kept)
        run([kincal, "calibrate", "--model", path("start.json"), "--data", data, "--json",
             path("loo-report.json")])
        with open(path("loo-report.json")) as f:
            _, values, _ = kincal_values(json.load(f))
        camera, target = frame_matrix(values[0:6]), frame_matrix(values[6:12])
        uv = pixels[k]
        seen = ~np.isnan(uv[:, 0])
        error = (project(camera, target, values[12:20], flanges[k], grid) - uv)[seen]
        loo.append(rms(error.ravel()))
        print("  %-16s %.3f px" % (image, loo[-1]))
    print("leave-one-out reprojection RMS: mean %.3f px, max %.3f px (the fit's own %.3f px)" %
          (float(np.mean(loo)), float(np.max(loo)), report["residual_rms"]))
    return failures
