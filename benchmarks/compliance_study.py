#!/usr/bin/env python3
"""Joint compliance, simulated (docs/theory.md, "Joint compliance under gravity"; issue 39).

A simulated UR5 (the preset ur5-urdf-compliance: UR's published masses and centres of mass)
whose true geometry is off nominal (0.3 mm and 0.5 mrad uniform on every free geometric
parameter) and whose joints deflect under gravity with compliances s x c0, c0 = (0, 3, 3, 10,
10, 0) x 1e-5 rad/Nm (shoulder and elbow about what the real UR5's data give), is measured by a
point tracker at 100 configurations (0.5 rad per joint around home) carrying a payload of 0 kg
at half of them and 4 kg at the other half, with Gaussian noise sigma on each coordinate.
Two calibrations of the same data, from the nominal model:
  geometric   ur5-urdf's parameters (no compliance, no payload column): what a purely
              geometric calibration reaches;
  compliant   the same with the compliances free (the payload per row).
Judged on 500 held-out configurations (payloads 0 and 4 kg) without noise: the mean 3-D
distance between the calibrated model's prediction and the truth. And the compliances'
recovery: estimate - truth against the reported std (over the seeds: the RMS of
(estimate - truth) / std, 1 for an efficient estimator). Medians over the seeds.

  PYTHONPATH=build/python benchmarks/compliance_study.py [--seeds 5] [--out FILE.md]
"""

import argparse
import statistics
import sys

import numpy as np

import kincal

C0 = np.array([0, 3e-5, 3e-5, 1e-4, 1e-4, 0])
JOINTS = ["shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint", "wrist_1_joint",
          "wrist_2_joint", "wrist_3_joint"]


def configurations(rng, count, home):
    q = home + rng.uniform(-0.5, 0.5, size=(count, 6))
    payload = np.where(np.arange(count) % 2 == 0, 0.0, 4.0)
    return np.hstack([q, payload[:, None]])


def run(scale, sigma, seed):
    rng = np.random.default_rng(seed)
    nominal = kincal.Model.preset("ur5-urdf-compliance")
    names = nominal.parameter_names
    values = nominal.nominal.copy()
    for i, name in enumerate(names):
        if name.endswith(".compliance"):
            values[i] = 0.0
    start = nominal.with_values(values)
    truth_values = values.copy()
    for i, (name, unit) in enumerate(zip(names, nominal.parameter_units)):
        if nominal.free[i] and not name.startswith("gravity") and not name.endswith(".compliance"):
            truth_values[i] += rng.uniform(-1, 1) * (0.3 if unit == "mm" else 5e-4)
    for j, joint in enumerate(JOINTS):
        truth_values[names.index(joint + ".compliance")] = scale * C0[j]
    truth = nominal.with_values(truth_values)
    home = np.array([0, -np.pi / 2, np.pi / 2, -np.pi / 2, -np.pi / 2, 0])
    q = configurations(rng, 100, home)
    _, readings, status, _ = truth.forward_kinematics(q)
    assert all(s == "ok" for s in status)
    readings = readings + rng.normal(0, sigma, size=readings.shape)
    held_q = configurations(rng, 500, home)
    _, held_truth, _, _ = truth.forward_kinematics(held_q)

    # The compliant model: compliances free where the preset frees them, gravity's tilt fixed.
    compliant = start.copy()
    compliant.set_free("gravity.*", False)
    data = kincal.Measurements(q, readings, compliant.actuator_names, compliant.reading_names)
    fit = kincal.calibrate(compliant, data, tolerance_priors="off")
    _, predicted, _, _ = fit.calibrated_model.forward_kinematics(held_q)
    compliant_error = np.linalg.norm(predicted - held_truth, axis=1).mean()
    z = []
    for p in fit["parameters"]:
        if p["name"].endswith(".compliance") and p["std"]:
            z.append((p["estimate"] - truth_values[names.index(p["name"])]) / p["std"])

    # The geometric model: the same arm without compliance (ur5-urdf), the payload unknown.
    geometric = kincal.Model.preset("ur5-urdf")
    gnames = geometric.parameter_names
    gvalues = geometric.nominal.copy()
    geometric = geometric.with_values(gvalues)
    for i, name in enumerate(gnames):
        geometric.set_free(name, bool(start.free[names.index(name)]))
    gdata = kincal.Measurements(q[:, :6], readings, geometric.actuator_names,
                                geometric.reading_names)
    gfit = kincal.calibrate(geometric, gdata, tolerance_priors="off")
    _, gpredicted, _, _ = gfit.calibrated_model.forward_kinematics(held_q[:, :6])
    geometric_error = np.linalg.norm(gpredicted - held_truth, axis=1).mean()
    return geometric_error, compliant_error, z


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--out", help="also write the table (Markdown) to this file")
    args = ap.parse_args()
    lines = ["| compliance scale s | noise sigma (mm) | geometric: held-out error (mm) | "
             "compliant: held-out error (mm) | compliances' RMS z |",
             "|---:|---:|---:|---:|---:|"]
    for sigma in (0.01, 0.06):
        for scale in (0.0, 0.25, 0.5, 1.0, 2.0):
            results = [run(scale, sigma, 100 * seed + 7) for seed in range(args.seeds)]
            g = statistics.median(r[0] for r in results)
            c = statistics.median(r[1] for r in results)
            z = np.concatenate([r[2] for r in results])
            lines.append("| %.2f | %.2f | %.4f | %.4f | %.2f |"
                         % (scale, sigma, g, c, float(np.sqrt(np.mean(np.square(z))))))
            print(lines[-1], flush=True)
    text = "\n".join(lines) + "\n"
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
