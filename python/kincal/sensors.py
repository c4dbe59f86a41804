"""Sensors written in Python, for prototyping (docs/python.md).

Subclass ``Sensor``, give its readings and parameters, and implement ``predict``::

    class Gauge(kincal.sensors.Sensor):
        type = "my-gauge"
        def __init__(self):
            super().__init__("g", ["g"], ["mm"], [("g.offset", 0.0, "mm")])
        def predict(self, params, position, rotation, jacobians):
            ...
            return reading, J_pose, J_params

``with_sensors(model, [Gauge()])`` puts it on a model's mechanism; ``check(model)`` runs
the finite-difference checks every built-in sensor passes; ``simulate(model, ...)``
calibrates it from simulated data with any backend. Python sensors cannot be written to a
model file (their code is not data): they are for prototyping, and the slow path (each
prediction calls into Python). A sensor ready for use is written in C++ and registered by
name (docs/architecture.md), and then usable from Python through model files like any other.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from . import _kincal
from ._errors import KincalInterrupt, _on_main_thread


__all__ = ["Sensor", "SimulatedCalibration", "check", "simulate", "with_sensors"]


class Sensor:
    """Base class of a sensor written in Python.

    ``predict(params, position, rotation, jacobians)`` gets the sensor's parameter values
    (in the order of ``parameters``) and the pose (``position`` (3,) mm, ``rotation`` (3, 3):
    x_base = rotation @ x_platform + position) and returns (reading (num_readings,),
    J_pose (num_readings, 6), J_params (num_readings, num_parameters)); the Jacobians may be
    None when ``jacobians`` is False. J_pose is with respect to the perturbation
    [dt; dw]: position + dt, expm([dw]x) @ rotation (docs/theory.md)."""

    type: str = "python-sensor"

    def __init__(
        self,
        name: str,
        reading_names: Sequence[str],
        reading_units: Sequence[str],
        parameters: Sequence[Tuple[str, float, str]],
        position_reading_index: int = -1,
    ) -> None:
        self.name = name
        self.reading_names = list(reading_names)
        self.reading_units = list(reading_units)
        self.parameters = [tuple(p) for p in parameters]
        self.position_reading_index = position_reading_index

    def predict(
        self, params: np.ndarray, position: np.ndarray, rotation: np.ndarray, jacobians: bool
    ) -> Tuple[np.ndarray, Optional[np.ndarray], Optional[np.ndarray]]:
        """The readings at the pose and, when ``jacobians``, their Jacobians."""
        raise NotImplementedError("a Sensor subclass implements predict")


def with_sensors(model: "_kincal.Model", sensors: List[Sensor]) -> "_kincal.Model":
    """``model``'s mechanism (values, free mask, actuator ranges) with ``sensors`` instead of
    its own; the sensors' parameters are free."""
    return _kincal._with_sensors(model, sensors)


def check(model: "_kincal.Model", seed: int = 1) -> Dict[str, float]:
    """The finite-difference checks of the built-in sensors (central differences, step
    1e-6) on ``model``'s sensors and on its residual Jacobian, at a simulated configuration:
    returns the worst relative errors; raises AssertionError when one exceeds 1e-6."""
    result: Dict[str, float] = dict(_kincal._check_sensors(model, seed))
    bad = {k: v for k, v in result.items() if k != "tolerance" and not v <= result["tolerance"]}
    if bad:
        raise AssertionError(f"Jacobians differ from finite differences: {bad}")
    return result


@dataclass
class SimulatedCalibration:
    """A simulated calibration of a model: the estimate, the truth and the data."""

    termination: str
    message: str
    iterations: int
    estimate: np.ndarray
    truth: np.ndarray
    nominal: np.ndarray
    free_indices: List[int]
    actuators: np.ndarray
    readings: np.ndarray
    parameter_rms_error_mm: float
    parameter_rms_error_rad: float


def simulate(
    model: "_kincal.Model",
    poses: int = 30,
    noise_mm: float = 0.0,
    noise_rad: float = 0.0,
    seed: int = 1,
    solver: str = "lm",
) -> SimulatedCalibration:
    """A simulated calibration (as ``kincal simulate``: errors of 5 mm and 0.01 rad on the
    free parameters, U[-noise, noise] on the readings) of any model, Python sensors
    included, solved in this process. Ctrl-C raises KincalInterrupt."""
    d = _kincal._simulate_direct(model, poses, noise_mm, noise_rad, seed, solver, _on_main_thread())
    interrupted = d.pop("interrupted")
    result = SimulatedCalibration(**d)
    if interrupted:
        raise KincalInterrupt("simulated calibration interrupted", result)
    return result
