#!/usr/bin/env python3
"""How good is a camera compared with a laser tracker? (docs/benchmarks.md, issue 38)

A simulated UR5 (the ur5-urdf presets: the URDF written from UR's published parameters) is
calibrated from a camera and from a laser tracker, on the same box of configurations (0.25 rad
per joint around home), and judged on held-out configurations:

  camera   ur5-urdf-camera (eye-to-hand: a 1280 x 1024 camera of 1200 px focal length 800 mm
           from a 6 x 8 chessboard on the flange), 0.2 px and 1 px of noise (standard
           deviation), 20-200 views, the intrinsics and distortion free or fixed at their true
           values (a camera calibrated beforehand);
  tracker  ur5-urdf (a reflector on the flange), 0.05 mm of noise, the same numbers of poses.

For each setting and seed, `kincal simulate --write-data` draws the truth and the data and
reports the held-out position error of the calibrated arm (mean over 200 configurations);
`kincal calibrate` on the same data reports the error its covariance predicts over the box (the
Cramér-Rao bound of the linearised problem at the estimate, as an RMS: for an error of the
same size in every direction the mean is 0.92 of the RMS). The table gives medians over the
seeds. Usage:

  benchmarks/camera_vs_tracker.py --kincal build/cli/kincal [--seeds 5] [--out FILE.md]
"""

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile

VIEWS = [20, 50, 100, 200]


def run(cmd, accept=(0,)):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode not in accept:
        sys.exit(f"failed ({done.returncode}): {' '.join(cmd)}\n{done.stderr}")
    return done


def one(kincal, work, model, noise, poses, seed):
    """Held-out position error (mean, mm) and the predicted one (mean, mm) of one run."""
    data = os.path.join(work, f"data-{seed}-{poses}.csv")
    sim = os.path.join(work, "sim.json")
    rep = os.path.join(work, "rep.json")
    for path in (data, sim, rep):
        if os.path.exists(path):
            os.remove(path)
    run([kincal, "simulate", "--model", model, "--noise-std", noise, "--poses", str(poses),
         "--seed", str(seed), "--write-data", data,
         "--json", sim])
    # Exit 3: a verdict other than "load", which the table counts.
    run([kincal, "calibrate", "--model", model, "--data", data, "--json", rep], accept=(0, 3))
    with open(sim) as f:
        held_out = json.load(f)["validation"]["after"]["position_mean_mm"]
    with open(rep) as f:
        report = json.load(f)
    predicted = report["predicted_pose_error"]["calibrated"]["position_mean_1sigma_mm"]
    os.remove(data)
    return held_out, predicted, report["verdict"]["overall"]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--kincal", required=True)
    parser.add_argument("--seeds", type=int, default=5)
    parser.add_argument("--out", help="write the table as Markdown to this file")
    args = parser.parse_args()
    kincal = os.path.abspath(args.kincal)
    rows = []
    with tempfile.TemporaryDirectory() as work:
        models = {}
        camera = os.path.join(work, "camera.json")
        run([kincal, "model", "--preset", "ur5-urdf-camera", "--out", camera])
        models["camera, intrinsics free"] = camera
        fixed = os.path.join(work, "camera-fixed.json")
        run([kincal, "model", "--preset", "ur5-urdf-camera", "--fix", "camera.f?", "--fix",
             "camera.c?", "--fix", "camera.k?", "--fix", "camera.p?", "--out", fixed])
        models["camera, intrinsics known"] = fixed
        tracker = os.path.join(work, "tracker.json")
        run([kincal, "model", "--preset", "ur5-urdf", "--out", tracker])
        # The camera presets' box, 0.25 rad per joint, for the tracker too.
        with open(tracker) as f:
            model = json.load(f)
        with open(camera) as f:
            box = [j["range_deg"] for j in json.load(f)["mechanism"]["joints"]]
        for joint, range_deg in zip(model["mechanism"]["joints"], box):
            joint["range_deg"] = range_deg
        with open(tracker, "w") as f:
            json.dump(model, f, indent=2)
        settings = [(f"{name}, {noise}", path, noise)
                    for name, path in models.items() if name.startswith("camera")
                    for noise in ("0.2px", "1px")]
        settings.append(("laser tracker, 0.05mm", tracker, "0.05mm"))
        for label, model, noise in settings:
            for poses in VIEWS:
                results = [one(kincal, work, model, noise, poses, seed)
                           for seed in range(1, args.seeds + 1)]
                held = statistics.median(r[0] for r in results)
                predicted = statistics.median(r[1] for r in results)
                loaded = sum(r[2] == "load" for r in results)
                rows.append((label, poses, held, predicted, f"{loaded}/{len(results)}"))
                print(f"{label:34s} {poses:4d}  held out {held:7.3f} mm  predicted "
                      f"{predicted:7.3f} mm  verdict load {loaded}/{len(results)}", flush=True)
    table = ["| set-up | views or poses | held-out position error (mean, mm) | "
             "predicted from the covariance (RMS, mm) | verdict `load` |",
             "|---|---|---|---|---|"]
    table += [f"| {label} | {poses} | {held:.3f} | {predicted:.3f} | {loads} |"
              for label, poses, held, predicted, loads in rows]
    if args.out:
        with open(args.out, "w") as f:
            f.write("\n".join(table) + "\n")


if __name__ == "__main__":
    main()
