# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""select: the same designs as activecal_select, and what they mean."""
import json
import threading

import numpy as np
import pytest

import activecal
from conftest import PUMA, SOURCE_DIR, program, run

# Small and quick: a 3-level lattice (729 poses), few restarts.
SMALL = dict(levels=3, num_poses=20, restarts=2)


def program_design(tmp_path, algorithm, seed, criterion="det", extra=()):
    json_out = tmp_path / f"{algorithm}.json"
    poses_out = tmp_path / f"{algorithm}.csv"
    run([program("activecal_select"), f"--robot={PUMA}",
         f"--levels={SMALL['levels']}", f"--num_poses={SMALL['num_poses']}",
         f"--restarts={SMALL['restarts']}", f"--algorithm={algorithm}",
         f"--criterion={criterion}", f"--seed={seed}",
         f"--json_out={json_out}", f"--poses_csv={poses_out}", *extra])
    return json.loads(json_out.read_text()), poses_out


@pytest.mark.parametrize("algorithm,criterion", [
    ("fedorov", "d"), ("eae", "d"), ("detmax", "d"), ("greedy", "d"),
    ("fedorov", "task_rms")])
def test_same_design_as_the_program(puma, tmp_path, algorithm, criterion):
    seed = 3
    expected, poses_csv = program_design(
        tmp_path, algorithm, seed,
        criterion="det" if criterion == "d" else criterion)
    design = activecal.select(puma, algorithm=algorithm, seed=seed,
                              criterion=criterion, **SMALL)
    # Bit for bit: the indices, log det, bound and history the program
    # wrote (JSON numbers read back exactly).
    assert list(design.pose_indices) == expected["pose_indices"]
    assert design.log10_det == expected["log10_det"]
    assert design.efficiency_lower_bound == expected["efficiency_lower_bound"]
    # (JSON has no -inf: a singular start, greedy's first steps, is null.)
    assert list(design.history) == [-np.inf if x is None else x
                                    for x in expected["history_log10_det"]]
    assert design.predicted_task_rms_m == expected["predicted_task_rms_m"]
    assert design.algorithm == expected["algorithm"]
    assert design.oi == expected["oi"]
    if criterion == "d":
        assert (design.log10_det_upper_bound ==
                expected["log10_det_upper_bound"])
    assert design.free_parameters == expected["free_parameters"]
    np.testing.assert_array_equal(design.joint_angles,
                                  np.array(expected["joint_angles_rad"]))
    joints, indices = activecal.read_poses(puma, str(poses_csv))
    np.testing.assert_array_equal(design.joint_angles, joints)
    np.testing.assert_array_equal(design.pose_indices, indices)




def test_design_meaning(puma):
    design = activecal.select(puma, seed=5, **SMALL)
    n = SMALL["num_poses"]
    assert design.joint_angles.shape == (n, puma.num_joints)
    assert len(set(design.pose_indices)) == n
    assert design.num_parameters == puma.num_free
    assert design.pool_size == SMALL["levels"] ** puma.num_joints
    # log10 det is that of X^T X, X the stacked point Jacobians of the
    # chosen poses (the robot file's free parameters, at nominal).
    X = puma.jacobian(design.joint_angles).reshape(-1, puma.num_free)
    sign, logdet = np.linalg.slogdet(X.T @ X)
    assert sign > 0
    assert logdet / np.log(10) == pytest.approx(design.log10_det, rel=1e-9)
    # The certificate: 0 < efficiency <= 1, the design below the bound.
    assert 0 < design.efficiency_lower_bound <= 1
    assert design.log10_det <= design.log10_det_upper_bound
    # The best restart's history ends at the design.
    assert design.history[-1] == pytest.approx(design.log10_det, abs=1e-9)
    assert design.history[0] <= design.history[-1]
    # The approximate design's M(w) has weights of sum 1: det(n M(w)) is
    # the bound's scale.
    approx = design.approximate
    assert approx["log10_det"] + puma.num_free * np.log10(n) >= design.log10_det
    assert np.sum(approx["weights"]) == pytest.approx(1.0)
    assert design.termination_type == "CONVERGENCE"
    assert design.oi > 0
    assert "fedorov" in design.report()


