"""Mechanisms written in Python, for prototyping (docs/python.md).

Subclass ``Mechanism``, give its actuators, parameters and home actuator values, and
implement ``forward`` (an open chain: the pose follows from the actuator values)::

    class Slider(kincal.mechanisms.Mechanism):
        type = "my-slider"
        actuators = [("x", "mm", 20.0)]
        parameters = [("slider.y", 5.0, "mm", True)]
        home_actuators = [0.0]
        def forward(self, params, q, jacobians):
            ...
            return position, rotation, J_params, J_actuators

``model(Slider(), [MySensor()])`` makes a model of it with sensors written in Python;
``check(model)`` runs kincal's finite-difference checks of the mechanism's Jacobians (those of
``kincal check``), ``kincal.sensors.check`` those of the sensors and the residuals, and
``kincal.sensors.simulate`` calibrates it from simulated data with any backend. Like Python
sensors, a Python mechanism cannot be written to a model file and is the slow path (each
evaluation calls into Python); a mechanism ready for use is written in C++ and loaded as a
plug-in (``kincal.load_plugin``).
"""

from __future__ import annotations

from typing import List, Optional, Sequence, Tuple

import numpy as np

from . import _kincal
from .sensors import Sensor

__all__ = ["Mechanism", "check", "model"]


class Mechanism:
    """Base class of a mechanism written in Python.

    ``actuators``: (name, unit, range) per actuator, unit "mm" or "rad", range the half-width
    of the box around home from which configurations are drawn. ``parameters``: (name,
    nominal, unit) or (name, nominal, unit, free). ``home_actuators``: the actuator values at
    home. ``forward(params, q, jacobians)`` returns the pose the actuator values ``q`` reach
    (``position`` (3,) mm and ``rotation`` (3, 3): x_base = rotation @ x_platform + position)
    and, when ``jacobians``, J_params (6, num_parameters) and J_actuators (6, num_actuators)
    with respect to the pose perturbation [dt; dw] (position + dt, expm([dw]x) @ rotation;
    docs/theory.md); they may be None otherwise. A Python mechanism has no inverse kinematics
    (kincal asks for it only to place a preset's home, given here)."""

    type: str = "python-mechanism"
    actuators: Sequence[Tuple[str, str, float]] = ()
    parameters: Sequence[Tuple] = ()
    home_actuators: Sequence[float] = ()

    def forward(
        self, params: np.ndarray, q: np.ndarray, jacobians: bool
    ) -> Tuple[np.ndarray, np.ndarray, Optional[np.ndarray], Optional[np.ndarray]]:
        """The pose at ``q`` and, when ``jacobians``, its two Jacobians."""
        raise NotImplementedError("a Mechanism subclass implements forward")


def model(mechanism: Mechanism, sensors: List[Sensor]) -> "_kincal.Model":
    """A model of ``mechanism`` with ``sensors`` (written in Python); the mechanism's
    parameters marked free and every sensor parameter are free."""
    return _kincal._python_model(mechanism, sensors)


def check(model: "_kincal.Model") -> List[Tuple[str, bool, float, float, str]]:
    """kincal's finite-difference checks of the model's mechanism Jacobians (J_pose_params
    and J_pose_actuators at 4 configurations each, as ``kincal check``): (name, passed,
    worst, tolerance, detail) per check; raises AssertionError when one fails."""
    results = [tuple(r) for r in _kincal._check_mechanism(model)]
    failed = [r for r in results if not r[1]]
    if failed:
        raise AssertionError("mechanism Jacobians differ from finite differences: " +
                             "; ".join(f"{r[0]}: worst {r[2]:.3g} > {r[3]:.3g} ({r[4]})" for r in failed))
    return results  # type: ignore[return-value]
