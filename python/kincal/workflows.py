"""simulate, calibrate, validate, observability, compare and design, and the model formats
(export, model_from_urdf): the library's workflows (framework/workflows/) called directly,
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
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import _kincal
from ._errors import KincalError, KincalInterrupt
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


def _report(command: str, answer: Dict[str, Any]) -> Report:
    """A workflow's answer as a Report: its JSON, with ``text`` and, when it has notes,
    ``notes`` and ``messages`` (the lines the program prints on stderr)."""
    report = Report(_json.loads(answer["report"]))
    report.__dict__["text"] = answer["text"]
    if "notes" in answer:
        report.__dict__["notes"] = list(answer["notes"])
        report.__dict__["messages"] = _messages(command, answer["notes"])
    return report


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
    tolerance_priors: str = "auto",
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
    images: Optional[PathLike] = None,
    steps: Sequence[str] = (),
    target: Optional[str] = None,
) -> Report:
    """Calibrates ``model`` (a Model or a model file) from ``data`` (Measurements or a
    measurement file): the calibrate workflow, as ``kincal calibrate`` runs it.

    ``solver`` names a backend (``kincal.solvers()``) and ``solver_option`` its settings
    (``{"linear_solver": "dense_qr"}``); ``loss`` a robust loss (``"huber:0.02"``); ``free``
    then ``fix`` are glob patterns applied to a copy of the model; ``prior_std`` priors per
    unit or pattern (``"2.887mm,0.0058rad"``, ``["leg*.base.z=0.5mm"]``); ``noise_std`` the
    readings' noise per unit (``"0.0007mm"``); ``folds`` K-fold cross-validation; ``starts``
    several starting values drawn from ``seed``; ``allow_rank_deficient`` fixes what the data
    cannot determine instead of stopping; ``tolerance_priors`` priors from the stated
    tolerances (``"auto"``: with a camera, when no prior is given; ``"on"``; ``"off"``);
    ``out``, ``json`` and ``html`` write the
    calibrated model and the reports (checked before the solve, written whole after it). With a
    camera, the page draws each view on its image, named by the data file's ``image`` column
    (as ``kincal.detect`` writes it) relative to ``images`` (default: the data file's folder).
    ``steps`` calibrates in steps, as ``--step``: each a comma-separated list of glob patterns
    (``["camera.*"]``) solved for alone first, in order; the full solve starts where they end.
    ``target`` is the pose accuracy needed (``"0.1mm"`` or ``"0.1mm,0.05deg"``, as
    ``--target``): the report's ``target`` says whether the predicted pose error meets it.

    Returns the report (``to_dict()`` is the program's JSON) with ``report.text`` (the text
    report), ``report.notes`` (what a user should read) and ``report.calibrated_model`` (a
    Model at the estimate, or None when the solver reached no solution, a status in
    ``report.termination``; ``report.solved`` says which). Bad input is ``KincalError``; Ctrl-C stops the solve at its best
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
            model_path, inputs, threading.current_thread() is threading.main_thread(),
            tolerance_priors, _path(images), list(steps), target or "")
    except ValueError as e:
        raise KincalError(str(e)) from None
    report = _report("calibrate", answer)
    report.__dict__["calibrated_model"] = answer["calibrated_model"]
    report.__dict__["solved"] = bool(answer["solved"])
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
    target: Optional[str] = None,
) -> Report:
    """Checks a calibrated ``model`` on held-out ``data``: the validate workflow, as
    ``kincal validate`` runs it. ``report`` is the calibration's report (a file, or the
    Report ``calibrate`` returned): its noise and the parameters' uncertainty predict the
    residuals; ``before`` the model the calibration started from (default with a report: its
    nominal values), for the position error before; ``noise_std`` replaces the predicted
    noise; ``target`` the pose accuracy needed (``"0.1mm"``, as ``--target``), judged against
    the measured error; ``json`` and ``html`` write the result. Returns its report, with
    ``text`` and ``notes``."""
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
            noise_std or "", skip_bad_rows, _path(json), _path(html), model_path, inputs,
            target or "")
    except ValueError as e:
        raise KincalError(str(e)) from None
    result = _report("validate", answer)
    return result