def test_pool_array_rows_and_labels(puma):
    rng = np.random.default_rng(7)
    lo, hi = puma.joint_limits.T
    pool = lo + (hi - lo) * rng.random((600, puma.num_joints))
    labels = np.arange(600) * 10 + 1000
    design = activecal.select(puma, pool=pool, pool_indices=labels,
                              num_poses=15, restarts=2, seed=2)
    rows = design.pool_rows
    np.testing.assert_array_equal(design.joint_angles, pool[rows])
    np.testing.assert_array_equal(design.pose_indices, labels[rows])
    # Without labels, the labels are the rows.
    plain = activecal.select(puma, pool=pool, num_poses=15, restarts=2,
                             seed=2)
    np.testing.assert_array_equal(plain.pose_indices, rows)


def test_lattice_design_is_the_same_over_the_lattice_as_an_array(puma):
    design = activecal.select(puma, seed=4, **SMALL)
    # The whole lattice as an array (its rows via a design of every pose is
    # too slow; the chosen rows must lie on the lattice levels instead).
    lo, hi = puma.joint_limits.T
    levels = SMALL["levels"]
    for j in range(puma.num_joints):
        grid = np.linspace(lo[j], hi[j], levels)
        full_turn = np.isclose(hi[j] - lo[j], 2 * np.pi)
        if full_turn:
            grid = lo[j] + (hi[j] - lo[j]) * np.arange(levels) / levels
        for value in design.joint_angles[:, j]:
            assert np.min(np.abs(grid - value)) < 1e-12


def test_results_do_not_depend_on_threads(puma):
    one = activecal.select(puma, seed=6, num_threads=1, **SMALL)
    two = activecal.select(puma, seed=6, num_threads=2, **SMALL)
    assert list(one.pose_indices) == list(two.pose_indices)
    assert one.log10_det == two.log10_det
    assert one.efficiency_lower_bound == two.efficiency_lower_bound


def test_progress_callback(puma):
    calls = []
    lock = threading.Lock()

    def progress(stage, done, total):
        with lock:
            calls.append((stage, done, total))

    activecal.select(puma, seed=1, progress=progress, **SMALL)
    stages = {c[0] for c in calls}
    assert {"jacobians", "approximate", "restarts"} <= stages
    restarts = [c for c in calls if c[0] == "restarts"]
    assert max(c[1] for c in restarts) == SMALL["restarts"]
    assert all(0 <= done <= total for _, done, total in calls)


def test_exception_in_progress_is_raised_after_the_work(puma):
    class Stop(Exception):
        pass

    def progress(stage, done, total):
        raise Stop(f"stop at {stage}")

    with pytest.raises(Stop, match="stop at jacobians"):
        activecal.select(puma, seed=1, progress=progress, **SMALL)
    # The module still works.
    assert activecal.select(puma, seed=1, **SMALL).log10_det > 0
    with pytest.raises(ValueError, match="progress: expected a callable"):
        activecal.select(puma, progress=3, **SMALL)


def test_bad_input(puma):
    with pytest.raises(ValueError, match="algorithm must be one of .* got 'fedorof'"):
        activecal.select(puma, algorithm="fedorof")
    with pytest.raises(ValueError, match=r"num_poses must be in \[1, 4096\]"):
        activecal.select(puma, levels=4, num_poses=0)
    with pytest.raises(ValueError, match="criterion must be"):
        activecal.select(puma, criterion="e", **SMALL)
    with pytest.raises(ValueError, match="levels=1"):
        activecal.select(puma, levels=1)
    with pytest.raises(ValueError, match=r"pool: expected an array of shape \(n, 6\)"):
        activecal.select(puma, pool=np.zeros((100, 5)))
    with pytest.raises(ValueError, match="pool must be 'lattice', 'sobol'"):
        activecal.select(puma, pool="grid")
    with pytest.raises(ValueError, match="select: unknown option 'num_pose'"):
        activecal.select(puma, num_pose=10)
    with pytest.raises(ValueError, match="pool pose 0"):
        activecal.select(puma, pool=np.full((50, 6), 100.0), num_poses=10)
    with pytest.raises(ValueError, match="the pool: .*auto_fix=True"):
        # One pose at the same place over and over identifies nothing.
        activecal.select(puma, pool=np.zeros((40, 6)), num_poses=10)


