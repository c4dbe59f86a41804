"""kincal.design inside a region (issue 40): ``within`` bounds the candidates by the measured
configurations' range, ``candidate_configurations`` gives them, and an imported arm keeps what
they determine; the same template as the program's."""

import subprocess

import numpy as np
import pytest

import kincal


def test_within_and_given_candidates(program, source_dir, tmp_path):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    model = kincal.model_from_urdf(str(urdf), "flange", point=[0, 0.09, 31])
    measured = np.radians([[-60, -150, 30, -180, 40, -90], [60, -40, 140, -20, 140, 90]])
    d = kincal.design(model, count=30, candidates=1000, noise_std="0.065mm", within=measured)
    q = d.configurations.actuators
    assert q.shape == (30, 6)
    assert (q >= measured.min(axis=0) - 1e-12).all() and (q <= measured.max(axis=0) + 1e-12).all()
    assert any("the candidates determine" in n for n in d.notes)
    # The program, given the same range as a file, writes the same template.
    model_file = tmp_path / "ur5.json"
    model_file.write_text(model.to_json())
    within = tmp_path / "within.csv"
    np.savetxt(within, measured, delimiter=",", comments="", fmt="%.17g",
               header="shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,"
                      "wrist_2_joint,wrist_3_joint")
    out_py, out_cli = tmp_path / "py.csv", tmp_path / "cli.csv"
    kincal.design(str(model_file), count=30, candidates=1000, noise_std="0.065mm",
                  within=measured, out=str(out_py))
    subprocess.run([program, "design", "--model", str(model_file), "--within", str(within),
                    "--poses", "30", "--candidates", "1000", "--noise-std", "0.065mm",
                    "--out", str(out_cli)], check=True, capture_output=True)
    assert out_py.read_text() == out_cli.read_text()
    given = measured[0] + (measured[1] - measured[0]) * np.random.default_rng(3).uniform(size=(80, 6))
    g = kincal.design(model, count=20, noise_std="0.065mm", candidate_configurations=given)
    for row in g.configurations.actuators:
        assert np.isclose(given, row, rtol=0, atol=1e-12).all(axis=1).any()
    with pytest.raises(kincal.KincalError, match="not both"):
        kincal.design(model, count=20, noise_std="0.065mm", within=measured,
                      candidate_configurations=given)


def test_limits_by_default_and_centre(program, source_dir, tmp_path):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    model = kincal.model_from_urdf(str(urdf), "flange", point=[0, 0.09, 31])
    d = kincal.design(model, count=20, candidates=1000, noise_std="0.065mm")
    assert d["candidates"]["region"] == "the joint limits"
    q = d.configurations.actuators
    assert (np.abs(q[:, 2]) <= np.pi + 1e-12).all() and np.abs(q).max() > 1.0
    centre = [0, -1.5, 3, -1.5, -1.5, 0]
    c = kincal.design(model, count=30, candidates=1000, noise_std="0.065mm", centre=centre,
                      config_range="0.5rad")
    assert c["candidates"]["region"].endswith("clipped to the joint limits")
    q = c.configurations.actuators
    assert (np.abs(q - centre) <= 0.5 + 1e-12).all() and (q[:, 2] <= np.pi + 1e-12).all()
    # The program's --centre writes the same template.
    model_file = tmp_path / "ur5.json"
    model_file.write_text(model.to_json())
    out_py, out_cli = tmp_path / "py.csv", tmp_path / "cli.csv"
    kincal.design(str(model_file), count=30, candidates=1000, noise_std="0.065mm", centre=centre,
                  config_range="0.5rad", out=str(out_py))
    subprocess.run([program, "design", "--model", str(model_file), "--centre",
                    ",".join(str(v) for v in centre), "--config-range", "0.5rad", "--poses", "30",
                    "--candidates", "1000", "--noise-std", "0.065mm", "--out", str(out_cli)],
                   check=True, capture_output=True)
    assert out_py.read_text() == out_cli.read_text()
    with pytest.raises(kincal.KincalError, match="not several"):
        kincal.design(model, count=20, noise_std="0.065mm", centre=centre, within=[centre])


def test_files_of_configurations_and_a_project_design_step(program, source_dir, tmp_path):
    urdf = source_dir / "examples" / "ur5-laser-tracker" / "ur5.urdf"
    model = kincal.model_from_urdf(str(urdf), "flange", point=[0, 0.09, 31])
    model_file = tmp_path / "ur5.json"
    model_file.write_text(model.to_json())
    within = tmp_path / "within.csv"
    within.write_text("shoulder_pan_joint_deg,shoulder_lift_joint_deg,elbow_joint_deg,"
                      "wrist_1_joint_deg,wrist_2_joint_deg,wrist_3_joint_deg,note\n"
                      "-60,-150,30,-180,40,-90,a\n60,-40,140,-20,140,90,b\n")
    # A file is read by the library as the program reads it (degrees converted).
    d = kincal.design(model, count=30, candidates=1000, noise_std="0.065mm", within=within)
    measured = np.radians([[-60, -150, 30, -180, 40, -90], [60, -40, 140, -20, 140, 90]])
    a = kincal.design(model, count=30, candidates=1000, noise_std="0.065mm", within=measured)
    assert np.array_equal(d.configurations.actuators, a.configurations.actuators)
    empty = tmp_path / "empty.csv"
    empty.write_text("shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,"
                     "wrist_2_joint,wrist_3_joint\n")
    with pytest.raises(kincal.KincalError, match=r"within: .*empty\.csv: no measurement rows"):
        kincal.design(model, count=30, noise_std="0.065mm", within=empty)
    # A project's design step with within, candidates-file and centre: Python writes the
    # program's templates.
    project = tmp_path / "design.yaml"
    project.write_text("""variables:
  out: x
steps:
  - design: {model: ur5.json, within: within.csv, poses: 20, candidates: 500,
             noise-std: 0.065mm, out: '${out}/within.csv'}
  - design: {model: ur5.json, candidates-file: within.csv, poses: 2, noise-std: 0.065mm,
             out: '${out}/given.csv'}
  - design: {model: ur5.json, centre: '0,-1.5,1.5,-1.5,-1.5,0', config-range: 0.3rad,
             poses: 20, candidates: 500, noise-std: 0.065mm, out: '${out}/centre.csv'}
""")
    kincal.run_project(project, {"out": str(tmp_path / "py")})
    subprocess.run([program, "run", str(project), "--set", "out=%s" % (tmp_path / "cli")],
                   check=True, capture_output=True)
    for name in ("within.csv", "given.csv", "centre.csv"):
        assert (tmp_path / "py" / name).read_text() == (tmp_path / "cli" / name).read_text(), name
