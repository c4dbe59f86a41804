"""Measurements: kincal's CSV format to and from numpy arrays."""

import numpy as np
import pytest

import kincal


def test_round_trip_keeps_every_bit_and_nan_for_missing(tmp_path):
    model = kincal.Model.preset("ur5")
    rng = np.random.default_rng(5)
    a = rng.normal(size=(5, len(model.actuator_names)))
    r = rng.normal(size=(5, len(model.reading_names))) * 100
    r[1, :] = np.nan  # a configuration whose point was not measured
    m = kincal.Measurements(a, r, model.actuator_names, model.reading_names)
    path = tmp_path / "d.csv"
    m.write(path, comment="made by a test")
    back = kincal.Measurements.read(path, model)
    np.testing.assert_array_equal(back.actuators, a)
    np.testing.assert_array_equal(back.readings, r)
    assert np.isnan(back.readings[1]).all()
    # The C++ writer gives the same numbers.
    (tmp_path / "c.csv").write_text(m.to_csv(model))
    np.testing.assert_array_equal(kincal.Measurements.read(tmp_path / "c.csv", model).readings, r)


def test_unit_suffixes_are_converted(tmp_path):
    model = kincal.Model.preset("ur5")
    names = [n + "_deg" for n in model.actuator_names]
    path = tmp_path / "d.csv"
    path.write_text(",".join(names + model.reading_names) + "\n" + ",".join(["90"] * 6 + ["1"] * len(model.reading_names)) + "\n")
    m = kincal.Measurements.read(path, model)
    np.testing.assert_allclose(m.actuators, np.full((1, 6), np.pi / 2))


def test_errors_name_the_file_and_line(tmp_path):
    model = kincal.Model.preset("cube-hexapod")
    path = tmp_path / "bad.csv"
    path.write_text("leg1,leg2,leg3,leg4,leg5,leg6,gauge\n1,2,3,4,5,x,7\n")
    with pytest.raises(ValueError, match=r"bad.csv:2"):
        kincal.Measurements.read(path, model)


def test_rows_must_agree():
    model = kincal.Model.preset("cube-hexapod")
    with pytest.raises(ValueError, match=r"readings: expected 2 rows"):
        kincal._kincal.measurements_to_csv(np.zeros((2, 6)), np.zeros((3, 1)), model)


def test_calibration_residuals_and_jacobian_match_finite_differences(tmp_path):
    model = kincal.Model.preset("cube-hexapod")
    path = tmp_path / "d.csv"
    kincal.simulate(case=3, seed=7, write_data=str(path))
    m = kincal.Measurements.read(path, model)
    r, J, names = m.residuals(model)
    assert r.shape == (40,) and J.shape == (40, 24) and len(names) == 24
    free = np.flatnonzero(model.free)
    x = model.nominal
    numeric = np.empty_like(J)
    for k, i in enumerate(free):
        up, down = x.copy(), x.copy()
        up[i] += 1e-6
        down[i] -= 1e-6
        numeric[:, k] = (kincal._kincal.calibration_residuals(model, m.actuators, m.readings, up)[0]
                         - kincal._kincal.calibration_residuals(model, m.actuators, m.readings, down)[0]) / 2e-6
    assert np.max(np.abs(J - numeric) / (1 + np.abs(numeric))) < 1e-6