@pytest.mark.parametrize("pool", ["lattice", "sobol", "random"])
def test_a_continuous_joint_gets_a_pool_of_each_kind(pool):
    # Issue 26, item 13: a robot with a continuous joint (the rail arm's j3)
    # got no pool of any kind ("no finite range"). It takes one turn,
    # [-pi, pi), the end left out (it is the start again).
    robot = activecal.load_robot(
        str(SOURCE_DIR / "tests" / "data" / "arm7_rail.urdf"), tip_link="tcp")
    lo, hi = robot.joint_limits.T
    continuous = np.flatnonzero(~np.isfinite(lo) & ~np.isfinite(hi))
    assert list(continuous) == [3]
    design = activecal.select(robot, pool=pool, levels=2, pool_size=500,
                              parameter_set="offsets", num_poses=20,
                              restarts=1, seed=1)
    assert design.joint_angles.shape == (20, robot.num_joints)
    assert len(set(design.pose_indices)) == 20
    q = design.joint_angles[:, 3]
    assert np.all(q >= -np.pi) and np.all(q < np.pi)
    assert design.termination_type == "CONVERGENCE"
    if pool == "lattice":
        # Two levels over one turn: -180 and 0 deg, never +180 (= -180).
        assert set(q) <= {-np.pi, 0.0}
        assert ("joint 4 (j3) has no limits: its 2 levels cover one turn "
                "from -180 deg (a continuous joint)") in design.notes
        assert design.pool_size == 2 ** robot.num_joints
    else:
        assert design.pool_size == 500


def test_task_design_with_measured_poses_and_target(puma, tmp_path):
    # Poses already measured count as prior information; the fewest new
    # poses meeting a predicted task RMS, as the program finds them.
    first = activecal.select(puma, algorithm="greedy", levels=3,
                             num_poses=12, certificate=False)
    measured = activecal.simulate(puma, first.joint_angles, noise_m=1e-4)
    path = tmp_path / "measured.csv"
    activecal.write_measurements(puma, str(path), measured)
    curve = tmp_path / "curve.csv"
    expected, _ = program_design(
        tmp_path, "fedorov", 2, criterion="task_rms",
        extra=[f"--measured_csv={path}", "--target_rms_m=8e-5",
               "--noise_m=1e-4", f"--curve_csv={curve}"])
    design = activecal.select(puma, criterion="task_rms", seed=2,
                              measured=measured, target_rms_m=8e-5,
                              noise_m=1e-4, **SMALL)
    assert design.num_measured == expected["num_measured"] == 12
    assert list(design.pose_indices) == expected["pose_indices"]
    assert design.predicted_task_rms_m == expected["predicted_task_rms_m"]
    target = design.target
    assert [[s, r] for s, r in zip(target["sizes"], target["rms_by_size_m"])] \
        == expected["predicted_task_rms_by_size_m"]
    assert target["best_reachable_rms_m"] == expected["best_reachable_rms_m"]
    # Meaning: the size found meets the target, one fewer does not.
    assert design.predicted_task_rms_m <= 8e-5
    sizes = list(target["sizes"])
    k = sizes.index(len(design.pose_indices))
    if len(design.pose_indices) - 1 in sizes:
        assert target["rms_by_size_m"][sizes.index(len(design.pose_indices) - 1)] > 8e-5
    assert target["rms_by_size_m"][k] == design.predicted_task_rms_m
    with pytest.raises(ValueError, match="measured needs criterion='task_rms'"):
        activecal.select(puma, measured=measured, **SMALL)


def test_single_precision_pool_as_the_program(puma, tmp_path):
    # pool_storage='float' (and 'auto' past max_double_pool_mib=0): the
    # same design, log det and certificate as activecal_select with the
    # same flags; the pool is stored in float, the numbers are in double.
    expected, _ = program_design(tmp_path, "fedorov", 2,
                                 extra=["--pool_storage=float"])
    assert expected["pool_storage"] == "float"
    design = activecal.select(puma, algorithm="fedorov", seed=2,
                              pool_storage="float", **SMALL)
    assert design.pool_storage == "float"
    assert list(design.pose_indices) == expected["pose_indices"]
    assert design.log10_det == expected["log10_det"]
    assert design.efficiency_lower_bound == expected["efficiency_lower_bound"]
    auto = activecal.select(puma, algorithm="fedorov", seed=2,
                            max_double_pool_mib=0, **SMALL)
    assert auto.pool_storage == "float"
    assert list(auto.pose_indices) == expected["pose_indices"]
    # Within the budget (and by default) the pool stays in double.
    assert activecal.select(puma, seed=2, **SMALL).pool_storage == "double"
    # Only fedorov/approx with the D criterion read float pools.
    with pytest.raises(ValueError, match="float storage needs a design"):
        activecal.select(puma, algorithm="eae", pool_storage="float", **SMALL)
    with pytest.raises(ValueError, match="pool_storage must be 'auto'"):
        activecal.select(puma, pool_storage="half", **SMALL)
