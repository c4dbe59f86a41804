"""kincal.run_project: a project file (docs/projects.md) run by the library's workflows, as
``kincal run PROJECT.yaml`` runs it with the program's commands. The file is read by the
library (framework/io/project_file.hpp): variables substituted, paths made relative to the
file's folder. Each step's keys become the keyword arguments of the workflow of the same
name (dashes as underscores); the JSON reports a step writes record the project as the
program's do."""

from __future__ import annotations

import inspect
import json as _json
import os
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

from . import _kincal
from ._errors import KincalError
from .workflows import (
    calibrate,
    compare,
    compensate,
    design,
    detect,
    export,
    fk,
    ik,
    model_from_urdf,
    observability,
    simulate,
    validate,
    verify,
)

PathLike = Union[str, "os.PathLike[str]"]
Option = Tuple[str, List[str], bool, int]  # key, values, is_switch, line

_WORKFLOWS: Dict[str, Callable[..., Any]] = {
    "calibrate": calibrate,
    "compare": compare,
    "compensate": compensate,
    "design": design,
    "detect": detect,
    "export": export,
    "fk": fk,
    "ik": ik,
    "observability": observability,
    "simulate": simulate,
    "validate": validate,
    "verify": verify,
}
# Where a keyword is spelt otherwise than the program's option.
_RENAMED = {("calibrate", "step"): "steps", ("design", "poses"): "count",
            ("design", "candidates-file"): "candidate_configurations", ("detect", "gate"): "gate_px"}
# Keys whose Python keyword takes the number without the unit the program's option carries.
_UNIT_SUFFIX = {("detect", "gate"): "px"}
# The program's progress on stderr: Python prints nothing, so the key has nothing to do.
_DISPLAY_ONLY = {"progress"}
_MODEL_KEYS = ["preset", "urdf", "tip", "base", "sensor", "point", "frame", "target",
               "compliance", "payload-column", "payload-centre", "out", "free", "fix"]


class _StepError(Exception):
    def __init__(self, key: Optional[str], message: str) -> None:
        super().__init__(message)
        self.key = key


def _numbers(key: str, values: List[str]) -> List[float]:
    try:
        return [float(v) for v in _single(key, values).split(",")]
    except ValueError:
        raise _StepError(key, "'%s': expected numbers separated by commas" % values[0]) from None


def _single(key: str, values: List[str]) -> str:
    if len(values) != 1:
        raise _StepError(key, "takes one value, got %d" % len(values))
    return values[0]


def _argument(key: str, values: List[str], is_switch: bool, parameter: inspect.Parameter) -> Any:
    annotation = str(parameter.annotation)
    if is_switch:
        if "bool" not in annotation:
            raise _StepError(key, "is a switch (true/false) in the file, but takes a value")
        return not values  # `false` keeps the value "false"
    if "bool" in annotation and "Union" not in annotation:
        raise _StepError(key, "is a switch: write true or false")
    if "Mapping" in annotation:
        items = {}
        for value in values:
            name, equals, text = value.partition("=")
            if not equals:
                raise _StepError(key, "'%s': expected NAME=VALUE" % value)
            items[name] = text
        return items
    if "Sequence[str]" in annotation:
        return list(values)
    if ("Sequence[float]" in annotation or "ArrayLike" in annotation) and \
            "str" not in annotation and "PathLike" not in annotation:
        return _numbers(key, values)  # e.g. ik's near, design's centre: "q1,q2,..."
    text = _single(key, values)
    try:
        if annotation in ("int", "Optional[int]"):
            return int(text)
        if annotation in ("float", "Optional[float]"):
            return float(text)
    except ValueError:
        raise _StepError(key, "'%s': expected a %s" % (text, annotation.replace(
            "Optional[", "").rstrip("]"))) from None
    return text


