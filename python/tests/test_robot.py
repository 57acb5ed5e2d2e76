# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Robot: loading, parameters, forward kinematics and the Jacobian."""
import numpy as np
import pytest

import activecal
from conftest import PUMA, UR10


def test_puma_file_matches_builtin(puma):
    builtin = activecal.puma560()
    assert puma.parameter_names == builtin.parameter_names
    np.testing.assert_array_equal(puma.nominal, builtin.nominal)
    np.testing.assert_array_equal(puma.true_parameters,
                                  builtin.true_parameters)
    assert puma.num_joints == 6
    assert len(puma.parameter_names) == puma.num_parameters == 48
    assert puma.free.dtype == bool and puma.free.sum() == puma.num_free
    # free_parameter_names are the names at the free flags, in order.
    names = np.array(puma.parameter_names)
    assert list(names[puma.free]) == puma.free_parameter_names
    assert set(puma.parameter_units) <= {"m", "rad", "1"}


def test_nominal_is_a_copy(puma):
    a = puma.nominal
    a[:] = 0
    assert np.any(puma.nominal != 0)


def test_forward_batch_and_frame(puma):
    rng = np.random.default_rng(1)
    lo, hi = puma.joint_limits.T
    q = lo + (hi - lo) * rng.random((5, puma.num_joints))
    points = puma.forward(q)
    assert points.shape == (5, 3)
    for k in range(5):
        np.testing.assert_array_equal(points[k], puma.forward(q[k]))
        T = puma.frame(q[k])
        np.testing.assert_allclose(T[:3, 3], points[k], rtol=0, atol=1e-12)
        np.testing.assert_allclose(T[:3, :3] @ T[:3, :3].T, np.eye(3),
                                   atol=1e-12)
        np.testing.assert_array_equal(T[3], [0, 0, 0, 1])
    # The true parameters move the point: forward takes a full vector.
    moved = puma.forward(q[0], parameters=puma.true_parameters)
    assert np.linalg.norm(moved - points[0]) > 1e-3


@pytest.mark.parametrize("which", ["puma", "ur10"])
def test_jacobian_is_the_derivative_of_forward(puma, ur10, which):
    robot = puma if which == "puma" else ur10.with_parameter_set("full")
    assert robot.num_free > 0
    q = np.array([0.1, -1.0, 1.2, -0.3, 0.5, 0.7])
    J = robot.jacobian(q)
    assert J.shape == (3, robot.num_free)
    free = np.flatnonzero(robot.free)
    h = 1e-6
    for col, i in enumerate(free):
        plus = robot.nominal.copy()
        minus = robot.nominal.copy()
        plus[i] += h
        minus[i] -= h
        numeric = (robot.forward(q, parameters=plus) -
                   robot.forward(q, parameters=minus)) / (2 * h)
        np.testing.assert_allclose(J[:, col], numeric, rtol=0, atol=1e-6)
    batch = robot.jacobian(np.vstack([q, q]))
    assert batch.shape == (2, 3, robot.num_free)
    np.testing.assert_array_equal(batch[1], J)
    assert robot.jacobian(q, type="pose").shape == (6, robot.num_free)


def test_urdf_chain_and_joint_names(ur10):
    assert ur10.is_urdf
    assert ur10.num_joints == 6
    assert ur10.joint_names[0] == "shoulder_pan_joint"
    assert ur10.true_parameters is None
    assert ur10.num_free == 0  # a URDF names no free parameters
    full = ur10.with_parameter_set("full")
    assert full.num_free > ur10.with_parameter_set("offsets").num_free > 0
    assert ur10.num_free == 0  # with_parameter_set made a copy
    with pytest.raises(ValueError, match="parameter_set must be"):
        ur10.with_parameter_set("most")
    shorter = activecal.load_robot(UR10, tip_link="wrist_3_link")
    assert shorter.num_joints == 6
    with pytest.raises(ValueError, match="2 leaves"):
        activecal.load_robot(UR10)


def test_save_reads_back(puma, tmp_path):
    path = tmp_path / "robot.yaml"
    values = puma.true_parameters
    puma.save(str(path), parameters=values)
    again = activecal.load_robot(str(path))
    np.testing.assert_array_equal(again.nominal, values)
    np.testing.assert_array_equal(again.free, puma.free)


def test_bad_input_raises_value_error_with_the_message(puma, tmp_path):
    with pytest.raises(ValueError, match="no_such_robot.yaml"):
        activecal.load_robot(str(tmp_path / "no_such_robot.yaml"))
    bad = tmp_path / "bad.yaml"
    bad.write_text("name: x\nlinks: 3\n")
    with pytest.raises(ValueError, match=r"bad\.yaml:\d+"):
        activecal.load_robot(str(bad))
    with pytest.raises(ValueError, match="base_link and --tip_link|URDF"):
        activecal.load_robot(PUMA, tip_link="tool0")
    with pytest.raises(ValueError, match="expected 6 values, got 5"):
        puma.forward(np.zeros(5))
    with pytest.raises(ValueError, match=r"expected an array of shape \(n, 6\)"):
        puma.forward(np.zeros((2, 5)))
    with pytest.raises(ValueError, match=r"got shape \(2, 3, 6\)"):
        puma.jacobian(np.zeros((2, 3, 6)))
    with pytest.raises(ValueError, match="expected an array of numbers"):
        puma.forward(["a", "b", "c", "d", "e", "f"])
    with pytest.raises(ValueError, match="not finite"):
        puma.forward([0, 0, np.nan, 0, 0, 0])
    with pytest.raises(ValueError, match="outside its range"):
        puma.forward([0, 0, 0, 0, 0, 100.0])
    # A measured reading may lie a few degrees beyond its range, for the
    # Jacobian as for forward (joint 2's range ends at 170 deg).
    beyond = np.radians([0, 172, 0, 0, 0, 0])
    assert puma.jacobian(beyond).shape == (3, puma.num_free)
    with pytest.raises(ValueError, match="q row 1: .*outside its range"):
        puma.jacobian(np.vstack([beyond, np.radians([0, 180, 0, 0, 0, 0])]))
    with pytest.raises(ValueError, match=r"parameters: expected an array of shape \(48,\)"):
        puma.forward(np.zeros(6), parameters=np.zeros(3))
    with pytest.raises(ValueError, match="marker must be in"):
        puma.forward(np.zeros(6), marker=3)
    # Integer arrays and lists convert.
    np.testing.assert_array_equal(puma.forward([0, 0, 0, 0, 0, 0]),
                                  puma.forward(np.zeros(6)))
