"""calibrate and validate call the library's workflows: typed keyword arguments, Models and
Measurements in memory, no command line and no temporary file; the reports are the
program's for the same inputs."""

import json
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import kincal
from conftest import without_timing


@pytest.fixture()
def case3(tmp_path):
    data = tmp_path / "d.csv"
    held = tmp_path / "h.csv"
    kincal.simulate(case=3, seed=7, write_data=str(data))
    kincal.simulate(case=3, seed=8, write_data=str(held))
    model = kincal.Model.preset("cube-hexapod")
    return model, kincal.Measurements.read(str(data), model), kincal.Measurements.read(str(held), model), data, held


def test_no_command_line_and_no_temporary_file(case3, monkeypatch):
    model, data, held, _, _ = case3

    def refused(*args, **kwargs):
        raise AssertionError("kincal built a command line or a temporary file")

    assert not hasattr(kincal._kincal, "run_command")  # no program inside the module
    monkeypatch.setattr(tempfile, "TemporaryDirectory", refused)
    monkeypatch.setattr(tempfile, "mkstemp", refused)
    monkeypatch.setattr(tempfile, "NamedTemporaryFile", refused)
    sim = kincal.simulate(model=model, configs=data, truth=model, seed=4)
    assert sim.termination == "converged" and sim.configs == "measurements"
    assert kincal.observability(model, data)["configurations"] == len(data)
    assert kincal.compare(model, model, data=data).pose_error.position_max_mm == 0
    assert kincal.export(model, "json")
    cal = kincal.calibrate(model, data, folds=3, prior_std=None)
    assert cal.termination == "converged"
    assert cal.calibrated_model is not None
    v = kincal.validate(cal.calibrated_model, held, report=cal)
    assert v["format"].startswith("kincal-valid")
    assert v.verdict in {"consistent", "larger_than_predicted", "smaller_than_predicted"}


def test_validate_with_the_report_in_memory_is_the_programs_with_its_file(case3, program, tmp_path):
    model, _, _, data, held = case3
    out, report = tmp_path / "c.json", tmp_path / "r.json"
    cal = kincal.calibrate(model, str(data), out=str(out), json=str(report))
    assert json.loads(report.read_text()) == cal.to_dict()
    assert cal["calibrated_model"]["file"] == str(out)
    np.testing.assert_array_equal(cal.calibrated_model.nominal, kincal.Model.load(str(out)).nominal)
    in_memory = kincal.validate(str(out), str(held), report=cal)
    from_files = kincal.validate(str(out), str(held), report=str(report))
    p = subprocess.run([program, "validate", "--model", str(out), "--data", str(held), "--report",
                        str(report), "--json", "-"], capture_output=True, text=True)
    assert p.returncode in (0, 1), p.stderr
    expected = json.loads(p.stdout)
    assert from_files.to_dict() == expected
    # In memory the report is named in words, not by a file: the figures are the same.
    a, b = in_memory.to_dict(), expected
    for key in ("configurations", "residual_rms", "noise", "parameter_uncertainty", "chi_square",
                "verdict", "residuals"):
        assert a[key] == b[key], key
    assert a["report"] != b["report"]
    assert str(held) in in_memory.text


def test_measurement_columns_are_matched_by_name(case3):
    model, data, _, _, _ = case3
    order = list(reversed(range(len(data.actuator_names))))
    shuffled = kincal.Measurements(data.actuators[:, order], data.readings,
                                   [data.actuator_names[i] for i in order], data.reading_names)
    a = kincal.calibrate(model, data)
    b = kincal.calibrate(model, shuffled)
    np.testing.assert_array_equal(a.parameters.estimate, b.parameters.estimate)
    missing = kincal.Measurements(data.actuators[:, :5], data.readings, data.actuator_names[:5],
                                  data.reading_names)
    with pytest.raises(kincal.KincalError, match="no actuator column 'leg6'"):
        kincal.calibrate(model, missing)


