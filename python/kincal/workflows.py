"""calibrate and validate: the library's workflows (framework/workflows/) called directly,
with typed keyword arguments. No command line is built and no file is written to call them:
a Model and Measurements go in as they are in memory (a file name is read by the library's
own reader). The report is the program's JSON for the same inputs (``to_dict()``).

A misspelt keyword is a TypeError, and ``mypy --strict`` finds it before the script runs
(the signatures below are the type stubs).
"""

from __future__ import annotations

import json as _json
import os
import threading
from typing import List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _kincal
from ._commands import KincalError, KincalInterrupt
from ._reports import Report
from .measurements import Measurements

PathLike = Union[str, "os.PathLike[str]"]
ModelArg = Union[PathLike, "_kincal.Model"]
DataArg = Union[PathLike, Measurements]

DEFAULT_RCOND = 1e-6
"""calibrate's numerical rank threshold (the program's --rcond default)."""


def _model(model: ModelArg) -> Tuple["_kincal.Model", str]:
    """The Model, and its file's path when it came as one ("" otherwise)."""
    if isinstance(model, _kincal.Model):
        return model, ""
    if isinstance(model, (str, os.PathLike)):
        path = os.fspath(model)
        try:
            return _kincal.Model.load(path), path
        except ValueError as e:
            raise KincalError(str(e)) from None
    raise TypeError(f"model: expected a file name or a kincal.Model, got {type(model).__name__}")


def _columns(names: List[str], wanted: List[str], values: np.ndarray, what: str) -> np.ndarray:
    """``values``' columns in the order of ``wanted`` (a model's names), found by name."""
    if names == wanted:
        return values
    missing = [n for n in wanted if n not in names]
    if missing:
        raise KincalError(f"data: no {what} column '{missing[0]}' (the model's {what}s are "
                          f"{', '.join(wanted)}; the measurements have {', '.join(names)})")
    return values[:, [names.index(n) for n in wanted]]


def _data(data: DataArg, model: "_kincal.Model") -> Tuple[Optional[str], object, object]:
    """(path, None, None) for a file, (None, actuators, readings) in the model's column order
    for Measurements."""
    if isinstance(data, Measurements):
        a = _columns(data.actuator_names, list(model.actuator_names), data.actuators, "actuator")
        r = _columns(data.reading_names, list(model.reading_names), data.readings, "reading")
        return None, a, r
    if isinstance(data, (str, os.PathLike)):
        return os.fspath(data), None, None
    raise TypeError(f"data: expected a file name or kincal.Measurements, got {type(data).__name__}")


def _path(value: Optional[PathLike]) -> str:
    return "" if value is None else os.fspath(value)


def _messages(command: str, notes: List[str]) -> str:
    return "".join(f"kincal {command}: note: {n}\n" for n in notes)


