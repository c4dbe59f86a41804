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
    unknown = _write(tmp_path / "unknown.yaml", "steps:\n  - reproduce:\n      trials: 3\n")
    with pytest.raises(kincal.KincalError, match=r"unknown\.yaml:2: steps\[1\]\.reproduce: "
                                                 r"'reproduce' is not a step kincal\.run_project "
                                                 r"runs"):
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


_KINEMATICS_PROJECT = """variables:
  out: results
steps:
  - model: {preset: ur5, out: '${out}/ur5.json'}
  - fk:
      model: ${out}/ur5.json
      actuators: 0,-90deg,90deg,0,90deg,0
      json: ${out}/fk.json
  - fk: {model: '${out}/ur5.json', data: configurations.csv, out: '${out}/fk.csv',
         json: '${out}/fk_table.json'}
  - ik: {model: '${out}/ur5.json', data: '${out}/fk.csv', seeds: true, out: '${out}/ik.csv'}
  - ik:
      model: ${out}/ur5.json
      pose: -474.55,-109.15,419.509,90,0,-90
      near: 0,-1.5,1.5,0,1.5,0
      json: ${out}/ik.json
  - ik:
      model: ${out}/ur5.json
      pose: -474.55,-109.15,419.509,90,0,-90
      all: true
      json: ${out}/ik_all.json
"""


