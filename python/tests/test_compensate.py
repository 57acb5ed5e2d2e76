# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""compensate: the same joints as activecal_compensate, and their meaning."""
import json
import subprocess

import numpy as np
import pytest

import activecal
from conftest import PUMA, program, run


@pytest.fixture(scope="module")
def calibrated(puma, tmp_path_factory):
    design = activecal.select(puma, levels=3, num_poses=30, seed=2,
                              restarts=2)
    m = activecal.simulate(puma, design.joint_angles, noise_m=1e-5, seed=1)
    estimate = activecal.identify(puma, m, model_selection="none")
    path = tmp_path_factory.mktemp("compensate") / "calibrated.yaml"
    estimate.save(str(path))
    return activecal.load_robot(str(path)), path


def taught_program(robot, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = robot.joint_limits.T
    return lo + 0.2 * (hi - lo) + 0.6 * (hi - lo) * rng.random(
        (n, robot.num_joints))


def test_same_program_as_the_program(puma, calibrated, tmp_path):
    robot, path = calibrated
    q = taught_program(puma, 15, 3)
    poses = tmp_path / "program.csv"
    activecal.write_poses(puma, str(poses), q)
    out = tmp_path / "compensated.csv"
    json_out = tmp_path / "compensation.json"
    run([program("activecal_compensate"), f"--robot={path}",
         f"--nominal={PUMA}", f"--poses_csv={poses}", f"--out={out}",
         f"--json_out={json_out}"])
    expected = json.loads(json_out.read_text())
    c = activecal.compensate(robot, program=q, nominal=puma)
    assert c.all_converged == expected["all_converged"]
    assert c.status == [t["status"] for t in expected["targets"]]
    np.testing.assert_array_equal(
        c.joint_angles, np.array([t["joints"] for t in expected["targets"]]))
    assert c.max_position_error_m == expected["max_ik_residual_m"]
    assert c.max_joint_change == expected["max_joint_change"]
    mine = tmp_path / "mine.csv"
    c.save(str(mine))
    assert mine.read_bytes() == out.read_bytes()


def test_compensated_joints_reach_what_the_program_meant(puma, calibrated):
    robot, _ = calibrated
    q = taught_program(puma, 10, 4)
    c = activecal.compensate(robot, program=q, nominal=puma)
    assert c.all_converged and c.status == ["converged"] * 10
    # The calibrated robot at the new joints reaches the target points ...
    reached = robot.forward(c.joint_angles)
    np.testing.assert_allclose(reached, c.target_points, rtol=0, atol=1e-8)
    assert np.all(c.position_error_m < 1e-8)
    # ... which the uncompensated program misses.
    assert np.max(np.linalg.norm(robot.forward(q) - c.target_points,
                                 axis=1)) > 1e-5
    # Cartesian targets: the same points reached, from the program's joints.
    t = activecal.compensate(robot, targets=c.target_points, starts=q)
    np.testing.assert_allclose(robot.forward(t.joint_angles), c.target_points,
                               rtol=0, atol=1e-8)


def test_compensate_bad_input(puma, calibrated):
    robot, _ = calibrated
    q = taught_program(puma, 3, 5)
    with pytest.raises(ValueError, match="give exactly one of program"):
        activecal.compensate(robot)
    with pytest.raises(ValueError, match="program needs nominal"):
        activecal.compensate(robot, program=q)
    with pytest.raises(ValueError, match="match must be position or pose"):
        activecal.compensate(robot, program=q, nominal=puma, match="joint")
    with pytest.raises(ValueError, match=r"targets: expected an array of shape \(n, 3\)"):
        activecal.compensate(robot, targets=np.zeros((3, 2)))
    with pytest.raises(ValueError, match="match='pose' needs the target orientations"):
        activecal.compensate(robot, targets=np.zeros((3, 3)), match="pose")
    # Issue 26: a NaN rotation vector was the identity, its target
    # "converged"; every value given must be finite.
    points = robot.forward(q)
    rotations = np.zeros((3, 3))
    for bad in (np.nan, np.inf, -np.inf):
        r = rotations.copy()
        r[1, 2] = bad
        with pytest.raises(ValueError,
                           match=r"rotations row 1: value 2 is not finite"):
            activecal.compensate(robot, targets=points, rotations=r,
                                 match="pose")
        with pytest.raises(ValueError,
                           match=r"rotations row 1: value 2 is not finite"):
            activecal.compensate(robot, targets=points, rotations=r)
        p = points.copy()
        p[2, 0] = bad
        with pytest.raises(ValueError,
                           match=r"targets row 2: value 0 is not finite"):
            activecal.compensate(robot, targets=p)
        s = q.copy()
        s[0, 3] = bad
        with pytest.raises(ValueError, match=r"starts row 0: .*not finite"):
            activecal.compensate(robot, targets=points, starts=s)
        with pytest.raises(ValueError, match=r"program row 0: .*not finite"):
            activecal.compensate(robot, program=s, nominal=puma)
    with pytest.raises(ValueError, match="compensate: unknown option 'tolerance'"):
        activecal.compensate(robot, program=q, nominal=puma, tolerance=1)
    ur10 = activecal.load_robot(str(PUMA).replace("puma560.yaml", "ur10.urdf"),
                                tip_link="tool0")
    with pytest.raises(ValueError, match="robot and nominal: "):
        activecal.compensate(robot, program=q, nominal=ur10)


def test_targets_file_same_as_the_program(puma, calibrated, tmp_path):
    robot, path = calibrated
    q = taught_program(puma, 6, 6)
    points = robot.forward(q) + 1e-4
    lines = ["pose_index,x_m,y_m,z_m"] + [
        f"{10 + i},{p[0]!r},{p[1]!r},{p[2]!r}" for i, p in enumerate(points)]
    targets_csv = tmp_path / "targets.csv"
    targets_csv.write_text("\n".join(lines) + "\n")
    read, rotations, starts, indices = activecal.read_targets(
        robot, str(targets_csv))
    np.testing.assert_array_equal(read, points)
    assert rotations is None and starts is None
    assert list(indices) == list(range(10, 16))
    out = tmp_path / "out.csv"
    json_out = tmp_path / "out.json"
    # Each target starts from the previous result: here one of them ends
    # at a joint limit (the program's exit status 2), which compensate
    # reports in `status`, not as an exception.
    done = subprocess.run([program("activecal_compensate"), f"--robot={path}",
                           f"--targets_csv={targets_csv}", f"--out={out}",
                           f"--json_out={json_out}"],
                          capture_output=True, text=True)
    assert done.returncode in (0, 2), done.stderr
    expected = json.loads(json_out.read_text())
    c = activecal.compensate(robot, targets=read, pose_indices=indices)
    assert c.status == [t["status"] for t in expected["targets"]]
    assert c.all_converged == expected["all_converged"] == (done.returncode == 0)
    assert c.messages == [t["message"] for t in expected["targets"]]
    np.testing.assert_array_equal(
        c.joint_angles, np.array([t["joints"] for t in expected["targets"]]))
    mine = tmp_path / "mine.csv"
    c.save(str(mine))
    assert mine.read_bytes() == out.read_bytes()
    with pytest.raises(ValueError, match="missing.csv"):
        activecal.read_targets(robot, str(tmp_path / "missing.csv"))
