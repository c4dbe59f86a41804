"""Joint compliance and corrected targets from Python: model_from_urdf(compliance=...) is
`kincal model --urdf --compliance`, and kincal.compensate is `kincal compensate` (the same
library calls), whose commands make the model read what was wanted."""

import subprocess

import numpy as np
import pytest

import kincal


def test_model_from_urdf_with_compliance_is_the_programs(program, source_dir, tmp_path):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    model_file = tmp_path / "ur5c.json"
    subprocess.run([program, "model", "--urdf", str(urdf), "--tip", "flange", "--compliance",
                    "--payload-column", "--payload-centre", "0,0,40", "--out", str(model_file)],
                   check=True, capture_output=True)
    model = kincal.model_from_urdf(str(urdf), "flange", compliance="auto", payload_column=True,
                                   payload_centre=[0, 0, 40])
    assert model.to_json() == model_file.read_text()
    assert model.actuator_names[-1] == "payload" and model.actuator_units[-1] == "kg"
    assert "elbow_joint.compliance" in model.parameter_names
    with pytest.raises(kincal.KincalError, match="need compliance"):
        kincal.model_from_urdf(str(urdf), "flange", payload_column=True)
    with pytest.raises(kincal.KincalError, match="compliance 'stiff'"):
        kincal.model_from_urdf(str(urdf), "flange", compliance="stiff")


def test_compensated_commands_reach_the_wanted_readings(program, tmp_path):
    model = kincal.Model.preset("ur5-urdf-compliance")
    model_file = tmp_path / "model.json"
    model_file.write_text(model.to_json())
    # Commands near home with 2 kg, and targets 0.5 mm away from where they put the point.
    rng = np.random.default_rng(4)
    home = np.array([0, -np.pi / 2, np.pi / 2, -np.pi / 2, -np.pi / 2, 0])
    commands = home + rng.uniform(-0.4, 0.4, size=(12, 6))
    q = np.hstack([commands, np.full((12, 1), 2.0)])
    _, readings, status, _ = model.forward_kinematics(q)
    assert all(s == "ok" for s in status)
    wanted = readings + rng.uniform(-0.5, 0.5, size=readings.shape)
    targets = tmp_path / "targets.csv"
    names = model.actuator_names[:6] + model.reading_names
    np.savetxt(targets, np.hstack([commands, wanted]), delimiter=",", header=",".join(names),
               comments="", fmt="%.17g")
    out = tmp_path / "commands.csv"
    result = kincal.compensate(model, str(targets), payload=2.0, out=str(out))
    assert result.failed == 0 and result.statuses == ["ok"] * 12
    assert result.commands.shape == (12, 7)
    np.testing.assert_array_equal(result.commands[:, 6], 2.0)  # the payload is an input
    _, reached, _, _ = model.forward_kinematics(result.commands)
    np.testing.assert_allclose(reached, wanted, atol=1e-8)
    # The smallest change that reaches them: well under a degree from the start commands.
    assert np.abs(result.commands[:, :6] - commands).max() < 0.01
    assert result.max_error < 1e-8 and 0.2 < result.mean_error_at_start < 1.0
    # The program writes the same table.
    cli_out = tmp_path / "cli.csv"
    subprocess.run([program, "compensate", "--model", str(model_file), "--targets", str(targets),
                    "--payload", "2", "--out", str(cli_out)], check=True, capture_output=True)
    assert cli_out.read_text() == out.read_text()
    with pytest.raises(kincal.KincalError, match="an input"):
        kincal.compensate(model, str(targets), payload=2.0, out=str(targets))


def test_tracker_frame_and_target_are_the_programs(program, source_dir):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    p = subprocess.run([program, "model", "--urdf", str(urdf), "--tip", "flange", "--sensor",
                        "pose-tracker", "--frame", "1000,200,0,0,0,90", "--target",
                        "0,0,50,0,90,0", "--out", "-"], capture_output=True, text=True, check=True)
    model = kincal.model_from_urdf(str(urdf), "flange", sensor="pose-tracker",
                                   frame=[1000, 200, 0, 0, 0, 90], target=[0, 0, 50, 0, 90, 0])
    assert model.to_json() == p.stdout
    with pytest.raises(kincal.KincalError, match="a target frame is a pose tracker's marker"):
        kincal.model_from_urdf(str(urdf), "flange", target=[0, 0, 50, 0, 0, 0])
