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

    monkeypatch.setattr(kincal._kincal, "run_command", refused)
    monkeypatch.setattr(tempfile, "TemporaryDirectory", refused)
    monkeypatch.setattr(tempfile, "mkstemp", refused)
    monkeypatch.setattr(tempfile, "NamedTemporaryFile", refused)
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