def observability(
    model: ModelArg,
    data: Optional[DataArg] = None,
    *,
    poses: Optional[int] = None,
    seed: int = 1,
    config_range: Optional[str] = None,
    rcond: float = DEFAULT_RCOND,
    free: Sequence[str] = (),
    fix: Sequence[str] = (),
    prior_std: Union[str, Sequence[str], None] = None,
    noise_std: Optional[str] = None,
    skip_bad_rows: bool = False,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
) -> Report:
    """How well ``model``'s free parameters are determined, before any solving: from the
    configurations of ``data`` (Measurements or a file; their readings are not used), or from
    ``poses`` random ones drawn from ``seed`` within ``config_range`` (``"20mm,0.5rad"``;
    default each actuator's range). ``free``, ``fix``, ``prior_std`` and ``noise_std`` as in
    ``calibrate``. The observability workflow, as ``kincal observability`` runs it: returns
    its report (rank, condition number, per-parameter figures) with ``report.text``."""
    m, model_path = _model(model)
    if data is not None:
        data_path, actuators, readings = _data(data, m)
    else:
        data_path, actuators, readings = None, None, None
    specs = [prior_std] if isinstance(prior_std, str) else list(prior_std or [])
    inputs = [p for p in (model_path, data_path) if p]
    try:
        answer = _kincal._observability(
            m, data_path, actuators, readings, 0 if poses is None else poses, seed, rcond,
            config_range or "", list(free), list(fix), specs, noise_std or "", skip_bad_rows,
            _path(json), _path(html), model_path, inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    return _report("", answer)


def compare(
    truth: ModelArg,
    model: ModelArg,
    *,
    data: Optional[DataArg] = None,
    poses: int = 200,
    seed: int = 1,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
) -> Report:
    """Compares ``model`` (a calibration's result) with the ``truth`` (a simulation's truth
    model): each parameter's error, and the pose error over the configurations of ``data``
    (its actuator columns) or ``poses`` drawn in the truth's workspace from ``seed``. The
    compare workflow, as ``kincal compare`` runs it: returns its report with ``text``."""
    t, truth_path = _model(truth)
    m, model_path = _model(model)
    data_path: Optional[str] = None
    actuators: object = None
    if data is not None:
        data_path, actuators, _ = _data(data, m)
    inputs = [p for p in (truth_path, model_path, data_path) if p]
    try:
        answer = _kincal._compare(t, m, data_path, actuators, poses, seed, _path(json), _path(html),
                                  truth_path, model_path, inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    return _report("", answer)


Quantity = Union[str, float]
"""A quantity per unit as text ("0.05mm,1e-4rad"; a bare number is mm), or a number (mm)."""


def _quantity(value: Optional[Quantity]) -> Optional[str]:
    return None if value is None else value if isinstance(value, str) else repr(float(value))


def simulate(
    *,
    preset: Optional[str] = None,
    model: Optional[ModelArg] = None,
    case: Optional[int] = None,
    poses: Optional[int] = None,
    noise_half_width: Optional[Quantity] = None,
    noise_std: Optional[Quantity] = None,
    param_error: Quantity = "5mm,0.01rad",
    config_range: Optional[Quantity] = None,
    seed: int = 1,
    validation: int = 200,
    solver: str = "lm",
    max_iterations: int = 200,
    solver_option: Optional[Mapping[str, object]] = None,
    threads: int = 0,
    formulation: Optional[str] = None,
    design: Optional[str] = None,
    design_candidates: int = 10000,
    prior_std: Union[str, Sequence[str], None] = None,
    configs: Optional[DataArg] = None,
    truth: Optional[ModelArg] = None,
    write_data: Optional[PathLike] = None,
    allow_rank_deficient: bool = False,
    starts: int = 1,
    json: Optional[PathLike] = None,
    trace: Optional[PathLike] = None,
) -> Report:
    """One simulated calibration: the simulate workflow, as ``kincal simulate`` runs it, e.g.
    ``simulate(case=3, seed=7)``. The model is a ``preset`` (default cube-hexapod) or a
    ``model`` (Model or file); ``case`` the paper's Table 2 case (it sets ``poses`` and the
    noise); ``noise_half_width`` (U[-a, a]) or ``noise_std`` the readings' noise per unit;
    ``param_error`` the true parameters' spread around the nominal ones (or ``truth``, a
    model); ``configs`` the configurations to simulate (Measurements or a file) instead of
    ``poses`` random ones, or ``design`` a criterion (D, A, E, I) to choose them; solver
    settings as in ``calibrate``; ``write_data`` writes the readings and the true model
    beside them, ``json`` and ``trace`` the reports. Returns the report (``to_dict()`` is the
    program's JSON) with ``text`` and ``notes``; Ctrl-C stops the solve at its best point and
    raises ``KincalInterrupt`` carrying the report."""
    if preset is not None and model is not None:
        raise KincalError("give either preset or model, not both")
    inputs: List[str] = []
    if model is not None:
        m, model_path = _model(model)
        model_name = model_path or m.source
        if model_path:
            inputs.append(model_path)
    else:
        model_name = preset or "cube-hexapod"
        try:
            m = _kincal.Model.preset(model_name)
        except ValueError as e:
            raise KincalError(f"preset: {e}") from None
    configs_path: Optional[str] = None
    configs_a: object = None
    configs_r: object = None
    if configs is not None:
        configs_path, configs_a, configs_r = _data(configs, m)
        if configs_path:
            inputs.append(configs_path)
    truth_model: Optional["_kincal.Model"] = None
    truth_name = ""
    if truth is not None:
        truth_model, truth_name = _model(truth)
        if truth_name:
            inputs.append(truth_name)
        else:
            truth_name = truth_model.source
    specs = [prior_std] if isinstance(prior_std, str) else list(prior_std or [])
    try:
        answer = _kincal._simulate(
            m, model_name, case or 0, poses, _quantity(noise_half_width), _quantity(noise_std),
            _quantity(param_error) or "", _quantity(config_range), seed, validation, solver,
            max_iterations, {str(k): str(v) for k, v in (solver_option or {}).items()}, threads,
            formulation or "", design or "", design_candidates, specs, configs_path, configs_a,
            configs_r, truth_model, truth_name, _path(write_data), allow_rank_deficient, starts,
            _path(json), _path(trace), inputs, threading.current_thread() is threading.main_thread())
    except ValueError as e:
        raise KincalError(str(e)) from None
    report = _report("simulate", answer)
    report.__dict__["solved"] = bool(answer["solved"])
    if answer["interrupted"]:
        raise KincalInterrupt("kincal.simulate interrupted", report)
    return report


def design(
    model: ModelArg,
    *,
    count: int,
    criterion: str = "D",
    candidates: int = 10000,
    seed: int = 1,
    singularity_margin: float = 0.5,
    orientation_length: Optional[Quantity] = None,
    config_range: Optional[Quantity] = None,
    free: Sequence[str] = (),
    fix: Sequence[str] = (),
    prior_std: Union[str, Sequence[str], None] = None,
    noise_std: Optional[Quantity] = None,
    existing: Optional[DataArg] = None,
    bound: bool = False,
    within: Union[PathLike, npt.ArrayLike, None] = None,
    candidate_configurations: Union[PathLike, npt.ArrayLike, None] = None,
    centre: Optional[npt.ArrayLike] = None,
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
    html: Optional[PathLike] = None,
    target: Optional[str] = None,
) -> Report:
    """Chooses ``count`` configurations worth measuring: the design workflow, as ``kincal
    design`` runs it. ``criterion`` D, A, E or I; ``candidates`` random candidates drawn in
    the actuators' box (``config_range``, default each actuator's range) from ``seed``, or in
    the range of the configurations ``within`` (rows x actuators, or a CSV file of them: where
    the robot was measured, as ``--within``), or the given ``candidate_configurations`` (rows
    or a file, ``--candidates-file``),
    or around the configuration ``centre`` (``--centre``) instead of home; an arm whose joints
    all have limits (a URDF's) is drawn within them by default, and every box within them;
    ``noise_std`` the readings' noise (default the model's reading_std, which it must then
    state); ``existing`` data already measured (Measurements or a file); ``bound`` also bounds
    how good any design can be; ``target`` the pose accuracy needed (``"0.1mm"``, as
    ``--target``), judged against the design's predicted error. ``report.configurations`` is a Measurements template of the
    chosen configurations (readings NaN); ``out`` writes it as the program does, ``json`` and
    ``html`` the reports. Ctrl-C stops the work with the best design so far (marked partial)
    and raises ``KincalInterrupt`` carrying the report."""
    m, model_path = _model(model)
    inputs = [model_path] if model_path else []
    existing_path: Optional[str] = None
    existing_a: object = None
    existing_r: object = None
    if existing is not None:
        existing_path, existing_a, existing_r = _data(existing, m)
        if existing_path:
            inputs.append(existing_path)
    specs = [prior_std] if isinstance(prior_std, str) else list(prior_std or [])

    def configurations(value: Union[PathLike, npt.ArrayLike, None]) -> object:
        if isinstance(value, (str, os.PathLike)):
            inputs.append(os.fspath(value))
            return os.fspath(value)  # read by the library, as the program reads the file
        return None if value is None else np.asarray(value, dtype=float)

    within_rows, candidate_rows = configurations(within), configurations(candidate_configurations)
    try:
        answer = _kincal._design(
            m, count, criterion, candidates, seed, singularity_margin,
            _quantity(orientation_length) or "", _quantity(config_range) or "", list(free),
            list(fix), specs, _quantity(noise_std) or "", existing_path, existing_a, existing_r,
            bound, _path(out), _path(json), _path(html), model_path, inputs,
            threading.current_thread() is threading.main_thread(),
            within_rows, candidate_rows,
            None if centre is None else np.asarray(centre, dtype=float), target or "")
    except ValueError as e:
        raise KincalError(str(e)) from None
    if answer["stopped_before_design"]:
        raise KincalInterrupt("kincal.design interrupted while drawing candidates: nothing chosen",
                              None)
    report = _report("design", answer)
    report.__dict__["configurations"] = Measurements.empty_readings(answer["configurations"], m)
    if answer["interrupted"] or report["partial"]:
        raise KincalInterrupt("kincal.design interrupted", report)
    return report


def verify(report: PathLike, model: Optional[PathLike] = None,
           json: Optional[PathLike] = None) -> Dict[str, Any]:
    """Whether the calibrated model file ``model`` (default: the file the report names) is the
    one the calibration report ``report`` was written with, as ``kincal verify``: a dict with
    ``match`` (bool), ``model``, ``sha256``, ``expected_sha256`` and, when they differ,
    ``message``; ``json`` writes the verdict. Called in the library
    (framework/workflows/verify.hpp)."""
    try:
        return dict(_kincal._verify(os.fspath(report), "" if model is None else os.fspath(model),
                                    "" if json is None else os.fspath(json)))
    except ValueError as e:
        raise KincalError(str(e)) from None


def export(model: ModelArg, format: str, out: Optional[PathLike] = None) -> str:
    """The calibrated model for a controller (``format`` urdf, csv, json, or one a plug-in
    registers), as ``kincal export``: returns the text, and writes it to ``out`` when given
    (never over the model file). Called in the library: a Model in memory is named by its
    source and the SHA-256 of its JSON (as ``Model.to_json`` writes it), a model file by its
    path and the SHA-256 of its bytes."""
    m, path = _model(model)
    try:
        return str(_kincal._export(m, format, path, "" if out is None else os.fspath(out)))
    except ValueError as e:
        raise KincalError(str(e)) from None


def _values_text(values: Union[str, Sequence[float], None]) -> str:
    """A configuration or pose as the program's text: a string as given (units allowed where
    the program takes them), numbers written exactly (repr round-trips)."""
    if values is None:
        return ""
    if isinstance(values, str):
        return values
    return ",".join(repr(float(v)) for v in values)


def _kinematics(command: str, answer: Dict[str, Any]) -> Report:
    report = _report(command, answer)
    if "notes" not in answer:
        report.__dict__["notes"] = []
        report.__dict__["messages"] = ""
    return report


def fk(
    model: ModelArg,
    actuators: Union[str, Sequence[float], None] = None,
    *,
    data: Optional[PathLike] = None,
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
) -> Report:
    """Forward kinematics at the model's values, as ``kincal fk``: of one configuration
    (``actuators``: numbers in the actuators' units, or the program's text with a unit after
    each value, ``"90deg,-45deg,..."``), or of each row of the CSV file ``data`` (its actuator
    columns; unit suffixes such as ``_deg`` allowed). Returns the program's JSON as a Report
    (one result: ``pose`` in mm and degrees, ``readings``; a table: ``rows`` with each one's
    ``status``, and ``failed``), with ``text`` (what the program prints; a table's CSV) and
    ``notes``. ``out`` writes a table's CSV, ``json`` the JSON. A configuration that cannot be
    computed raises KincalError; a table's row that cannot is a status."""
    m, model_path = _model(model)
    inputs = [p for p in (model_path, _path(data)) if p]
    try:
        answer = _kincal._fk(m, model_path, _values_text(actuators), _path(data), _path(out),
                             _path(json), inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    return _kinematics("fk", answer)


def ik(
    model: ModelArg,
    pose: Union[str, Sequence[float], None] = None,
    *,
    data: Optional[PathLike] = None,
    near: Optional[Sequence[float]] = None,
    seeds: bool = False,
    all: bool = False,
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
) -> Report:
    """Inverse kinematics at the model's values, as ``kincal ik``: at one ``pose`` (x, y, z in
    mm and rx, ry, rz in degrees, Z-Y-X: R = Rz(rz) Ry(ry) Rx(rx)), or at each row of the CSV
    file ``data`` (columns x_mm, y_mm, z_mm, rx_deg, ry_deg, rz_deg). ``near`` (actuator values)
    picks the solution nearest them, a serial arm's branch; ``seeds`` starts each row of
    ``data`` from its own actuator columns; ``all`` lists every distinct solution found at
    ``pose``, nearest first (``solutions``). Returns the program's JSON as a Report, with
    ``text`` and ``notes``, as ``fk``."""
    m, model_path = _model(model)
    inputs = [p for p in (model_path, _path(data)) if p]
    try:
        answer = _kincal._ik(m, model_path, _values_text(pose), _path(data),
                             [float(v) for v in near] if near is not None else [], bool(seeds),
                             bool(all), _path(out), _path(json), inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    return _kinematics("ik", answer)


def detect(
    target: str,
    out: PathLike,
    *,
    poses: Optional[PathLike] = None,
    images: Optional[PathLike] = None,
    camera: str = "camera",
    gate_px: float = 2.0,
    start_model: Optional[PathLike] = None,
    mounting: str = "eye-to-hand",
    mechanism: Optional[ModelArg] = None,
    intrinsics: Optional[Sequence[float]] = None,
    json: Optional[PathLike] = None,
) -> Report:
    """Finds a calibration target in images, as ``kincal detect``: ``target`` as the program
    takes it (``"chessboard:6x8:20mm"``, ``"charuco:7x5:36.195mm:18.256mm:DICT_6X6_250"``...),
    ``poses`` a CSV with an ``image`` column and the configuration's columns (images relative to
    it or to ``images``), or ``images`` a folder alone. Writes the measurement file ``out`` (one
    row per image with the target), and ``start_model`` (OpenCV's intrinsics or ``intrinsics``
    = (fx, fy, cx, cy) px, the hand-eye mounts; the mechanism ``mechanism``'s, or flange-pose)
    and ``json`` when given. The Report holds each image's fate (``images``), ``found``,
    ``total``, and ``text``, ``csv`` and ``start_error`` (why no starting model, or ""). Needs a
    kincal built with OpenCV. Ctrl-C stops between images and raises ``KincalInterrupt`` with
    what was found, which is written."""
    m = _model(mechanism)[0] if mechanism is not None else None
    try:
        answer = _kincal._detect(
            target, _path(poses), _path(images), os.fspath(out), camera, gate_px,
            _path(start_model), mounting, m, [float(v) for v in (intrinsics or [])], _path(json),
            threading.current_thread() is threading.main_thread())
    except ValueError as e:
        raise KincalError(str(e)) from None
    report = Report(_json.loads(answer["report"]))
    report.__dict__["text"] = answer["text"]
    report.__dict__["csv"] = answer["csv"]
    report.__dict__["start_error"] = answer["start_error"]
    if answer["interrupted"]:
        raise KincalInterrupt("kincal.detect interrupted", report)
    return report


def html_report(model: ModelArg, data: DataArg, out: PathLike, **options: Any) -> Report:
    """Calibrates as ``calibrate`` (the same keyword arguments) and writes the HTML report
    to ``out``."""
    return calibrate(model, data, html=out, **options)


def model_from_urdf(
    urdf: PathLike,
    tip: str,
    base: Optional[str] = None,
    sensor: str = "point-tracker",
    point: Optional[Sequence[float]] = None,
    compliance: Optional[str] = None,
    payload_column: bool = False,
    payload_centre: Optional[Sequence[float]] = None,
    frame: Optional[Sequence[float]] = None,
    target: Optional[Sequence[float]] = None,
) -> "_kincal.Model":
    """A model imported from a URDF (the chain from ``base``, default the root link, to
    ``tip``), as ``kincal model --urdf``, every parameter free: ``sensor`` point-tracker or
    pose-tracker, ``point`` the point tracker's target x, y, z (mm) on the tip link.
    ``compliance`` adds joint compliance under gravity (``--compliance``): "auto" (the URDF's
    inertial masses when it has them, else fitted), "urdf" or "fitted"; ``payload_column`` reads
    the payload's mass per row (column ``payload``, kg), ``payload_centre`` its centre of mass
    x, y, z (mm) in the tip link's frame. ``frame`` is the tracker's frame in the arm's base
    coordinates and ``target`` a pose tracker's marker on the tip link, each x, y, z (mm), rx,
    ry, rz (degrees, Z-Y-X), as ``--frame`` and ``--target``. Called in the library
    (models/urdf_io.hpp)."""
    try:
        return _kincal._model_from_urdf(os.fspath(urdf), tip, base or "", sensor,
                                        [float(v) for v in point] if point is not None else [],
                                        compliance or "", payload_column,
                                        [float(v) for v in payload_centre]
                                        if payload_centre is not None else [],
                                        [float(v) for v in frame] if frame is not None else [],
                                        [float(v) for v in target] if target is not None else [])
    except ValueError as e:
        raise KincalError(str(e)) from None


def compensate(
    model: ModelArg,
    targets: PathLike,
    *,
    nominal: Optional[ModelArg] = None,
    near: Optional[Sequence[float]] = None,
    payload: Optional[float] = None,
    tolerance: float = 1e-9,
    out: Optional[PathLike] = None,
    json: Optional[PathLike] = None,
) -> Report:
    """Corrected targets: the commands that make the calibrated ``model`` read what
    ``targets`` (a CSV file) wants, as ``kincal compensate`` computes them, geometry and joint
    deflection under gravity included. ``targets`` holds the wanted readings (the model's
    reading columns) and optionally each row's starting commands; with ``nominal`` it holds
    commands only and the wanted readings are the nominal model's there. ``near`` starts rows
    without commands (default home); ``payload`` (kg) fills a payload column the file lacks.
    ``out`` writes the commands' CSV, ``json`` the summary. Returns the summary as a Report,
    with ``text``, ``commands`` (rows x actuators, NaN where a row failed) and ``statuses``."""
    m, model_path = _model(model)
    targets_path = os.fspath(targets)
    inputs = [p for p in (model_path, targets_path) if p]
    nominal_model: Optional["_kincal.Model"] = None
    if nominal is not None:
        nominal_model, nominal_path = _model(nominal)
        if nominal_path:
            inputs.append(nominal_path)
    try:
        answer = _kincal._compensate(
            m, targets_path, nominal_model, [float(v) for v in near] if near is not None else [],
            None if payload is None else float(payload), float(tolerance), _path(out), _path(json),
            inputs)
    except ValueError as e:
        raise KincalError(str(e)) from None
    result = _report("compensate", answer)
    result.__dict__["commands"] = answer["commands"]
    result.__dict__["statuses"] = list(answer["statuses"])
    return result
