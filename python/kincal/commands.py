"""simulate, observability, design, compare, export and model_from_urdf: kincal's commands,
run in-process, returning their JSON reports as Report objects (``to_dict()`` is exactly
what ``kincal <command> --json`` writes). Every option of the command is a keyword argument
(see ``kincal._commands``); ``kincal <command> --help`` and the README list them.

calibrate, validate and html_report call the library's workflows directly, with typed
keyword arguments (kincal.workflows); they are re-exported here.
"""

from __future__ import annotations

import os
from typing import Any, Optional

from . import _kincal
from ._commands import (
    OptionValue,
    Workdir,
    data_path,
    json_report,
    model_path,
    option_args,
    run,
    with_text,
)
from ._reports import Report
from .workflows import DataArg, ModelArg, PathLike, calibrate, validate


def simulate(
    *,
    preset: Optional[str] = None,
    model: Any = None,
    case: Optional[int] = None,
    seed: Optional[int] = None,
    solver: Optional[str] = None,
    **options: OptionValue,
) -> Report:
    """One simulated calibration, as ``kincal simulate``: e.g. ``simulate(case=3, seed=7)``.
    ``model`` is a model file or a Model; other options as the command's (``poses=``,
    ``noise=``, ``param_error=``, ``solver_option={...}``, ``write_data=``, ...). The solve
    runs with the GIL released; Ctrl-C stops it at its best point (KincalInterrupt)."""
    with Workdir() as work:
        args = option_args({"preset": preset, "case": case, "seed": seed, "solver": solver})
        if model is not None:
            args += ["--model", model_path(model, work)]
        args += option_args(options)
        report, _, out, err = json_report("simulate", args, work)
        return with_text(report, out, err)


def observability(model: Any, data: Any = None, **options: OptionValue) -> Report:
    """Identifiability of ``model``'s free parameters from ``data`` (or ``poses=M,
    seed=S`` random configurations), as ``kincal observability``."""
    with Workdir() as work:
        args = ["--model", model_path(model, work)]
        if data is not None:
            args += ["--data", data_path(data, model, work)]
        report, _, out, err = json_report("observability", args + option_args(options), work)
        return with_text(report, out, err)


def design(model: Any, *, count: int, **options: OptionValue) -> Report:
    """Chooses ``count`` configurations worth measuring, as ``kincal design`` (options:
    ``noise_std=``, ``criterion=``, ``existing=``, ``bound=True``, ``out=``...). Without
    ``out`` the configurations go to a temporary file, read back as ``report.configurations``
    (a Measurements whose readings are NaN: a template)."""
    from .measurements import Measurements

    with Workdir() as work:
        out_file = options.pop("out", None)
        configs = str(out_file) if out_file is not None else work.file("configs.csv")
        path = model_path(model, work)
        args = ["--model", path, "--poses", str(count), "--out", configs] + option_args(options)
        report, _, out, err = json_report("design", args, work)
        if os.path.exists(configs):
            m = model if isinstance(model, _kincal.Model) else _kincal.Model.load(path)
            report.__dict__["configurations"] = Measurements.read(configs, m, allow_no_readings=True)
        return with_text(report, out, err)


def compare(truth: Any, model: Any, **options: OptionValue) -> Report:
    """Compares a calibrated model with the true one, as ``kincal compare``."""
    with Workdir() as work:
        args = ["--truth", model_path(truth, work, "truth.json"), "--model", model_path(model, work)]
        report, _, out, err = json_report("compare", args + option_args(options), work)
        return with_text(report, out, err)


def export(model: Any, format: str, out: Optional[str] = None) -> str:
    """The calibrated model for a controller (``format`` urdf, csv or json), as
    ``kincal export``: returns the text, and writes it to ``out`` when given."""
    with Workdir() as work:
        target = out if out is not None else work.file("export." + format)
        run("export", ["--model", model_path(model, work), "--format", format, "--out", target])
        with open(target, encoding="utf-8") as f:
            return f.read()


def html_report(model: ModelArg, data: DataArg, out: PathLike, **options: Any) -> Report:
    """Calibrates as ``calibrate`` (the same keyword arguments) and writes the HTML report
    to ``out``."""
    return calibrate(model, data, html=out, **options)


def model_from_urdf(
    urdf: str,
    tip: str,
    base: Optional[str] = None,
    sensor: Optional[str] = None,
    point: Optional[str] = None,
) -> "_kincal.Model":
    """A model imported from a URDF (the chain from ``base`` to ``tip``), as ``kincal model
    --urdf``; ``sensor`` point-tracker or pose-tracker, ``point`` x,y,z on the tip."""
    with Workdir() as work:
        path = work.file("urdf-model.json")
        args = ["--urdf", os.fspath(urdf), "--tip", tip]
        args += option_args({"base": base, "sensor": sensor, "point": point}) + ["--out", path]
        run("model", args)
        return _kincal.Model.load(path)
