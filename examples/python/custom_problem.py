"""Your own least-squares problem through kincal's backends (docs/python.md): fitting a
circle to noisy points, with residuals and Jacobian in numpy."""

import numpy as np

import kincal

rng = np.random.default_rng(1)
angles = rng.uniform(0, 2 * np.pi, 50)
points = np.c_[3 + 2 * np.cos(angles), -1 + 2 * np.sin(angles)] + rng.normal(0, 0.01, (50, 2))


def residuals(p: np.ndarray) -> np.ndarray:
    """Distance of each point to the circle (centre p[0], p[1], radius p[2])."""
    return np.hypot(points[:, 0] - p[0], points[:, 1] - p[1]) - p[2]


def jacobian(p: np.ndarray) -> np.ndarray:
    d = np.hypot(points[:, 0] - p[0], points[:, 1] - p[1])
    return np.c_[-(points[:, 0] - p[0]) / d, -(points[:, 1] - p[1]) / d, -np.ones(len(points))]


problem = kincal.LeastSquaresProblem(residuals, jacobian, 3, len(points), ["cx", "cy", "r"])
for solver in ["gn", "lm", "ceres", "ipopt", "nlopt:LD_LBFGS"]:
    result = kincal.solve(problem, np.array([0.0, 0.0, 1.0]), solver, max_iterations=1000)
    print(f"{solver:16s} {result.termination:15s} {result.iterations:4d} iterations  "
          f"centre ({result.x[0]:.4f}, {result.x[1]:.4f}) radius {result.x[2]:.4f}")