def calibrate(
    model: ModelArg,
    data: DataArg,
    *,
    solver: str = "lm",
    max_iterations: int = 200,
    solver_option: Optional[Mapping[str, object]] = None,
    loss: Optional[str] = None,
    free: Sequence[str] = (),
    fix: Sequence[str] = (),
    prior_std: Union[str, Sequence[str], None] = None,
    noise_std: Optional[str] = None,
    folds: int = 0,
    starts: int = 1,
    seed: int = 1,
    rcond: float = DEFAULT_RCOND,
    allow_rank_deficient: bool = False,
    formulation: Optional[str] = None,
    skip_bad_rows: bool = False,
    threads: int = 0,
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
) -> Report:
    """Calibrates ``model`` (a Model or a model file) from ``data`` (Measurements or a
    measurement file): the calibrate workflow, as ``kincal calibrate`` runs it.

    ``solver`` names a backend (``kincal.solvers()``) and ``solver_option`` its settings
    (``{"linear_solver": "dense_qr"}``); ``loss`` a robust loss (``"huber:0.02"``); ``free``
    then ``fix`` are glob patterns applied to a copy of the model; ``prior_std`` priors per
    unit or pattern (``"2.887mm,0.0058rad"``, ``["leg*.base.z=0.5mm"]``); ``noise_std`` the
    readings' noise per unit (``"0.0007mm"``); ``folds`` K-fold cross-validation; ``starts``
    several starting values drawn from ``seed``; ``allow_rank_deficient`` fixes what the data
    cannot determine instead of stopping; ``out``, ``json`` and ``html`` write the
    calibrated model and the reports (checked before the solve, written whole after it).

    Returns the report (``to_dict()`` is the program's JSON) with ``report.text`` (the text
    report), ``report.notes`` (what a user should read) and ``report.calibrated_model`` (a
    Model at the estimate, or None when the solver reached no solution, a status in
    ``report.termination``). Bad input is ``KincalError``; Ctrl-C stops the solve at its best
    point and raises ``KincalInterrupt`` carrying the report."""
    m, model_path = _model(model)
    data_path, actuators, readings = _data(data, m)
    specs = [prior_std] if isinstance(prior_std, str) else list(prior_std or [])
    inputs = [p for p in (model_path, data_path) if p]
    try:
        answer = _kincal._calibrate(
            m, data_path, actuators, readings, solver, max_iterations,
            {str(k): str(v) for k, v in (solver_option or {}).items()}, loss or "", list(free),
            list(fix), specs, noise_std or "", folds, starts, seed, rcond, allow_rank_deficient,
            formulation or "", skip_bad_rows, threads, _path(out), _path(json), _path(html),
            model_path, inputs, threading.current_thread() is threading.main_thread())
    except ValueError as e:
        raise KincalError(str(e)) from None
    report = Report(_json.loads(answer["report"]))
    report.__dict__["text"] = answer["text"]
    report.__dict__["notes"] = list(answer["notes"])
    report.__dict__["messages"] = _messages("calibrate", answer["notes"])
    report.__dict__["calibrated_model"] = answer["calibrated_model"]
    if answer["interrupted"]:
        raise KincalInterrupt("kincal.calibrate interrupted", report)
    return report


def validate(
    model: ModelArg,
    data: DataArg,
    *,
    report: Union[PathLike, Report, None] = None,
    before: Optional[ModelArg] = None,
    noise_std: Optional[str] = None,
    skip_bad_rows: bool = False,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
) -> Report:
    """Checks a calibrated ``model`` on held-out ``data``: the validate workflow, as
    ``kincal validate`` runs it. ``report`` is the calibration's report (a file, or the
    Report ``calibrate`` returned): its noise and the parameters' uncertainty predict the
    residuals; ``before`` the model the calibration started from (default with a report: its
    nominal values), for the position error before; ``noise_std`` replaces the predicted
    noise; ``json`` and ``html`` write the result. Returns its report, with ``text`` and
    ``notes``."""
    m, model_path = _model(model)
    data_path, actuators, readings = _data(data, m)
    inputs = [p for p in (model_path, data_path) if p]
    report_json: Optional[str] = None
    report_name = ""
    if isinstance(report, Report):
        report_json = _json.dumps(report.to_dict())
        report_name = "the calibration report"
    elif report is not None:
        report_name = os.fspath(report)
        inputs.append(report_name)
        try:
            with open(report_name, encoding="utf-8") as f:
                report_json = f.read()
        except OSError as e:
            raise KincalError(f"{report_name}: cannot read the calibration report ({e.strerror})") from None
    before_model: Optional["_kincal.Model"] = None
    before_name = ""
    if before is not None:
        before_model, before_name = _model(before)
        if before_name:
            inputs.append(before_name)
        else:
            before_name = before_model.source or "the model before calibration"
    try:
        answer = _kincal._validate(
            m, data_path, actuators, readings, report_json, report_name, before_model, before_name,
            noise_std or "", skip_bad_rows, _path(json), _path(html), model_path, inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    result = Report(_json.loads(answer["report"]))
    result.__dict__["text"] = answer["text"]
    result.__dict__["notes"] = list(answer["notes"])
    result.__dict__["messages"] = _messages("validate", answer["notes"])
    return result
