"""kincal.run_project: the project file the program runs (kincal run), run by the library's
workflows, writes the same files (examples/hexapod-gauge/project.yaml); errors name the file,
the line and the step."""

from __future__ import annotations

import json
import os
import subprocess
from pathlib import Path

import pytest

import kincal


def _files(folder: Path, prefix: str) -> dict:
    return {p.name: p.read_text().replace(prefix, "OUT") for p in sorted(folder.iterdir())}


def test_the_hexapod_project_writes_what_kincal_run_writes(tmp_path: Path, program: str,
                                                           source_dir: Path) -> None:
    project = source_dir / "examples" / "hexapod-gauge" / "project.yaml"
    py_out, cli_out = tmp_path / "python", tmp_path / "program"
    results = kincal.run_project(project, {"out": str(py_out)})
    assert [command for command, _ in results] == ["model", "simulate", "observability",
                                                   "calibrate", "verify", "export"]
    assert results[4][1]["match"]
    p = subprocess.run([program, "run", str(project), "--set", "out=%s" % cli_out],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    from_python, from_program = _files(py_out, str(py_out)), _files(cli_out, str(cli_out))
    assert sorted(from_python) == sorted(from_program)
    for name in from_program:
        assert from_python[name] == from_program[name], name
    report = json.loads(from_python["report.json"])
    assert report["project"]["content"] == project.read_text()
    assert report["project"]["step"] == 4
    # The record redoes the run.
    os.remove(py_out / "calibrated.json")
    kincal.run_project(from_report=py_out / "report.json")
    assert (py_out / "calibrated.json").read_text().replace(str(py_out), "OUT") == \
        from_program["calibrated.json"]


def _write(path: Path, text: str) -> Path:
    path.write_text(text)
    return path


def test_errors_name_the_file_line_and_step(tmp_path: Path) -> None:
    typo = _write(tmp_path / "typo.yaml",
                  "steps:\n  - model:\n      out: m.json\n  - calibrate:\n      model: m.json\n"
                  "      data: d.csv\n      seeed: 3\n")
    with pytest.raises(kincal.KincalError, match=r"typo\.yaml:7: steps\[2\]\.calibrate: seeed: "
                                                 r"not an option of kincal\.calibrate"):
        kincal.run_project(typo)
    assert not (tmp_path / "m.json").exists()  # checked before the first step ran
    unknown = _write(tmp_path / "unknown.yaml", "steps:\n  - fk:\n      model: m.json\n")
    with pytest.raises(kincal.KincalError, match=r"unknown\.yaml:2: steps\[1\]\.fk: 'fk' is not "
                                                 r"a step kincal\.run_project runs"):
        kincal.run_project(unknown)
    order = _write(tmp_path / "order.yaml",
                   "steps:\n  - calibrate:\n      model: m.json\n      data: d.csv\n"
                   "      fix: '*'\n      free: 'base.*'\n")
    with pytest.raises(kincal.KincalError, match=r"order\.yaml:6: .*free: comes after fix"):
        kincal.run_project(order)
    missing = _write(tmp_path / "missing.yaml",
                     "steps:\n  - calibrate:\n      model: nothere.json\n      data: d.csv\n")
    with pytest.raises(kincal.KincalError, match=r"missing\.yaml:3: steps\[1\]\.calibrate: .*"
                                                 r"nothere\.json"):
        kincal.run_project(missing)
    with pytest.raises(kincal.KincalError, match=r"declares no variable 'x'"):
        kincal.run_project(missing, {"x": "1"})
    with pytest.raises(kincal.KincalError, match="either path or from_report"):
        kincal.run_project()
