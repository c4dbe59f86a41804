"""Models, parameters and kinematics over arrays; shapes, dtypes and copies."""

import numpy as np
import pytest

import kincal


def test_presets_include_the_papers_hexapod():
    names = [name for name, _ in kincal.presets()]
    assert "cube-hexapod" in names and "ur5" in names


def test_parameters_have_names_units_nominal_and_free_mask():
    m = kincal.Model.preset("cube-hexapod")
    assert len(m.parameter_names) == len(m.nominal) == len(m.free) == len(m.parameter_units)
    assert m.free.dtype == np.bool_ and m.free.sum() == 24  # the paper's 24 free parameters
    assert set(m.parameter_units) <= {"mm", "rad"}
    assert m.actuator_names == [f"leg{i}" for i in range(1, 7)]
    assert m.reading_names == ["gauge"]
    count = m.set_free("gauge.*", True)
    assert count > 0 and m.free.sum() >= 24
    with pytest.raises(ValueError, match="nomatch"):
        m.set_free("nomatch*", True)


def test_model_json_round_trip_keeps_values_and_mask():
    m = kincal.Model.preset("ur5")
    values = m.nominal + 0.25
    again = kincal.Model.from_json(m.to_json(values))
    np.testing.assert_allclose(again.nominal, values, rtol=1e-15, atol=1e-15)  # angles in degrees
    np.testing.assert_array_equal(again.free, m.free)
    assert kincal.Model.from_json(m.to_json()).parameter_names == m.parameter_names


def test_forward_then_inverse_kinematics_round_trip():
    m = kincal.Model.preset("cube-hexapod")
    rng = np.random.default_rng(3)
    home, _, status, _ = m.inverse_kinematics(np.array([[0, 0, 410, 0, 0, 0]], dtype=float))
    assert status == ["ok"]
    q = home + rng.uniform(-5, 5, size=(8, 6))
    poses, readings, status, reason = m.forward_kinematics(q)
    assert poses.shape == (8, 6) and readings.shape == (8, 1) and status == ["ok"] * 8
    q2, readings2, status2, _ = m.inverse_kinematics(poses)
    assert status2 == ["ok"] * 8
    np.testing.assert_allclose(q2, q, atol=1e-8)
    np.testing.assert_allclose(readings2, readings, atol=1e-8)


def test_inverse_kinematics_near_a_configuration_or_one_per_pose():
    m = kincal.Model.preset("ur5-urdf")
    q = np.radians([[20, -70, 80, -90, -90, 10], [20, -150, -80, 40, -90, 10],
                    [160, -120, -60, -30, 70, -20]])
    poses, _, status, _ = m.forward_kinematics(q)
    assert status == ["ok"] * 3
    seeded, _, status, _ = m.inverse_kinematics(poses, near=q)  # a start per pose
    assert status == ["ok"] * 3
    np.testing.assert_allclose(seeded, q, atol=1e-7)
    one, _, _, _ = m.inverse_kinematics(poses[1:2], near=q[1])  # one start for every pose
    np.testing.assert_allclose(one[0], q[1], atol=1e-7)
    home, _, _, _ = m.inverse_kinematics(poses)
    assert np.abs(home - q).max() > 1e-3  # from home some pose lands on another branch
    with pytest.raises(ValueError, match="one per pose"):
        m.inverse_kinematics(poses, near=q[:2])


def test_one_configuration_may_be_a_vector():
    m = kincal.Model.preset("puma560")
    poses, _, status, _ = m.forward_kinematics(np.zeros(6))
    assert poses.shape == (1, 6) and status == ["ok"]


def test_unreachable_pose_is_a_status_not_nan_garbage():
    m = kincal.Model.preset("ur5")  # about 0.85 m of reach
    q, readings, status, reason = m.inverse_kinematics([[1e5, 0, 0, 0, 0, 0], [1e5, 1, 0, 0, 0, 0]])
    assert status[0] != "ok" and reason[0]
    assert np.isnan(q).all() and np.isnan(readings).all()


def test_wrong_shapes_name_the_argument_and_the_expected_shape():
    m = kincal.Model.preset("cube-hexapod")
    with pytest.raises(ValueError, match=r"actuators: expected shape \(n, 6\), got \(6, 3\)"):
        m.forward_kinematics(np.zeros((6, 3)))
    with pytest.raises(ValueError, match=r"transposed"):
        m.forward_kinematics(np.zeros((6, 2)))
    with pytest.raises(ValueError, match=r"poses: expected shape \(n, 6\), got \(2, 2, 6\)"):
        m.inverse_kinematics(np.zeros((2, 2, 6)))
    with pytest.raises(ValueError, match=r"actuators: expected shape \(n, 6\), got \(5,\)"):
        m.forward_kinematics(np.zeros(5))
    with pytest.raises(ValueError, match=r"values: expected shape"):
        m.with_values(np.zeros(3))


def test_wrong_dtypes_raise_value_error():
    m = kincal.Model.preset("cube-hexapod")
    with pytest.raises(ValueError, match="actuators: expected real numbers"):
        m.forward_kinematics(np.zeros((2, 6), dtype=complex))
    with pytest.raises(ValueError, match="actuators: expected real numbers"):
        m.forward_kinematics(np.array([["a"] * 6]))
    with pytest.raises(ValueError, match="actuators: expected real numbers"):
        m.forward_kinematics(np.zeros((2, 6), dtype=bool))


def test_float64_c_order_is_read_without_a_copy_and_other_layouts_with_one():
    a = np.zeros((4, 6))
    assert kincal._kincal._array_address(a, "a", 6) == a.ctypes.data
    f = np.asfortranarray(np.zeros((4, 6)))
    assert kincal._kincal._array_address(f, "a", 6) != f.ctypes.data
    ints = np.zeros((4, 6), dtype=np.int32)
    assert kincal._kincal._array_address(ints, "a", 6) != ints.ctypes.data
    strided = np.zeros((4, 12))[:, ::2]
    assert kincal._kincal._array_address(strided, "a", 6) != strided.ctypes.data
    # The copies hold the same numbers: a Fortran-ordered or int array gives the same poses.
    m = kincal.Model.preset("cube-hexapod")
    q = np.full((3, 6), 440.0)
    np.testing.assert_array_equal(m.forward_kinematics(np.asfortranarray(q))[0], m.forward_kinematics(q)[0])
    np.testing.assert_array_equal(
        m.forward_kinematics(q.astype(np.int64))[0], m.forward_kinematics(q)[0]
    )


def test_errors_are_python_exceptions_never_aborts(tmp_path):
    with pytest.raises(ValueError, match="no-such-preset"):
        kincal.Model.preset("no-such-preset")
    with pytest.raises(ValueError, match="missing.json"):
        kincal.Model.load(str(tmp_path / "missing.json"))
    (tmp_path / "bad.json").write_text('{"format": "kincal-model", "version": 1}')
    with pytest.raises(ValueError, match="bad.json"):
        kincal.Model.load(str(tmp_path / "bad.json"))
    with pytest.raises(ValueError, match="<string>: malformed JSON: parse error at line 1"):
        kincal.Model.from_json("{")


def test_a_model_pickles_as_its_model_file():
    import pickle

    m = kincal.Model.preset("ur5")
    m.set_free("base.*", False)
    again = pickle.loads(pickle.dumps(m))
    assert again.parameter_names == m.parameter_names and again.source == "ur5"
    np.testing.assert_allclose(again.nominal, m.nominal, rtol=1e-15, atol=1e-15)
    np.testing.assert_array_equal(again.free, m.free)