def _keywords(command: str, options: List[Option]) -> Dict[str, Any]:
    function = _WORKFLOWS[command]
    parameters = inspect.signature(function).parameters
    kwargs: Dict[str, Any] = {}
    free_at = fix_at = -1
    for index, (key, values, is_switch, _) in enumerate(options):
        if key == "plugin" or key in _DISPLAY_ONLY:
            continue  # plug-ins are loaded before the step (_load_plugins)
        name = _RENAMED.get((command, key), key.replace("-", "_"))
        if name not in parameters:
            raise _StepError(key, "not an option of kincal.%s (its options: %s); kincal run "
                             "runs what Python does not" % (command, ", ".join(parameters)))
        suffix = _UNIT_SUFFIX.get((command, key))
        if suffix:
            values = [v[:-len(suffix)] if v.endswith(suffix) else v for v in values]
        free_at = index if key == "free" else free_at
        fix_at = index if key == "fix" else fix_at
        kwargs[name] = _argument(key, values, is_switch, parameters[name])
    if 0 <= fix_at < free_at:
        raise _StepError("free", "comes after fix here; kincal.%s applies free, then fix: write "
                         "free first (or run the project with kincal run)" % command)
    return kwargs


def _model_step(options: List[Option]) -> Any:
    """The `model` step: kincal model's options (a preset or a URDF, free/fix in order, out)."""
    given = {key: (values, is_switch) for key, values, is_switch, _ in options}
    for key in given:
        if key not in _MODEL_KEYS and key != "plugin":
            raise _StepError(key, "not an option of kincal model (its options: %s)"
                             % ", ".join(_MODEL_KEYS))

    def text(key: str, default: Optional[str] = None) -> Optional[str]:
        return _single(key, given[key][0]) if key in given else default

    def numbers(key: str) -> Optional[List[float]]:
        return _numbers(key, given[key][0]) if key in given else None

    urdf = text("urdf")
    if urdf is not None:
        if "preset" in given:
            raise _StepError("preset", "urdf and preset: give one or the other")
        if "tip" not in given:
            raise _StepError("urdf", "needs tip (the link the tool is on)")
        compliance = None
        if "compliance" in given:
            values, is_switch = given["compliance"]
            compliance = ("auto" if not values else None) if is_switch else values[0]
        payload_column = False
        if "payload-column" in given:
            values, is_switch = given["payload-column"]
            if not is_switch:
                raise _StepError("payload-column", "is a switch: write true or false")
            payload_column = not values
        model = model_from_urdf(urdf, tip=text("tip") or "", base=text("base"),
                                sensor=text("sensor", "point-tracker") or "point-tracker",
                                point=numbers("point"), compliance=compliance,
                                payload_column=payload_column,
                                payload_centre=numbers("payload-centre"),
                                frame=numbers("frame"), target=numbers("target"))
    else:
        for key in ("tip", "base", "sensor", "point", "frame", "target", "compliance",
                    "payload-centre", "payload-column"):
            if key in given:
                raise _StepError(key, "needs urdf")
        try:
            model = _kincal.Model.preset(text("preset", "cube-hexapod") or "")
        except ValueError as e:
            raise _StepError("preset", str(e)) from None
    for key, values, _, _ in options:  # in the order given, as kincal model applies them
        if key in ("free", "fix"):
            for pattern in values:
                try:
                    model.set_free(pattern, key == "free")
                except ValueError:
                    raise _StepError(key, "'%s': matches no parameter of the model" % pattern) \
                        from None
    out = text("out")
    if out is not None and out != "-":
        _kincal._write_model_file(model, out, [urdf] if urdf else [])
    return model


def _load_plugins(options: List[Option]) -> None:
    for key, values, _, _ in options:
        if key == "plugin":
            for path in values:
                _kincal.load_plugin(path)


def _location(project: Dict[str, Any], index: int, key: Optional[str], message: str) -> str:
    step = project["steps"][index]
    line = step["line"]
    for option_key, values, _, option_line in step["options"]:
        if option_key == key or any(len(v) >= 3 and v in message for v in values):
            line = option_line
            break
    return "%s:%d: steps[%d].%s: %s" % (project["file"], line, index + 1, step["command"],
                                        message)


