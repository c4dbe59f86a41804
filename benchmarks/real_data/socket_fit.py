#!/usr/bin/env python3
"""Calibrate a URDF arm from joint angles alone, a ball on its tool put into sockets of
unknown position, pairs of sockets a known distance apart, with numpy and scipy alone: the
benchmark's independent counterpart of kincal's `socket` sensors and `fixture-distance`
constraint (docs/fixtures.md) through `kincal calibrate` and `kincal validate` (no kincal
code).

    socket_fit.py --urdf ARM.urdf --tip LINK --data TRAIN.csv --test HELD_OUT.csv
                  --free FREE.txt --reading-std 0.1 --distance 50 --distance-std 0.05
                  --out RESULT.json

The files: the arm's joint columns and, per socket S, columns S.x, S.y, S.z, filled (0) in the
rows measured in S, empty elsewhere. A socket's residual is the ball (the tool frame's origin,
kinematics.py) minus the socket's centre (S.point.x, .y, .z, base coordinates), over
--reading-std; sockets named <stem>_0 and <stem>_1 are --distance apart: one residual
(|p_0 - p_1| - distance) / distance-std per pair. FREE.txt lists the parameters to estimate
(one pattern a line, fnmatch: the caller's choice, as kincal's model file `free`); the rest
stay at the URDF's values (0), the sockets start at the mean of the nominal ball positions.
RESULT.json holds the estimate, the final cost and the held-out residuals (ball - socket).
"""

import argparse
import fnmatch

import numpy as np

import fit
import kinematics as kin


class SocketProblem:
    def __init__(self, arm, sockets, reading_std, distance, distance_std):
        self.arm, self.sockets = arm, sockets
        self.mech = len(arm.parameter_names())
        self.names = [n for n, _ in arm.parameter_names()]
        self.names += ["%s.point.%s" % (s, a) for s in sockets for a in "xyz"]
        self.std, self.distance, self.distance_std = reading_std, distance, distance_std
        index = {s: i for i, s in enumerate(sockets)}
        self.pairs = [(index[s], index[s[:-2] + "_1"]) for s in sockets
                      if s.endswith("_0") and s[:-2] + "_1" in index]

    def load(self, path):
        """Joint values, the socket of each row and its readings (one socket a row)."""
        q, columns = fit.read_measurements(path, self.arm.names)
        which = np.full(q.shape[0], -1)
        meas = np.zeros((q.shape[0], 3))
        for k, s in enumerate(self.sockets):
            if s + ".x" not in columns:
                continue
            rows = ~np.isnan(columns[s + ".x"])
            which[rows] = k
            meas[rows] = np.stack([columns[s + "." + a][rows] for a in "xyz"], 1)
        keep = which >= 0
        return q[keep], which[keep], meas[keep]

    def residuals(self, x, data, jacobian):
        """Whitened residuals (rows x 3, then one per pair) and their Jacobian (all columns)."""
        q, which, meas = data
        R, t, moves = self.arm.walk(x[:self.mech], q, motions=jacobian)
        centres = x[self.mech:].reshape(-1, 3)
        r = (t - centres[which] - meas) / self.std
        gaps = [centres[a] - centres[b] for a, b in self.pairs]
        c = [(np.linalg.norm(g) - self.distance) / self.distance_std for g in gaps]
        r = np.concatenate([r.reshape(-1), c])
        if not jacobian:
            return r, None
        n = q.shape[0]
        J = np.zeros((3 * n + len(self.pairs), len(self.names)))
        for i, (kind, u, o) in enumerate(moves):
            J[:3 * n, i] = kin.point_motion(kind, u, o, t).reshape(-1) / self.std
        rows = np.arange(n)
        for a in range(3):
            J[3 * rows + a, self.mech + 3 * which + a] = -1.0 / self.std
        for p, ((a, b), g) in enumerate(zip(self.pairs, gaps)):
            unit = g / np.linalg.norm(g) / self.distance_std
            J[3 * n + p, self.mech + 3 * a:self.mech + 3 * a + 3] = unit
            J[3 * n + p, self.mech + 3 * b:self.mech + 3 * b + 3] = -unit
        return r, J

    def evaluate(self, x, free, jacobian, data):
        r, J = self.residuals(x, data, jacobian)
        cost = 0.5 * float(r @ r)
        if not jacobian:
            return cost, None, None
        J = J[:, free]
        return cost, J.T @ J, J.T @ r


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    for a in ("--urdf", "--tip", "--data", "--test", "--free", "--out"):
        ap.add_argument(a, required=True)
    ap.add_argument("--reading-std", type=float, required=True)
    ap.add_argument("--distance", type=float, required=True)
    ap.add_argument("--distance-std", type=float, required=True)
    args = ap.parse_args()
    arm = kin.UrdfArm(args.urdf, args.tip)
    with open(args.data) as f:
        header = next(line for line in f if not line.startswith("#")).strip().split(",")
    sockets = sorted({c[:-2] for c in header if c.endswith(".x")})
    problem = SocketProblem(arm, sockets, args.reading_std, args.distance, args.distance_std)
    data = problem.load(args.data)
    x = np.zeros(len(problem.names))
    _, t, _ = arm.walk(x[:problem.mech], data[0], motions=False)
    for k in range(len(sockets)):
        x[problem.mech + 3 * k:problem.mech + 3 * k + 3] = t[data[1] == k].mean(axis=0)
    with open(args.free) as f:
        patterns = [line.strip() for line in f if line.strip()]
    free = [i for i, n in enumerate(problem.names)
            if any(fnmatch.fnmatchcase(n, p) for p in patterns)]
    evaluate = lambda x, free, jac: problem.evaluate(x, free, jac, data)
    x, cost, iterations = fit.levenberg_marquardt(evaluate, x, free)
    held, _ = problem.residuals(x, problem.load(args.test), False)
    held = (held[:held.size - len(problem.pairs)] * args.reading_std).reshape(-1, 3)
    fit.write_result(args.out, problem.names, x, free, cost, 3 * data[0].shape[0]
                     + len(problem.pairs), iterations, held.tolist())


if __name__ == "__main__":
    main()
