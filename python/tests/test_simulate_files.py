# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""simulate and the CSV files: the same measurements as activecal_simulate."""
import numpy as np
import pytest

import activecal
from conftest import PUMA, program, run


def lattice_poses(robot, n, seed):
    design = activecal.select(robot, algorithm="greedy", levels=3,
                              num_poses=n, seed=seed, certificate=False)
    return design.joint_angles, design.pose_indices


@pytest.mark.parametrize("kind", ["position", "pose", "distance"])
def test_same_measurements_as_the_program(puma, tmp_path, kind):
    joints, indices = lattice_poses(puma, 12, 1)
    poses = tmp_path / "poses.csv"
    activecal.write_poses(puma, str(poses), joints, indices)
    out = tmp_path / "program.csv"
    run([program("activecal_simulate"), f"--robot={PUMA}",
         f"--poses_csv={poses}", f"--out={out}", f"--type={kind}",
         "--noise_m=0.0005", "--rotation_noise_rad=0.002", "--seed=9"])
    m = activecal.simulate(puma, joints, noise_m=0.0005,
                           rotation_noise_rad=0.002, seed=9, type=kind)
    assert len(m) == (11 if kind == "distance" else 12)
    assert set(m.types) == {kind}
    mine = tmp_path / "python.csv"
    activecal.write_measurements(puma, str(mine), m)
    # The same file, byte for byte, and the same numbers read back.
    assert mine.read_bytes() == out.read_bytes()
    again = activecal.read_measurements(puma, str(out))
    for field in ("joints", "positions", "rotations", "distances", "joints2"):
        np.testing.assert_array_equal(getattr(again, field),
                                      getattr(m, field))


def test_simulated_points_are_true_forward_kinematics_plus_noise(puma):
    joints, _ = lattice_poses(puma, 20, 2)
    exact = activecal.simulate(puma, joints, noise_m=0.0, seed=1)
    np.testing.assert_array_equal(
        exact.positions, puma.forward(joints, parameters=puma.true_parameters))
    noisy = activecal.simulate(puma, joints, noise_m=0.01, seed=1)
    noise = noisy.positions - exact.positions
    assert 0.005 < noise.std() < 0.02
    again = activecal.simulate(puma, joints, noise_m=0.01, seed=1)
    np.testing.assert_array_equal(again.positions, noisy.positions)
    other = activecal.simulate(puma, joints, noise_m=0.01, seed=2)
    assert np.any(other.positions != noisy.positions)
    # The distance between consecutive poses.
    dist = activecal.simulate(puma, joints, noise_m=0.0, type="distance")
    np.testing.assert_allclose(
        dist.distances,
        np.linalg.norm(np.diff(exact.positions, axis=0), axis=1), rtol=1e-12)
    np.testing.assert_array_equal(dist.joints2, joints[1:])
    assert np.all(np.isnan(dist.positions))


def test_measurements_from_arrays_and_round_trip(puma, tmp_path):
    joints, _ = lattice_poses(puma, 10, 3)
    points = puma.forward(joints)
    m = activecal.Measurements("position", joints, positions=points,
                               sigma_m=np.full((10, 3), 1e-4))
    assert len(m) == 10 and m.types == ["position"] * 10
    path = tmp_path / "m.csv"
    activecal.write_measurements(puma, str(path), m)
    back = activecal.read_measurements(puma, str(path))
    np.testing.assert_array_equal(back.joints, joints)
    np.testing.assert_array_equal(back.positions, points)
    np.testing.assert_array_equal(back.sigma_m, m.sigma_m)
    # Millimetres and degrees read back to rounding.
    mm = tmp_path / "mm.csv"
    activecal.write_measurements(puma, str(mm), m, millimetres=True,
                                 joint_degrees=True)
    assert "x_mm" in mm.read_text().splitlines()[0]
    np.testing.assert_allclose(
        activecal.read_measurements(puma, str(mm)).positions, points,
        rtol=1e-14, atol=1e-14)
    # Indexing: ints, slices, masks, index arrays; + concatenates.
    assert len(m[2:5]) == 3
    np.testing.assert_array_equal(m[[4, 1]].joints, joints[[4, 1]])
    np.testing.assert_array_equal(m[m.positions[:, 2] > np.median(points[:, 2])].positions,
                                  points[points[:, 2] > np.median(points[:, 2])])
    assert len(m[:4] + m[4:]) == 10
    with pytest.raises(IndexError):
        m[[10]]


def test_file_errors_name_the_file_and_line(puma, tmp_path):
    with pytest.raises(ValueError, match="missing.csv"):
        activecal.read_measurements(puma, str(tmp_path / "missing.csv"))
    bad = tmp_path / "bad.csv"
    bad.write_text("q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m\n"
                   "0,0,0,0,0,abc,1,2,3\n")
    with pytest.raises(ValueError, match=r"bad\.csv:2: q6_rad: expected a number, got 'abc'"):
        activecal.read_measurements(puma, str(bad))
    with pytest.raises(ValueError, match=r"joint_angles: expected an array of shape \(n, 6\)"):
        activecal.simulate(puma, np.zeros(6))
    with pytest.raises(ValueError, match="type must be position, pose or distance"):
        activecal.simulate(puma, np.zeros((2, 6)), type="angle")
    with pytest.raises(ValueError, match="simulate: unknown option 'noise'"):
        activecal.simulate(puma, np.zeros((2, 6)), noise=0.1)
    with pytest.raises(ValueError, match="type=position needs positions"):
        activecal.Measurements("position", np.zeros((2, 6)))
    with pytest.raises(ValueError, match="positions: expected 2 rows"):
        activecal.Measurements("position", np.zeros((2, 6)),
                               positions=np.zeros((3, 3)))
    with pytest.raises(ValueError, match="pose_indices: expected 2 values"):
        activecal.write_poses(puma, str(tmp_path / "p.csv"), np.zeros((2, 6)),
                              [1, 2, 3])
    # Issue 26: labels every reader refuses were written.
    with pytest.raises(ValueError, match=r"pose_indices\[0\] = -1: a pose "
                       r"label must be an integer in \[0, 9e15\]"):
        activecal.write_poses(puma, str(tmp_path / "p.csv"), np.zeros((2, 6)),
                              [-1, 2])
    assert not (tmp_path / "p.csv").exists()
    # A program may repeat a label (a pool may not).
    activecal.write_poses(puma, str(tmp_path / "p.csv"), np.zeros((2, 6)),
                          [3, 3])
    with pytest.raises(ValueError, match="cannot write"):
        activecal.write_poses(puma, str(tmp_path / "no" / "p.csv"),
                              np.zeros((2, 6)))


def test_joined_measurements_of_different_robots_do_not_crash(puma):
    a = activecal.Measurements("position", np.zeros((2, 6)),
                               positions=np.zeros((2, 3)))
    b = activecal.Measurements("position", np.zeros((2, 7)),
                               positions=np.ones((2, 3)))
    both = a + b
    joints = both.joints
    assert joints.shape == (4, 6)
    assert np.all(joints[:2] == 0) and np.all(np.isnan(joints[2:]))
    np.testing.assert_array_equal(both.positions[2:], np.ones((2, 3)))
    with pytest.raises(ValueError, match="measurement 2: joints: expected 6 joint values, got 7"):
        activecal.write_measurements(puma, "/dev/null", both)
    with pytest.raises(ValueError, match="measured: expected activecal.Measurements, got list"):
        activecal.select(puma, criterion="task_rms", measured=[1, 2])