def _verdict(command: str, result: Any) -> Optional[str]:
    """Why the program would end this step with a verdict's exit code (1, or 3 for a
    calibration not to load), its files written; None when it would exit with 0."""
    if command == "verify":
        return None if result["match"] else str(result["message"])
    if not hasattr(result, "to_dict"):
        return None  # model (a Model), export (its text)
    report = result.to_dict()
    if command in ("fk", "ik", "compensate") and report.get("failed"):
        rows = report["rows"]  # fk, ik: the rows; compensate: their count
        return "%d of %d %s failed (see their status and reason)" % (
            report["failed"], rows if isinstance(rows, int) else len(rows),
            "targets" if command == "compensate" else "rows")
    if command in ("calibrate", "simulate") and not result.solved:
        return "the solver did not reach a solution (%s: %s)" % (report.get("termination"),
                                                                 report.get("message", ""))
    if command == "calibrate" and report["verdict"]["overall"] == "do_not_load":
        for finding in report["verdict"]["findings"]:
            if finding["level"] == "do_not_load":
                return "verdict: do not load this calibration: " + finding["text"]
    if command == "validate" and report["verdict"] == "larger_than_predicted":
        return "verdict: the held-out residuals are larger than predicted"
    return None


def run_project(path: Optional[PathLike] = None, variables: Optional[Mapping[str, str]] = None,
                from_report: Optional[PathLike] = None,
                keep_going: bool = False) -> List[Tuple[str, Any]]:
    """Runs the project file ``path`` (YAML or JSON, docs/projects.md), or the project the
    JSON report ``from_report`` records, step by step with the library's workflows; returns
    (command, result) per step: a Model for ``model``, the workflow's answer for the others.
    ``variables`` replace the values of the project's variables (``--set NAME=VALUE``).
    Every step's keys are checked before the first step runs; an error is a KincalError
    naming the file, the line and the step. A step the program would end with a verdict (a
    ``verify`` that finds another model, a calibration not to load, held-out residuals larger
    than predicted, rows of ``fk``, ``ik`` or ``compensate`` that failed, a solve that reached
    no solution) stops the run with a KincalError after writing its files, as ``kincal run``
    stops; with ``keep_going`` (``--keep-going``) the later steps run and each result carries
    its own verdict."""
    overrides = [(str(k), str(v)) for k, v in (variables or {}).items()]
    try:
        if path is not None and from_report is None:
            project = _kincal._read_project(os.fspath(path), overrides)
        elif from_report is not None and path is None:
            project = _kincal._project_from_report(os.fspath(from_report), overrides)
        else:
            raise KincalError("run_project: give either path or from_report")
    except ValueError as e:
        raise KincalError(str(e)) from None
    steps = project["steps"]
    plans: List[Optional[Dict[str, Any]]] = []
    for index, step in enumerate(steps):
        command = step["command"]
        if command != "model" and command not in _WORKFLOWS:
            raise KincalError(_location(project, index, None, "'%s' is not a step "
                                        "kincal.run_project runs (it runs model, %s); kincal run "
                                        "runs every command" % (command, ", ".join(_WORKFLOWS))))
        try:
            plans.append(None if command == "model" else _keywords(command, step["options"]))
        except _StepError as e:
            raise KincalError(_location(project, index, e.key, "%s: %s" % (e.key, e))) from None
    results: List[Tuple[str, Any]] = []
    for index, (step, kwargs) in enumerate(zip(steps, plans)):
        command = step["command"]
        _kincal._set_project_record(project["records"][index])
        try:
            _load_plugins(step["options"])
            result = _model_step(step["options"]) if kwargs is None else \
                _WORKFLOWS[command](**kwargs)
        except _StepError as e:
            raise KincalError(_location(project, index, e.key, "%s: %s" % (e.key, e))) from None
        except (KincalError, ValueError) as e:
            raise KincalError(_location(project, index, None, str(e))) from None
        finally:
            _kincal._set_project_record("")
        results.append((command, result))
        verdict = _verdict(command, result)
        if verdict is not None and not keep_going:
            raise KincalError(_location(project, index, None, verdict.rstrip(".") + "; the later "
                                        "steps were not run (keep_going=True runs them)"))
    return results


__all__ = ["run_project"]
