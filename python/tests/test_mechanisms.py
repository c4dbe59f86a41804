"""A mechanism written in Python: kincal's conformance checks of its Jacobians pass (and fail
on a wrong one), and it calibrates with a Python sensor."""

import numpy as np
import pytest

import kincal.mechanisms
import kincal.sensors


class PlanarArm(kincal.mechanisms.Mechanism):
    """Two revolute joints about z: theta_i = q_i + offset_i, links l1, l2 in the plane."""

    type = "test-planar-2r"
    actuators = [("joint1", "rad", 0.6), ("joint2", "rad", 0.6)]
    parameters = [("arm.base.x", 0.0, "mm"), ("arm.base.y", 0.0, "mm"),
                  ("arm.l1", 300.0, "mm", True), ("arm.l2", 200.0, "mm", True),
                  ("arm.offset1", 0.0, "rad", True), ("arm.offset2", 0.0, "rad", True)]
    home_actuators = [0.3, 0.9]
    flip = 1.0  # -1 in the test of a wrong Jacobian

    def forward(self, params, q, jacobians):
        bx, by, l1, l2, o1, o2 = params
        t1 = q[0] + o1
        t12 = t1 + q[1] + o2
        position = np.array([bx + l1 * np.cos(t1) + l2 * np.cos(t12),
                             by + l1 * np.sin(t1) + l2 * np.sin(t12), 0.0])
        c, s = np.cos(t12), np.sin(t12)
        rotation = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        if not jacobians:
            return position, rotation, None, None
        d_t1 = np.array([-l1 * np.sin(t1) - l2 * np.sin(t12), l1 * np.cos(t1) + l2 * np.cos(t12), 0])
        d_t12 = np.array([-l2 * np.sin(t12), l2 * np.cos(t12), 0.0])
        z = np.array([0.0, 0.0, 1.0])
        J_params = np.zeros((6, 6))
        J_params[0, 0] = J_params[1, 1] = 1.0
        J_params[:3, 2] = [np.cos(t1), np.sin(t1), 0.0]
        J_params[:3, 3] = [np.cos(t12), np.sin(t12), 0.0]
        J_params[:, 4] = np.concatenate([d_t1, z])
        J_params[:, 5] = np.concatenate([d_t12, self.flip * z])
        J_actuators = J_params[:, 4:6].copy()
        J_actuators[:, 1] = np.concatenate([d_t12, z])
        return position, rotation, J_params, J_actuators


class Tracker(kincal.sensors.Sensor):
    """The arm's end point, seen by a tracker with an unknown offset."""

    type = "test-tracker"

    def __init__(self):
        super().__init__("tracker", ["tracker.x", "tracker.y", "tracker.z"], ["mm"] * 3,
                         [("tracker.x0", 10.0, "mm"), ("tracker.y0", -5.0, "mm"),
                          ("tracker.z0", 2.0, "mm")], position_reading_index=0)

    def predict(self, params, position, rotation, jacobians):
        reading = position + params
        if not jacobians:
            return reading, None, None
        return reading, np.hstack([np.eye(3), np.zeros((3, 3))]), np.eye(3)


def test_a_python_mechanism_passes_kincals_checks_and_calibrates():
    model = kincal.mechanisms.model(PlanarArm(), [Tracker()])
    assert model.free.sum() == 4 + 3
    checks = kincal.mechanisms.check(model)
    assert [name for name, *_ in checks] == ["J_pose_params of the mechanism",
                                             "J_pose_actuators of the mechanism"]
    assert all(passed and worst <= tolerance for _, passed, worst, tolerance, _ in checks)
    kincal.sensors.check(model)
    run = kincal.sensors.simulate(model, poses=20, noise_mm=0.0, seed=3, solver="lm")
    assert run.termination == "converged", run.message
    assert run.parameter_rms_error_mm < 1e-6 and run.parameter_rms_error_rad < 1e-9
    np.testing.assert_allclose(run.estimate[run.free_indices], run.truth[run.free_indices],
                               atol=1e-6)


def test_a_wrong_mechanism_jacobian_fails_the_check_naming_it():
    wrong = PlanarArm()
    wrong.flip = -1.0
    model = kincal.mechanisms.model(wrong, [Tracker()])
    with pytest.raises(AssertionError, match="J_pose_params"):
        kincal.mechanisms.check(model)


def test_bad_mechanism_definitions_are_value_errors():
    class NoUnit(PlanarArm):
        actuators = [("joint1", "deg", 0.6), ("joint2", "rad", 0.6)]

    with pytest.raises(ValueError, match="unit 'deg'"):
        kincal.mechanisms.model(NoUnit(), [Tracker()])

    class Raises(PlanarArm):
        def forward(self, params, q, jacobians):
            raise RuntimeError("boom in forward")

    with pytest.raises(RuntimeError, match="boom in forward"):
        kincal.mechanisms.model(Raises(), [Tracker()])