def test_fk_and_ik_steps_write_what_kincal_run_writes(tmp_path: Path, program: str) -> None:
    project = _write(tmp_path / "kinematics.yaml", _KINEMATICS_PROJECT)
    _write(tmp_path / "configurations.csv",
           "joint1_deg,joint2_deg,joint3_deg,joint4_deg,joint5_deg,joint6_deg\n"
           "0,-90,90,0,90,0\n10,-80,70,-30,80,20\n")
    py_out, cli_out = tmp_path / "python", tmp_path / "program"
    results = kincal.run_project(project, {"out": str(py_out)})
    assert [command for command, _ in results] == ["model", "fk", "fk", "ik", "ik", "ik"]
    p = subprocess.run([program, "run", str(project), "--set", "out=%s" % cli_out],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    from_python, from_program = _files(py_out, str(py_out)), _files(cli_out, str(cli_out))
    assert sorted(from_program) == ["fk.csv", "fk.json", "fk_table.json", "ik.csv", "ik.json",
                                    "ik_all.json", "ur5.json"]
    for name in from_program:
        assert from_python[name] == from_program[name], name
    # What the files say: the seeded ik finds each row's own configuration again.
    rows = json.loads(from_python["fk_table.json"])["rows"]
    assert [r["status"] for r in rows] == ["ok", "ok"]
    assert results[3][1].text.splitlines()[2].startswith("3,0.1745329251994")
    unseeded = kincal.ik(py_out / "ur5.json", data=py_out / "fk.csv")
    assert any("the actuator columns are not read (seeds starts each row from them)" in n
               for n in unseeded.notes), unseeded.notes
    assert len(results[5][1]["solutions"]) > 1


def test_fk_and_ik_one_pose_and_their_errors(tmp_path: Path) -> None:
    model = kincal.Model.preset("cube-hexapod")
    forward = kincal.fk(model, [350.0] * 6)
    assert forward["format"] == "kincal-fk" and forward["status"] == "ok"
    pose = [forward["pose"][k] for k in ("x_mm", "y_mm", "z_mm", "rx_deg", "ry_deg", "rz_deg")]
    inverse = kincal.ik(model, pose)
    assert inverse["actuators"]["leg1"] == pytest.approx(350.0, abs=1e-9)
    assert inverse.text.endswith("(actuator units: leg1 mm, leg2 mm, leg3 mm, leg4 mm, leg5 mm, "
                                 "leg6 mm)\n")
    assert kincal.fk(model, "0.35m,350,350mm,350,350,350")["pose"] == forward["pose"]
    with pytest.raises(kincal.KincalError, match=r"actuators '1,2': 2 numbers, expected 6"):
        kincal.fk(model, "1,2")
    with pytest.raises(kincal.KincalError, match=r"leg1 = a value in deg, but leg1 is a length"):
        kincal.fk(model, "90deg,350,350,350,350,350")
    with pytest.raises(kincal.KincalError, match=r"pose '0,0,9000,0,0,0': .*expected a pose the "
                                                 r"model can reach"):
        kincal.ik(kincal.Model.preset("ur5"), "0,0,9000,0,0,0")
    with pytest.raises(kincal.KincalError, match="give actuators or data, not both"):
        kincal.fk(model, [350.0] * 6, data=tmp_path / "x.csv")
    with pytest.raises(kincal.KincalError, match="seeds reads a start per row of data"):
        kincal.ik(model, pose, seeds=True)
    with pytest.raises(kincal.KincalError, match=r"near: 2 numbers, expected 6"):
        kincal.ik(model, pose, near=[1.0, 2.0])


_TARGET_PROJECT = """variables:
  out: results
steps:
  - model: {preset: cube-hexapod, out: '${out}/nominal.json'}
  - simulate: {model: '${out}/nominal.json', case: 5, seed: 7, solver: gn,
               write-data: '${out}/measured.csv'}
  - simulate: {model: '${out}/nominal.json', truth: '${out}/measured.truth.json', case: 5,
               seed: 8, solver: gn, write-data: '${out}/held-out.csv'}
  - calibrate: {model: '${out}/nominal.json', data: '${out}/measured.csv', target: 0.05mm,
                out: '${out}/calibrated.json', json: '${out}/report.json',
                html: '${out}/report.html'}
  - validate: {model: '${out}/calibrated.json', data: '${out}/held-out.csv', target: 0.05mm,
               report: '${out}/report.json', json: '${out}/validate.json',
               html: '${out}/validate.html'}
  - design: {model: '${out}/nominal.json', poses: 30, candidates: 2000, noise-std: 0.0072mm,
             target: 0.001mm, out: '${out}/design.csv', json: '${out}/design.json',
             html: '${out}/design.html'}
"""


def test_target_is_judged_as_the_program_judges_it(tmp_path: Path, program: str) -> None:
    project = _write(tmp_path / "target.yaml", _TARGET_PROJECT)
    py_out, cli_out = tmp_path / "python", tmp_path / "program"
    # One gauge cannot place the platform to 0.05 mm everywhere: the calibration is not to be
    # loaded, and the run stops there, as the program's does (exit code 3).
    with pytest.raises(kincal.KincalError, match=r"target\.yaml:9: steps\[4\]\.calibrate: "
                                                 r"verdict: do not load this calibration: .*does "
                                                 r"not meet the 0\.05 mm target.*later steps"):
        kincal.run_project(project, {"out": str(tmp_path / "stopped")})
    assert (tmp_path / "stopped" / "report.json").exists()
    assert not (tmp_path / "stopped" / "validate.json").exists()
    results = kincal.run_project(project, {"out": str(py_out)}, keep_going=True)
    p = subprocess.run([program, "run", str(project), "--set", "out=%s" % cli_out,
                        "--keep-going"], capture_output=True, text=True)
    assert p.returncode == 3, p.stderr
    from_python, from_program = _files(py_out, str(py_out)), _files(cli_out, str(cli_out))
    assert sorted(from_python) == sorted(from_program)
    for name in from_program:
        # Where a report names an option, it spells it as the face does.
        spelt = from_python[name].replace("from noise_std", "from --noise-std")
        assert spelt.replace('source": "noise_std"', 'source": "--noise-std"') == \
            from_program[name], name
    targets = {command: result["target"] for command, result in results
               if command in ("calibrate", "validate", "design")}
    assert targets["calibrate"]["meets"] is False and targets["design"]["meets"] is False
    # A length gauge measures no point: the held-out data cannot judge a position target.
    assert targets["validate"]["meets"] is None
    assert results[4][1]["verdict"] == "consistent"
    assert "target: does not meet the 0.05 mm target" in results[3][1].text
    assert "target: does not meet the 0.001 mm target" in results[5][1].text
    assert "target: does not meet the 0.05 mm target" in p.stdout
    with pytest.raises(kincal.KincalError, match=r"target '0\.1': no length in mm"):
        kincal.validate(py_out / "calibrated.json", py_out / "held-out.csv", target="0.1")


def test_keys_spelt_otherwise_in_python_are_mapped() -> None:
    from kincal.project import _keywords

    assert _keywords("detect", [("target", ["chessboard:6x8:20mm"], False, 3),
                                ("gate", ["1.5px"], False, 4),
                                ("intrinsics", ["800,800,320,240"], False, 5),
                                ("progress", [], True, 6)]) == {
        "target": "chessboard:6x8:20mm", "gate_px": 1.5, "intrinsics": [800.0, 800.0, 320.0, 240.0]}
    assert _keywords("design", [("poses", ["20"], False, 3), ("centre", ["0,1.5"], False, 4),
                                ("candidates-file", ["c.csv"], False, 5)]) == {
        "count": 20, "centre": [0.0, 1.5], "candidate_configurations": "c.csv"}
    assert _keywords("ik", [("near", ["0,-1.5,1.5,0,1.5,0"], False, 3), ("all", [], True, 4)]) == {
        "near": [0.0, -1.5, 1.5, 0.0, 1.5, 0.0], "all": True}


def _ur5_dataset(source_dir: Path) -> Path:
    folder = Path(os.environ.get("KINCAL_DATASETS", source_dir.parent / "shared" / "datasets"))
    folder = folder / "ur5-laser-tracker"
    if not folder.is_dir():
        # As the example's test (exit 77): the public dataset is not committed.
        pytest.skip("the public UR5 dataset is not at %s" % folder)
    return folder


def test_the_ur5_project_from_python_writes_the_programs_files(tmp_path: Path, program: str,
                                                               source_dir: Path) -> None:
    import importlib.util

    example = source_dir / "examples" / "ur5-laser-tracker"
    spec = importlib.util.spec_from_file_location("ur5_run", example / "run.py")
    assert spec is not None and spec.loader is not None
    ur5 = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ur5)
    dataset = _ur5_dataset(source_dir)
    data = tmp_path / "data"
    data.mkdir()
    ur5.write_measurements(ur5.read_dataset(str(dataset / ur5.GRID)), str(data / "grid.csv"))
    ur5.write_measurements(ur5.read_dataset(str(dataset / ur5.TEST)), str(data / "test.csv"))
    project = example / "project.yaml"
    py_out, cli_out = tmp_path / "python", tmp_path / "program"
    results = kincal.run_project(project, {"data": str(data), "out": str(py_out)})
    assert [command for command, _ in results] == ["model", "calibrate", "model", "calibrate",
                                                   "export", "validate", "validate"]
    p = subprocess.run([program, "run", str(project), "--set", "data=%s" % data,
                        "--set", "out=%s" % cli_out], capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    from_python, from_program = _files(py_out, str(py_out)), _files(cli_out, str(cli_out))
    assert sorted(from_python) == sorted(from_program) and len(from_program) == 9
    for name in from_program:
        assert from_python[name] == from_program[name], name


def test_rows_that_failed_stop_the_run_as_the_program_exits_with_1(tmp_path: Path,
                                                                    program: str) -> None:
    # The gauge cannot read 5000 mm: compensate's second target fails, fk's second row too.
    _write(tmp_path / "targets.csv", "gauge\n342.5\n5000\n")
    _write(tmp_path / "legs.csv", "leg1,leg2,leg3,leg4,leg5,leg6\n350,350,350,350,350,350\n"
                                  "350,350,350,350,350,1e6\n")
    project = _write(tmp_path / "rows.yaml", """steps:
  - model: {preset: cube-hexapod, out: m.json}
  - compensate: {model: m.json, targets: targets.csv, out: commands.csv}
  - fk: {model: m.json, data: legs.csv, out: poses.csv}
""")
    with pytest.raises(kincal.KincalError, match=r"rows\.yaml:3: steps\[2\]\.compensate: 1 of 2 "
                                                 r"targets failed .*later steps were not run"):
        kincal.run_project(project)
    assert (tmp_path / "commands.csv").exists() and not (tmp_path / "poses.csv").exists()
    results = kincal.run_project(project, keep_going=True)
    assert results[2][1]["failed"] == 1
    p = subprocess.run([program, "run", str(project), "--keep-going"], capture_output=True,
                       text=True)
    assert p.returncode == 1, p.stderr
    assert "steps[2].compensate exited with 1; running the later steps" in p.stderr
