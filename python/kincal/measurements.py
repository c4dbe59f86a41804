"""Measurements as numpy arrays, read and written in kincal's CSV format (the format of
``kincal calibrate --data``; docs/calibrating-a-machine.md)."""

from __future__ import annotations

import os
from dataclasses import dataclass, field, fields
from typing import Any, List, Optional, Tuple, Union

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

    def __post_init__(self) -> None:
        self._check()

    def __setstate__(self, state: Any) -> None:
        """Unpickling: the state comes from elsewhere (a file, a socket) and is checked as a
        measurement file's content is, never taken as it is."""
        expected = {f.name for f in fields(self)}
        if not isinstance(state, dict) or set(state) != expected:
            raise ValueError(
                "kincal.Measurements pickle: expected a state with the fields " + ", ".join(sorted(expected))
            )
        self.__dict__.update(state)
        self._check()

    def _check(self) -> None:
        """ValueError unless this could be a measurement file kincal reads back: column names
        of the name policy (docs/reliability.md, "Names"), none twice, one per column,
        finite actuator values, readings finite or NaN (not taken)."""
        for name in ("actuator_names", "reading_names", "notices"):
            value = getattr(self, name)
            if not isinstance(value, (list, tuple)) or not all(isinstance(s, str) for s in value):
                raise ValueError(f"{name}: expected a list of strings")
            setattr(self, name, list(value))
        _kincal.check_measurements(self.actuators, self.readings, self.actuator_names, self.reading_names)

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
        """Writes the file (the column names are this object's) as the program writes its
        files: to a temporary file renamed over ``path``, so that it is old or new, whole.
        ValueError, writing nothing, for a column name kincal would not read back (the name
        policy, docs/reliability.md), a value a measurement file cannot hold, or a path the
        program would not write (a directory, a read-only file)."""
        _kincal.write_measurements(
            os.fspath(path), self.actuators, self.readings, self.actuator_names, self.reading_names, comment
        )
