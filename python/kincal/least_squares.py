"""The generic least-squares layer: your own problem through kincal's backends.

``LeastSquaresProblem(residuals, jacobian, num_parameters, num_residuals)`` takes Python
callables; ``solve(problem, x0, solver="lm")`` runs any registered backend (``solvers()``)
on it and returns a SolveResult. This is the slow path: every evaluation calls into Python.
The backends are the same honest ones as calibrate's: a "converged" claim is checked at the
returned point (docs/solvers.md).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Optional, Union

import numpy as np

from . import _kincal
from ._errors import KincalInterrupt, _on_main_thread

LeastSquaresProblem = _kincal.LeastSquaresProblem


@dataclass
class SolveResult:
    """What a solve returned: the best point ``x``, why it stopped (``termination``:
    converged, max_iterations, diverged, failed, user_stopped; ``message``), counts, costs
    (1/2 |r|^2) and the per-iteration ``trace`` (columns iteration, cost, gradient_norm,
    step_norm, damping, seconds)."""

    x: np.ndarray
    solver: str
    termination: str
    message: str
    converged: bool
    iterations: int
    initial_cost: float
    final_cost: float
    residual_evaluations: int
    jacobian_evaluations: int
    wall_seconds: float
    trace: np.ndarray


def solve(
    problem: "_kincal.LeastSquaresProblem",
    x0: np.ndarray,
    solver: str = "lm",
    *,
    max_iterations: int = 200,
    function_tolerance: float = 1e-12,
    parameter_tolerance: float = 1e-10,
    gradient_tolerance: float = 1e-12,
    lower: Optional[np.ndarray] = None,
    upper: Optional[np.ndarray] = None,
    options: Optional[Dict[str, Union[str, int, float]]] = None,
    loss: str = "none",
    verbosity: int = 0,
) -> SolveResult:
    """Minimises 1/2 |r(x)|^2 from ``x0`` with backend ``solver`` (gn, lm, ceres, ipopt,
    nlopt:<ALGORITHM>; ``options`` are its key=value settings, docs/solvers.md; ``loss`` a
    robust loss, huber:DELTA or cauchy:DELTA, for lm and ceres). The GIL is
    released between evaluations; Ctrl-C raises KincalInterrupt whose ``result`` is the
    SolveResult at the best point so far. An exception in a callable propagates."""
    backend_options = {str(k): str(v) for k, v in (options or {}).items()}
    d = _kincal._solve(
        problem,
        x0,
        solver,
        max_iterations,
        function_tolerance,
        parameter_tolerance,
        gradient_tolerance,
        lower,
        upper,
        backend_options,
        loss,
        verbosity,
        _on_main_thread(),
    )
    interrupted = d.pop("interrupted")
    result = SolveResult(**d)
    if interrupted:
        raise KincalInterrupt("kincal.solve interrupted at the best point so far", result)
    return result


def solvers() -> Dict[str, str]:
    """The registered solver names (a family as nlopt:<ALGORITHM>) and descriptions."""
    return dict(_kincal.solvers())
