"""A sensor written in Python: finite-difference checks, then a calibration with it."""

import numpy as np
import pytest

import kincal
import kincal.sensors


def skew(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


class PythonGauge(kincal.sensors.Sensor):
    """A length gauge from a base point to a platform point, with an offset: the paper's
    sensor, written again in Python."""

    type = "python-gauge"

    def __init__(self, base=(0.0, 0.0, 0.0), platform=(0.0, 0.0, 0.0)):
        params = [(f"pg.base.{a}", v, "mm") for a, v in zip("xyz", base)]
        params += [(f"pg.platform.{a}", v, "mm") for a, v in zip("xyz", platform)]
        params.append(("pg.offset", 0.0, "mm"))
        super().__init__("pg", ["pg"], ["mm"], params)

    def predict(self, params, position, rotation, jacobians):
        b, p, offset = params[0:3], params[3:6], params[6]
        world = rotation @ p + position
        d = world - b
        length = np.linalg.norm(d)
        reading = np.array([length + offset])
        if not jacobians:
            return reading, None, None
        u = d / length
        # t <- t + dt, R <- exp([dw]x) R: d(world) = dt - [R p]x dw
        J_pose = np.concatenate([u, -u @ skew(rotation @ p)]).reshape(1, 6)
        J_params = np.concatenate([-u, u @ rotation, [1.0]]).reshape(1, 7)
        return reading, J_pose, J_params


class WrongJacobian(PythonGauge):
    def predict(self, params, position, rotation, jacobians):
        reading, J_pose, J_params = super().predict(params, position, rotation, jacobians)
        if J_params is not None:
            J_params = J_params * 1.01
        return reading, J_pose, J_params


def gauge_model(sensor):
    base = kincal.Model.preset("cube-hexapod")
    base.set_free("*", False)
    return kincal.sensors.with_sensors(base, [sensor])


def test_python_sensor_passes_the_finite_difference_checks():
    model = gauge_model(PythonGauge((10.0, -20.0, 0.0), (5.0, 15.0, 0.0)))
    worst = kincal.sensors.check(model)
    assert worst["J_reading_params"] < 1e-6 and worst["J_reading_pose"] < 1e-6


def test_a_wrong_jacobian_fails_the_checks():
    model = gauge_model(WrongJacobian((10.0, -20.0, 0.0), (5.0, 15.0, 0.0)))
    with pytest.raises(AssertionError, match="J_reading_params"):
        kincal.sensors.check(model)


def test_python_sensor_calibrates():
    model = gauge_model(PythonGauge((10.0, -20.0, 0.0), (5.0, 15.0, 0.0)))
    assert model.free.sum() == 7 and model.reading_names == ["pg"]
    result = kincal.sensors.simulate(model, poses=40, seed=3)
    assert result.termination == "converged", result.message
    free = result.free_indices
    np.testing.assert_allclose(result.estimate[free], result.truth[free], atol=1e-6)
    assert result.parameter_rms_error_mm < 1e-6


def test_errors_in_predict_reach_python():
    class Broken(PythonGauge):
        def predict(self, params, position, rotation, jacobians):
            raise RuntimeError("broken sensor")

    with pytest.raises(RuntimeError, match="broken sensor"):
        kincal.sensors.simulate(gauge_model(Broken()), poses=10)


def test_sensor_definitions_are_checked():
    class BadUnit(PythonGauge):
        def __init__(self):
            super().__init__()
            self.reading_units = ["inch"]

    with pytest.raises(ValueError, match="inch"):
        gauge_model(BadUnit())
