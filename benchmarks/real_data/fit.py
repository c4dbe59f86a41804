"""What the benchmark's calibration scripts share: reading a measurement file, choosing the
parameters the data determine, and Levenberg-Marquardt on the normal equations (numpy and
scipy, no kincal code).

The problems hand over `evaluate(x, free, jacobian)`: the cost 1/2 sum r^2 over all residuals
and, with `jacobian`, J^T J and J^T r of the columns `free`, accumulated over chunks of rows so
that 10^6 rows never hold the whole Jacobian (3 x 10^6 x 63 doubles would be 1.5 GB).
"""

import csv
import json

import numpy as np
import scipy.linalg

CHUNK = 20000  # rows per block of the Jacobian


def read_measurements(path, joints):
    """Joint values (N, joints) and the reading columns {name: (N,) array, NaN where empty}
    of a kincal measurement file (comment lines start with '#')."""
    skip = 0
    with open(path, newline="") as f:
        for line in f:
            skip += 1
            if not line.startswith("#"):
                header = next(csv.reader([line]))
                break
    try:
        table = np.loadtxt(path, delimiter=",", comments="#", skiprows=skip, ndmin=2)
    except ValueError:  # empty fields (sensors not read in a row): the slow reader
        with open(path, newline="") as f:
            rows = [r for r in csv.reader(l for l in f if not l.startswith("#"))][1:]
        table = np.array([[float(v) if v != "" else np.nan for v in r] for r in rows if r])
    column = {name: table[:, i] for i, name in enumerate(header)}
    missing = [j for j in joints if j not in column]
    if missing:
        raise SystemExit("%s: no column for joint(s) %s" % (path, ", ".join(missing)))
    q = np.stack([column[j] for j in joints], axis=1)
    return q, {k: v for k, v in column.items() if k not in joints}


def identifiable(G, classes, rcond=1e-6, part=1e-3):
    """The parameters to estimate, from G = J^T J of every parameter at the start: scale the
    columns to unit norm, take the numerical rank (singular values above rcond of the
    largest), then pick columns greedily, each the one farthest from the span of those
    already chosen (pivoted Cholesky of the scaled G, i.e. pivoted QR of the scaled J), from
    the lowest class that still has a column with a part above `part` outside that span."""
    d = np.sqrt(np.diag(G))
    live = np.flatnonzero(d > 1e-12 * d.max())
    S = G[np.ix_(live, live)] / np.outer(d[live], d[live])
    s = np.sqrt(np.clip(scipy.linalg.eigvalsh(S), 0.0, None))
    rank = int(np.sum(s > rcond * s.max()))
    cls = np.asarray(classes)[live]
    left = np.diag(S).copy()  # squared part of each column outside the chosen span
    L = np.zeros((len(live), rank))
    chosen = []
    for k in range(rank):
        pick = None
        for c in sorted(set(cls)):
            cand = [j for j in range(len(live)) if cls[j] == c and j not in chosen]
            if cand and max(left[cand]) > part ** 2:
                # the first of (nearly) equal columns, so exact duplicates go to the
                # parameter listed first
                best = max(left[cand])
                pick = next(j for j in cand if left[j] >= best * (1.0 - 1e-9))
                break
        if pick is None:
            rest = [j for j in range(len(live)) if j not in chosen]
            pick = rest[int(np.argmax(left[rest]))]
        L[:, k] = (S[:, pick] - L[:, :k] @ L[pick, :k]) / np.sqrt(left[pick])
        left -= L[:, k] ** 2
        left[pick] = 0.0
        chosen.append(pick)
    return sorted(int(live[j]) for j in chosen), s


def levenberg_marquardt(evaluate, x, free, first=None, max_iterations=100, tolerance=1e-12):
    """Minimise the cost over x[free] from x; `first` is (cost, J^T J, J^T r) at x when the
    caller has it. Stops when a step lowers the cost by less than `tolerance` of it (or
    predicts so). Returns x, the cost and the number of iterations."""
    x = x.copy()
    cost, H, g = first if first is not None else evaluate(x, free, True)
    lam = 1e-4
    for iteration in range(1, max_iterations + 1):
        d = np.sqrt(np.diag(H))
        d[d == 0] = 1.0
        Hs, gs = H / np.outer(d, d), g / d
        while True:
            A = Hs + lam * np.eye(len(free))
            step = -scipy.linalg.solve(A, gs, assume_a="pos") / d
            trial = x.copy()
            trial[free] += step
            new_cost = evaluate(trial, free, False)[0]
            predicted = -(g @ step + 0.5 * step @ H @ step)
            if np.isfinite(new_cost) and new_cost <= cost:
                break
            lam *= 10.0
            if lam > 1e12:
                return x, cost, iteration
        decrease = cost - new_cost
        x = trial
        lam = max(lam / 10.0, 1e-12)
        if decrease <= tolerance * cost or predicted <= tolerance * cost:
            return x, new_cost, iteration
        cost, H, g = evaluate(x, free, True)
    return x, cost, max_iterations


def write_result(path, names, x, free, cost, residual_count, iterations, held_out):
    """The script's answer, for the runner to compare with kincal's."""
    with open(path, "w") as f:
        json.dump({"free": [names[i] for i in free],
                   "estimate": {names[i]: float(x[i]) for i in free},
                   "final_cost": float(cost), "residuals": int(residual_count),
                   "residual_rms": float(np.sqrt(2.0 * cost / residual_count)),
                   "iterations": iterations, "held_out_residuals": held_out}, f)
