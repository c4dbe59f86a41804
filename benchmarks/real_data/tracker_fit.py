#!/usr/bin/env python3
"""Calibrate a URDF arm from point- or pose-tracker readings with numpy and scipy alone: the
benchmark's independent counterpart of `kincal model --urdf ... --sensor point-tracker|
pose-tracker` followed by `kincal calibrate` and `kincal validate` (no kincal code).

    tracker_fit.py --urdf ARM.urdf --tip LINK --sensor point|pose --data CAL.csv
                   --test HELD_OUT.csv --out RESULT.json

The model: kinematics.py's error model of the arm, and a tracker with its own frame
(`tracker.frame.*`, in base coordinates) that sees a target point (`tracker.target.x,y,z`)
or a marker frame (`tracker.marker.*`) on the tool frame:
    point: y = R_f^T (x - t_f), x the target in base coordinates (readings tracker.x, .y, .z)
    pose:  the marker frame in the tracker's frame: its position, and its rotation vector
           (tracker.rotvec_x, _y, _z); the rotation residual is log(R_pred R_meas^T)
Every parameter starts at 0 (the URDF's geometry); those the data determine are chosen by
fit.identifiable on J at the start, the rest stay at 0. The residuals are divided by
--reading-std (mm, or mm,rad: kincal's reading_std), or taken as they are without it.
RESULT.json holds the estimate, the final cost and the residuals (predicted - measured) on
the held-out file.
"""

import argparse

import numpy as np

import fit
import kinematics as kin


class TrackerProblem:
    def __init__(self, arm, sensor, reading_std=None):
        self.arm, self.pose = arm, sensor == "pose"
        # each residual divided by its reading's std (kincal's reading_std), or as it is
        self.weight = (1.0 if reading_std is None else
                       1.0 / np.repeat(reading_std[:2 if self.pose else 1], 3))
        named = arm.parameter_names()
        named += [("tracker.frame." + c, 1) for c in kin.FRAME]
        named += ([("tracker.marker." + c, 1) for c in kin.FRAME] if self.pose
                  else [("tracker.target." + c, 1) for c in "xyz"])
        self.names = [n for n, _ in named]
        self.classes = [c for _, c in named]
        self.mech = len(arm.parameter_names())
        self.readings = (["tracker." + a for a in "xyz"]
                         + (["tracker.rotvec_" + a for a in "xyz"] if self.pose else []))

    def load(self, path):
        q, columns = fit.read_measurements(path, self.arm.names)
        y = np.stack([columns[r] for r in self.readings], axis=1)
        if self.pose:  # the measured rotations as matrices, once
            return q, (y[:, :3], kin.exp_so3(y[:, 3:]))
        return q, (y, None)

    def residuals(self, x, q, meas, free=None):
        """Residuals (N, 3 or 6) and, with `free`, their Jacobian (N, 3 or 6, len(free))."""
        R, t, moves = self.arm.walk(x[:self.mech], q, motions=free is not None)
        fR, ft = kin.frame_block(x[self.mech:self.mech + 6])
        s = x[self.mech + 6:]
        if self.pose:
            mR, mt = kin.frame_block(s)
            xp = t + R @ mt
            yt = (xp - ft) @ fR
            Ry = fR.T @ R @ mR
            phi = kin.log_so3(Ry @ np.swapaxes(meas[1], 1, 2))
            r = np.concatenate([yt - meas[0], phi], axis=1)
        else:
            xp = t + R @ s
            r = (xp - ft) @ fR - meas[0]
        if free is None:
            return r, None
        Ef = kin.zyx_rates(*x[self.mech + 3:self.mech + 6])
        # the tracker's frame: shifting it by u moves what it sees by -u; turning it by w
        # about its origin turns what it sees by -w about that origin
        moves = moves + [("t", -np.eye(3)[k], None) for k in range(3)]
        moves += [("r", -Ef[:, k], ft) for k in range(3)]
        if self.pose:
            W = R @ kin.zyx_rates(*s[3:6])
            moves += [("t", R[:, :, k], None) for k in range(3)]
            moves += [("r", W[:, :, k], xp) for k in range(3)]
            Jl = kin.left_jacobian_inverse(phi) @ fR.T
        else:
            moves += [("t", R[:, :, k], None) for k in range(3)]
        J = np.zeros(r.shape + (len(free),))
        for c, i in enumerate(free):
            kind, u, o = moves[i]
            J[:, :3, c] = kin.point_motion(kind, u, o, xp) @ fR
            if self.pose and kind == "r":
                J[:, 3:, c] = (Jl @ np.broadcast_to(u, xp.shape)[:, :, None])[:, :, 0]
        return r, J

    def evaluate(self, x, free, jacobian, q, meas):
        cost, H, g = 0.0, np.zeros((len(free), len(free))), np.zeros(len(free))
        for a in range(0, q.shape[0], fit.CHUNK):
            part = (meas[0][a:a + fit.CHUNK],
                    None if meas[1] is None else meas[1][a:a + fit.CHUNK])
            r, J = self.residuals(x, q[a:a + fit.CHUNK], part, free if jacobian else None)
            r = r * self.weight
            cost += 0.5 * float(np.sum(r * r))
            if jacobian:
                J = (J * np.reshape(self.weight, (-1, 1))).reshape(-1, len(free))
                H += J.T @ J
                g += J.T @ r.reshape(-1)
        return cost, H, g


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--urdf", required=True)
    ap.add_argument("--tip", required=True)
    ap.add_argument("--sensor", choices=["point", "pose"], required=True)
    ap.add_argument("--data", required=True)
    ap.add_argument("--test", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--reading-std", metavar="MM[,RAD]",
                    help="the readings' std (kincal's reading_std): residuals divided by it")
    args = ap.parse_args()
    std = (None if args.reading_std is None
           else np.array([float(v) for v in args.reading_std.split(",")]))
    problem = TrackerProblem(kin.UrdfArm(args.urdf, args.tip), args.sensor, std)
    q, meas = problem.load(args.data)
    evaluate = lambda x, free, jac: problem.evaluate(x, free, jac, q, meas)
    x = np.zeros(len(problem.names))
    every = list(range(len(x)))
    cost, G, g = evaluate(x, every, True)
    free, _ = fit.identifiable(G, problem.classes)
    first = (cost, G[np.ix_(free, free)], g[free])
    x, cost, iterations = fit.levenberg_marquardt(evaluate, x, free, first)
    tq, tmeas = problem.load(args.test)
    held, _ = problem.residuals(x, tq, tmeas)
    fit.write_result(args.out, problem.names, x, free, cost, q.shape[0] * len(problem.readings),
                     iterations, held.tolist())


if __name__ == "__main__":
    main()
