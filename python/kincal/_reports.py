"""Reports: the JSON documents of kincal's commands, with numpy arrays for their numbers.

A report's fields are the keys of the command's JSON report (docs/*.md describe them);
``to_dict()`` returns that JSON exactly as the program writes it.
"""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, Iterator, List

import numpy as np


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _numbers(values: List[Any]) -> bool:
    return bool(values) and all(v is None or _is_number(v) for v in values)


def convert(value: Any) -> Any:
    """A JSON value as Python sees it in a report: numbers in lists become float64 arrays
    (null becomes NaN), lists of such lists 2-D arrays, objects Reports, lists of objects
    Tables; anything else is returned as it is."""
    if isinstance(value, dict):
        return Report(value)
    if isinstance(value, list):
        if _numbers(value):
            return np.array([np.nan if v is None else v for v in value], dtype=np.float64)
        if value and all(isinstance(v, list) and _numbers(v) for v in value):
            if len({len(v) for v in value}) == 1:
                return np.array(
                    [[np.nan if x is None else x for x in v] for v in value], dtype=np.float64
                )
        if value and all(isinstance(v, dict) for v in value):
            return Table(value)
    return value


class Report:
    """One JSON object of a report. ``report.field`` converts as ``convert`` does;
    ``report["field"]`` gives the raw JSON value; ``to_dict()`` the whole document."""

    def __init__(self, document: Dict[str, Any]) -> None:
        self._doc = document

    def __getattr__(self, name: str) -> Any:
        doc = self.__dict__.get("_doc")
        if doc is None or name not in doc:
            raise AttributeError(f"report has no field '{name}'")
        return convert(doc[name])

    def __getitem__(self, name: str) -> Any:
        return self._doc[name]

    def __contains__(self, name: object) -> bool:
        return name in self._doc

    def __iter__(self) -> Iterator[str]:
        return iter(self._doc)

    def keys(self) -> List[str]:
        """The fields, in the JSON's order."""
        return list(self._doc)

    def covariance(self) -> np.ndarray:
        """The estimated parameters' covariance (n x n, in their units, in the order of
        ``parameters``), rebuilt from the report's standard deviations and correlation
        matrix: cov_ij = std_i corr_ij std_j. NaN where the report has no std (a parameter
        the data cannot determine). ``ValueError`` for a report without both (only a
        calibration report has them)."""
        if "parameters" not in self._doc or "correlation" not in self._doc:
            raise ValueError("covariance(): this report has no 'parameters' and 'correlation'; "
                             "expected a calibration report (kincal.calibrate)")
        std = np.array([np.nan if p.get("std") is None else p["std"]
                        for p in self._doc["parameters"]], dtype=np.float64)
        corr = np.array([[np.nan if x is None else x for x in row]
                         for row in self._doc["correlation"]], dtype=np.float64)
        if corr.shape != (std.size, std.size):
            raise ValueError(f"covariance(): correlation is {corr.shape}, expected "
                             f"({std.size}, {std.size}) for {std.size} parameters")
        return std[:, None] * corr * std[None, :]

    def to_dict(self) -> Dict[str, Any]:
        """A copy of the JSON document, exactly as the program writes it."""
        return copy.deepcopy(self._doc)

    def to_json(self) -> str:
        """The document as JSON text (2-space indent)."""
        return json.dumps(self._doc, indent=2)

    def __repr__(self) -> str:
        kind = self._doc.get("format", "object")
        return f"<kincal.Report {kind}: {', '.join(list(self._doc)[:6])}...>"


class Table:
    """A JSON list of objects (a report's parameters, trace, residuals): ``table.column``
    is that field over the rows, a float64 array when it holds numbers (NaN for null),
    else a list; ``table[i]`` is row i as a Report."""

    def __init__(self, rows: List[Dict[str, Any]]) -> None:
        self._rows = rows

    def __len__(self) -> int:
        return len(self._rows)

    def __getitem__(self, i: int) -> Report:
        return Report(self._rows[i])

    def columns(self) -> List[str]:
        """The fields of the rows, in first-seen order."""
        seen: Dict[str, None] = {}
        for row in self._rows:
            for key in row:
                seen.setdefault(key, None)
        return list(seen)

    def __getattr__(self, name: str) -> Any:
        rows = self.__dict__.get("_rows")
        if rows is None or not rows or not any(name in r for r in rows):
            raise AttributeError(f"table has no column '{name}'")
        values = [r.get(name) for r in rows]
        if all(v is None or _is_number(v) for v in values):
            return np.array([np.nan if v is None else v for v in values], dtype=np.float64)
        return values

    def to_list(self) -> List[Dict[str, Any]]:
        """A copy of the rows as JSON objects."""
        return copy.deepcopy(self._rows)

    def __repr__(self) -> str:
        return f"<kincal.Table {len(self._rows)} rows: {', '.join(self.columns())}>"