def test_options_are_typed_values_and_bad_ones_are_one_line(case3):
    model, data, _, _, _ = case3
    with pytest.raises(TypeError, match="solvr"):
        kincal.calibrate(model, data, solvr="lm")  # type: ignore[call-arg]
    with pytest.raises(kincal.KincalError, match="fix 'leg9\\*': matches no parameter"):
        kincal.calibrate(model, data, fix=["leg9*"])
    with pytest.raises(kincal.KincalError, match="loss 'hubr:1'"):
        kincal.calibrate(model, data, loss="hubr:1")
    with pytest.raises(kincal.KincalError, match="give the robust loss as loss="):
        kincal.calibrate(model, data, solver_option={"loss": "huber:1"})
    with pytest.raises(kincal.KincalError, match="noise_std '0.01rad': no value for mm"):
        kincal.calibrate(model, data, noise_std="0.01rad")
    with pytest.raises(kincal.KincalError, match="prior_std 'leg9=0.1'.*matches no parameter"):
        kincal.calibrate(model, data, noise_std="0.001mm", prior_std="leg9=0.1")
    with pytest.raises(ValueError, match="no-such-solver"):
        kincal.calibrate(model, data, solver="no-such-solver")


def test_prior_and_noise_reach_the_report_as_the_programs_options_do(case3, program, tmp_path):
    model, _, _, data, _ = case3
    model_file = tmp_path / "m.json"
    model_file.write_text(model.to_json())
    report = kincal.calibrate(str(model_file), str(data), noise_std="0.0007mm",
                              prior_std=["leg*.base.z=0.5mm"], fix=["gauge.offset"], folds=4)
    p = subprocess.run([program, "calibrate", "--model", str(model_file), "--data", str(data),
                        "--noise-std", "0.0007mm", "--prior-std", "leg*.base.z=0.5mm", "--fix",
                        "gauge.offset", "--folds", "4", "--json", "-"],
                       capture_output=True, text=True)
    assert p.returncode in (0, 3), p.stderr
    assert without_timing(report.to_dict()) == without_timing(json.loads(p.stdout))


def test_an_output_never_overwrites_an_input(case3):
    _, _, _, data, _ = case3
    model = kincal.Model.preset("cube-hexapod")
    before = data.read_bytes()
    with pytest.raises(kincal.KincalError, match="an input"):
        kincal.calibrate(model, str(data), json=str(data))
    assert data.read_bytes() == before


