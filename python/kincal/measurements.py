"""Measurements as numpy arrays, read and written in kincal's CSV format (the format of
``kincal calibrate --data``; docs/calibrating-a-machine.md)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import List, Optional, Tuple, Union

import numpy as np

from . import _kincal


@dataclass
class Measurements:
    """One row per measured configuration: ``actuators`` (n, num_actuators) in the
    actuators' units, ``readings`` (n, num_readings) with NaN for a reading not taken, the
    column names, and the notices the reader gave (ignored columns...)."""

    actuators: np.ndarray
    readings: np.ndarray
    actuator_names: List[str]
    reading_names: List[str]
    notices: List[str] = field(default_factory=list)

    @classmethod
    def read(
        cls, path: Union[str, "os.PathLike[str]"], model: "_kincal.Model", allow_no_readings: bool = False
    ) -> "Measurements":
        """Reads a measurement file for ``model`` (unit suffixes converted); ValueError names
        the file and line of anything wrong. ``allow_no_readings``: a design template."""
        a, r, notices = _kincal.read_measurements(os.fspath(path), model, allow_no_readings)
        return cls(a, r, list(model.actuator_names), list(model.reading_names), list(notices))

    @classmethod
    def empty_readings(cls, actuators: np.ndarray, model: "_kincal.Model") -> "Measurements":
        """Configurations with every reading NaN (to be measured, or simulated)."""
        a = np.array(actuators, dtype=np.float64, ndmin=2)
        r = np.full((a.shape[0], len(model.reading_names)), np.nan)
        return cls(a, r, list(model.actuator_names), list(model.reading_names))

    def __len__(self) -> int:
        return int(self.actuators.shape[0])

    def to_csv(self, model: "_kincal.Model", comment: str = "") -> str:
        """The CSV text for ``model``'s columns, at full precision."""
        return str(_kincal.measurements_to_csv(self.actuators, self.readings, model, comment))

    def residuals(
        self, model: "_kincal.Model", values: Optional[np.ndarray] = None
    ) -> Tuple[np.ndarray, np.ndarray, List[str]]:
        """The calibration problem of these measurements for ``model``: the residuals
        (predicted - measured, weighted by the model's reading_std, one per reading, 0 where
        missing) and their Jacobian with respect to the free parameters, at the nominal
        values or ``values`` (one per parameter), and the free parameters' names."""
        r, J, names = _kincal.calibration_residuals(model, self.actuators, self.readings, values)
        return r, J, list(names)

    def write(self, path: Union[str, "os.PathLike[str]"], comment: str = "") -> None:
        """Writes the file (the column names are this object's)."""
        lines = []
        if comment:
            lines += ["# " + line for line in comment.splitlines()]
        lines.append(",".join(self.actuator_names + self.reading_names))
        for a, r in zip(np.asarray(self.actuators), np.asarray(self.readings)):
            values = [repr(float(v)) for v in a] + ["" if np.isnan(v) else repr(float(v)) for v in r]
            lines.append(",".join(values))
        with open(os.fspath(path), "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")
