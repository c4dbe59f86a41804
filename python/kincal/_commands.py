"""kincal's commands from Python: simulate, calibrate, observability, design, validate,
compare, export and the HTML report run in this process through the program's own code
(``_kincal.run_command``), so that a report's ``to_dict()`` is the program's JSON.

Options are keyword arguments named as the command's options with ``_`` for ``-``
(``solver_option={"max_iterations": ...}``, ``prior_std=["leg*=0.1"]``): ``True`` is a
flag, a list repeats the option, a dict gives ``key=value`` items, ``None`` leaves it out.
Models and measurements may be files or ``Model`` / ``Measurements`` objects (written to a
temporary file first, at full precision).
"""

from __future__ import annotations

import json
import os
import tempfile
import threading
from typing import Any, Dict, List, Mapping, Optional, Tuple, Union

from . import _kincal
from ._reports import Report


class KincalError(ValueError):
    """Bad input to a command: the program's one-line message (what and where)."""


class KincalInterrupt(KeyboardInterrupt):
    """Ctrl-C during a kincal call. ``result`` holds what was done: the report of a solve
    stopped at its best point so far, or the partial study."""

    def __init__(self, message: str, result: Any) -> None:
        super().__init__(message)
        self.result = result


def _on_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


def option_args(options: Mapping[str, Any]) -> List[str]:
    """The command-line form of keyword options (see the module's documentation)."""
    args: List[str] = []
    for key, value in options.items():
        if value is None or value is False:
            continue
        flag = "--" + key.replace("_", "-")
        if value is True:
            args.append(flag)
        elif isinstance(value, dict):
            for k, v in value.items():
                args += [flag, f"{k}={v}"]
        elif isinstance(value, (list, tuple)):
            for v in value:
                args += [flag, str(v)]
        else:
            args += [flag, str(value)]
    return args


def run(command: str, args: List[str]) -> Tuple[int, str, str, bool]:
    """Runs ``kincal COMMAND ARGS...`` in-process (GIL released) with standard output and
    error of its own: returns (exit code, what it printed on each, interrupted); what other
    threads print meanwhile is not part of it. Raises KincalError on bad input."""
    code, out, err, interrupted = _kincal.run_command([command] + args, _on_main_thread())
    out_text = out.decode("utf-8", "replace")
    err_text = err.decode("utf-8", "replace")
    if code == 2:
        lines = [line for line in err_text.splitlines() if line.strip()]
        raise KincalError(lines[-1] if lines else f"kincal {command}: bad input")
    return code, out_text, err_text, interrupted


class Workdir:
    """A temporary directory for the files a command reads and writes."""

    def __init__(self) -> None:
        self._dir = tempfile.TemporaryDirectory(prefix="kincal-")
        self.path = self._dir.name

    def file(self, name: str) -> str:
        return os.path.join(self.path, name)

    def close(self) -> None:
        self._dir.cleanup()

    def __enter__(self) -> "Workdir":
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def model_path(model: Any, work: Workdir, name: str = "model.json") -> str:
    """A model file for ``model``: its path, or a temporary file holding a Model."""
    if isinstance(model, (str, os.PathLike)):
        return os.fspath(model)
    if isinstance(model, _kincal.Model):
        path = work.file(name)
        with open(path, "w", encoding="utf-8") as f:
            f.write(model.to_json())
        return path
    raise TypeError(f"model: expected a file name or a kincal.Model, got {type(model).__name__}")


def data_path(data: Any, model: Any, work: Workdir, name: str = "data.csv") -> str:
    """A measurement file for ``data``: its path, or a temporary file of Measurements."""
    from .measurements import Measurements

    if isinstance(data, (str, os.PathLike)):
        return os.fspath(data)
    if isinstance(data, Measurements):
        path = work.file(name)
        data.write(path)
        return path
    raise TypeError(f"data: expected a file name or kincal.Measurements, got {type(data).__name__}")


def json_report(
    command: str, args: List[str], work: Workdir, json_option: str = "--json"
) -> Tuple[Report, int, str, str]:
    """Runs a command with its JSON report sent to a temporary file and returns the report
    (exit code 1, a solve that reached no solution, is a status in the report, not an
    error). Ctrl-C raises KincalInterrupt carrying the report written."""
    report_file = work.file(command + "-report.json")
    code, out, err, interrupted = run(command, args + [json_option, report_file])
    report: Optional[Report] = None
    if os.path.exists(report_file):
        with open(report_file, encoding="utf-8") as f:
            report = Report(json.load(f))
    if interrupted or code == 130:
        raise KincalInterrupt(f"kincal {command} interrupted", report)
    if report is None:
        lines = [line for line in err.splitlines() if line.strip()]
        raise RuntimeError(lines[-1] if lines else f"kincal {command} wrote no report")
    return report, code, out, err


def with_text(report: Report, out: str, err: str) -> Report:
    """The report, with the command's text output as ``report.text`` (not in to_dict)."""
    report.__dict__["text"] = out
    report.__dict__["messages"] = err
    return report


OptionValue = Union[None, bool, int, float, str, List[Any], Dict[str, Any]]