def test_mypy_strict_catches_a_misspelt_option(tmp_path):
    script = tmp_path / "user.py"
    script.write_text(
        "import kincal\n"
        "model = kincal.Model.preset('cube-hexapod')\n"
        "report = kincal.calibrate(model, 'd.csv', folds=5, max_iteratons=50)\n"
        "v = kincal.validate(report.calibrated_model, 'h.csv', report=report)\n"
    )
    p = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(script)],
                       capture_output=True, text=True)
    assert p.returncode == 1, p.stdout + p.stderr
    assert 'Unexpected keyword argument "max_iteratons"' in p.stdout, p.stdout
    script.write_text(script.read_text().replace("max_iteratons", "max_iterations"))
    p = subprocess.run([sys.executable, "-m", "mypy", "--strict", "--no-incremental", str(script)],
                       capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr


def test_model_from_urdf_and_export_are_the_programs_without_it(program, source_dir, tmp_path, monkeypatch):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    model_file = tmp_path / "ur5.json"
    subprocess.run([program, "model", "--urdf", str(urdf), "--tip", "flange", "--point", "0,0,50",
                    "--out", str(model_file)], check=True, capture_output=True)
    model = kincal.model_from_urdf(str(urdf), "flange", point=[0, 0, 50])
    assert model.to_json() == model_file.read_text()
    for format in ("urdf", "json"):
        p = subprocess.run([program, "export", "--model", str(model_file), "--format", format],
                           capture_output=True, text=True, check=True)
        assert kincal.export(str(model_file), format) == p.stdout, format
    p = subprocess.run([program, "export", "--model", str(model_file), "--format", "csv"],
                       capture_output=True, text=True)
    assert p.returncode == 2
    with pytest.raises(kincal.KincalError) as refused:
        kincal.export(str(model_file), "csv")
    assert str(refused.value) in p.stderr  # the program's line, without its "kincal export: error:"
    out = tmp_path / "ur5-export.urdf"
    text = kincal.export(model, "urdf", out=str(out))
    assert out.read_text() == text and "flange" in text
    with pytest.raises(kincal.KincalError, match="format 'step': expected urdf, csv, json"):
        kincal.export(model, "step")
    with pytest.raises(kincal.KincalError, match="an input"):
        kincal.export(str(model_file), "json", out=str(model_file))
    with pytest.raises(kincal.KincalError, match="sensor 'laser'"):
        kincal.model_from_urdf(str(urdf), "flange", sensor="laser")
    with pytest.raises(kincal.KincalError, match="no-such-link"):
        kincal.model_from_urdf(str(urdf), "no-such-link")


def test_observability_is_the_programs_from_memory_and_from_files(case3, program, tmp_path, monkeypatch):
    model, data, _, data_file, _ = case3
    model_file = tmp_path / "m.json"
    model_file.write_text(model.to_json())
    p = subprocess.run([program, "observability", "--model", str(model_file), "--poses", "30", "--seed", "2",
                        "--config-range", "20mm", "--json", "-"], capture_output=True, text=True, check=True)
    random = kincal.observability(str(model_file), poses=30, seed=2, config_range="20mm")
    assert random.to_dict() == json.loads(p.stdout)
    assert random.text.startswith("30 configurations\n")
    p = subprocess.run([program, "observability", "--model", str(model_file), "--data", str(data_file),
                        "--fix", "gauge.offset", "--json", "-"], capture_output=True, text=True, check=True)
    from_file = kincal.observability(str(model_file), str(data_file), fix=["gauge.offset"])
    assert from_file.to_dict() == json.loads(p.stdout)
    in_memory = kincal.observability(model, data, fix=["gauge.offset"])
    assert in_memory["condition_number"] == from_file["condition_number"]
    with pytest.raises(kincal.KincalError, match="exactly one of data and poses"):
        kincal.observability(model, data, poses=30)
    with pytest.raises(kincal.KincalError, match="exactly one of data and poses"):
        kincal.observability(model)


def test_simulate_in_memory_is_the_programs_from_files(case3, program, tmp_path):
    model, data, _, data_file, _ = case3
    truth_file = tmp_path / "t.json"
    truth_file.write_text(model.with_values(model.nominal + 0.01).to_json())
    model_file = tmp_path / "m.json"
    model_file.write_text(model.to_json())
    args = ["--model", str(model_file), "--configs", str(data_file), "--truth", str(truth_file),
            "--noise-std", "0.0007mm", "--seed", "5", "--json", "-"]
    p = subprocess.run([program, "simulate"] + args, capture_output=True, text=True, check=True)
    expected = json.loads(p.stdout)
    from_files = kincal.simulate(model=str(model_file), configs=str(data_file), truth=str(truth_file),
                                 noise_std="0.0007mm", seed=5)
    assert without_timing(from_files.to_dict()) == without_timing(expected)
    in_memory = kincal.simulate(model=model, configs=data, truth=kincal.Model.load(str(truth_file)),
                                noise_std="0.0007mm", seed=5)
    a, b = in_memory.to_dict(), expected
    assert a["parameters"] == b["parameters"] and a["validation"] == b["validation"]
    with pytest.raises(kincal.KincalError, match="configs gives the configurations"):
        kincal.simulate(model=model, configs=data, poses=10)
    with pytest.raises(kincal.KincalError, match="noise_std is the noise's std"):
        kincal.simulate(case=3, noise_std="0.001mm")
