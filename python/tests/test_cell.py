# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""The cell where Python plans a pose: select(..., cell=) chooses from the
poses the cell can run, as activecal_select --cell; compensate(..., cell=)
gives a configuration through the table the status 'collision', as
activecal_compensate --cell (issue #24 item 6)."""
import re

import numpy as np
import pytest

import activecal

import json

from conftest import PUMA, SOURCE_DIR, program, run

CELL = str(SOURCE_DIR / "tests" / "data" / "puma_table_cell.yaml")
TWO = str(SOURCE_DIR / "tests" / "data" / "puma_two_targets_cell.yaml")


def feasible_count(design):
    line = [n for n in design.notes if n.startswith("cell: ")]
    assert len(line) == 1, design.notes
    m = re.match(r"cell: (\d+) of (\d+) poses feasible", line[0])
    assert m, line[0]
    return int(m.group(1)), int(m.group(2)), line[0]


def cell_verdicts(robot, joints):
    """The cell's collision and joint-margin check of each row, recomputed
    through compensate (the program compensated on the robot it was taught
    with converges to itself)."""
    c = activecal.compensate(robot, program=joints, nominal=robot, cell=CELL)
    return c.status, c.messages


def test_select_with_cell_chooses_feasible_poses_only():
    robot = activecal.load_robot(PUMA)
    free = activecal.select(robot, levels=3, num_poses=12, restarts=1)
    design = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                              cell=CELL)
    feasible, total, line = feasible_count(design)
    assert total == 729 and 0 < feasible < 729, line
    assert "obstacle table" in line
    status, messages = cell_verdicts(robot, design.joint_angles)
    assert status == ["converged"] * 12, list(zip(status, messages))
    # Without the cell the same selection takes poses the cell refuses: the
    # check above can fail.
    status, _ = cell_verdicts(robot, free.joint_angles)
    assert "collision" in status, status
    # pose_indices and pool_rows are rows of the lattice (the pool given).
    assert np.array_equal(design.pose_indices, design.pool_rows)


def test_select_with_cell_on_an_array_pool_keeps_the_rows_given():
    robot = activecal.load_robot(PUMA)
    full = activecal.select(robot, levels=3, num_poses=40, restarts=1)
    pool = full.joint_angles
    design = activecal.select(robot, pool=pool, num_poses=10, restarts=1,
                              cell=CELL)
    feasible, total, _ = feasible_count(design)
    assert total == 40 and feasible < 40
    rows = np.asarray(design.pool_rows)
    assert np.array_equal(pool[rows], design.joint_angles)
    status, _ = cell_verdicts(robot, pool[rows])
    assert status == ["converged"] * 10


def test_select_cell_keeping_no_pose_names_the_counts(tmp_path):
    cell = tmp_path / "all.yaml"
    cell.write_text(open(CELL).read().replace("offset_m: 0.3", "offset_m: 5.0"))
    with pytest.raises(ValueError, match=r"cell: .*0 of 729 poses feasible; "
                       r"rejected: joint margin 0, self-collision 330, "
                       r"obstacle table 399"):
        activecal.select(activecal.load_robot(PUMA), levels=3, num_poses=12,
                         cell=cell)


def test_compensate_with_cell_gives_the_pose_through_the_table_collision():
    robot = activecal.load_robot(PUMA)
    # A lattice pose whose arm is below the table top (z < 0.3 in the base
    # frame) and one clear of it, found by the cell's own verdicts.
    design = activecal.select(robot, levels=3, num_poses=40, restarts=1)
    status, messages = cell_verdicts(robot, design.joint_angles)
    table = [i for i, m in enumerate(messages) if m.startswith("obstacle table")]
    clear = [i for i, s in enumerate(status) if s == "converged"]
    assert table and clear, list(zip(status, messages))
    program = design.joint_angles[[clear[0], table[0]]]
    plain = activecal.compensate(robot, program=program, nominal=robot)
    assert plain.status == ["converged", "converged"]
    c = activecal.compensate(robot, program=program, nominal=robot, cell=CELL)
    assert c.status == ["converged", "collision"], c.messages
    assert re.match(r"obstacle table \(L\d\)$", c.messages[1]), c.messages
    assert not c.all_converged
    assert "1 collision" in c.report()
    # The configuration is kept (the program's own joints).
    assert np.allclose(c.joint_angles[1], program[1], atol=1e-9)


def test_bad_cell_and_unknown_options_are_value_errors(tmp_path):
    robot = activecal.load_robot(PUMA)
    with pytest.raises(ValueError, match=r"^cell: .*nothing.yaml"):
        activecal.select(robot, levels=3, num_poses=12,
                         cell=str(tmp_path / "nothing.yaml"))
    with pytest.raises(ValueError, match=r"^cell: .*nothing.yaml"):
        activecal.compensate(robot, program=np.zeros((1, 6)), nominal=robot,
                             cell=tmp_path / "nothing.yaml")
    with pytest.raises(ValueError, match="unknown option 'cel'"):
        activecal.select(robot, levels=3, num_poses=12, cel=CELL)


def cli_select(tmp_path, *flags):
    out = tmp_path / "design.json"
    run([program("activecal_select"), f"--robot={PUMA}", "--levels=3",
         "--num_poses=12", "--restarts=1", "--algorithm=fedorov",
         f"--json_out={out}", *flags])
    return json.loads(out.read_text())


def test_select_with_cell_plans_the_cells_targets_as_the_cli(tmp_path):
    # Two reflectors back to back: the cell's targets are the markers (the
    # robot file's one marker is not planned), each pose's rows those seen.
    robot = activecal.load_robot(PUMA)
    design = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                              algorithm="fedorov", cell=TWO)
    cli = cli_select(tmp_path, f"--cell={TWO}")
    assert list(design.free_parameters) == cli["free_parameters"]
    assert list(design.pose_indices) == cli["pose_indices"]
    assert design.log10_det == pytest.approx(cli["log10_det"], abs=1e-9)


def test_select_with_cell_returns_feasible_rejected_and_targets_seen(tmp_path):
    robot = activecal.load_robot(PUMA)
    design = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                              algorithm="fedorov", cell=TWO)
    cli = cli_select(tmp_path, f"--cell={TWO}")
    assert design.feasible_poses == cli["feasible_poses"]
    assert design.feasible_poses == feasible_count(design)[0]
    assert design.rejected == cli["rejected"]
    assert sum(v if isinstance(v, int) else sum(v.values())
               for v in design.rejected.values()) == 729 - design.feasible_poses
    assert design.targets_seen == cli["targets_seen"]
    assert len(design.targets_seen) == 12
    assert all(seen and set(seen) <= {"front", "back"}
               for seen in design.targets_seen)
    # Without a cell: None.
    free = activecal.select(robot, levels=3, num_poses=12, restarts=1)
    assert free.feasible_poses is None and free.rejected is None
    assert free.targets_seen is None and free.tour is None


def test_select_order_shortest_is_the_clis_tour(tmp_path):
    robot = activecal.load_robot(PUMA)
    plain = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                             algorithm="fedorov", cell=CELL)
    design = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                              algorithm="fedorov", cell=CELL, order="shortest")
    cli = cli_select(tmp_path, f"--cell={CELL}", "--order=shortest")
    # The same poses, in the tour's order (the CLI's), rows kept together.
    assert sorted(design.pose_indices) == sorted(plain.pose_indices)
    assert list(design.pose_indices) == cli["pose_indices"]
    assert list(design.pose_indices) != list(plain.pose_indices)
    where = {int(i): k for k, i in enumerate(plain.pose_indices)}
    perm = [where[int(i)] for i in design.pose_indices]
    assert np.array_equal(design.joint_angles, plain.joint_angles[perm])
    assert np.array_equal(design.pool_rows, np.asarray(plain.pool_rows)[perm])
    t = design.tour
    c = cli["tour"]
    for key in ("motion_time_before_s", "motion_time_after_s"):
        assert t[key] == pytest.approx(c[key], rel=1e-12)
    assert t["motion_time_after_s"] <= t["motion_time_before_s"] + 1e-9
    assert t["blocked_moves"] == c["blocked_moves"] == len(t["blocked"])
    assert t["blocked"] == c["blocked"]
    # The CLI's tour, key for key: what the moves were checked against and
    # the velocities assumed (the PUMA's file gives none).
    assert set(t) == set(c), set(t) ^ set(c)
    assert t["moves_checked"] is c["moves_checked"] is True
    assert t["velocity_note"] == c["velocity_note"]
    assert "taken at 1 rad/s" in t["velocity_note"]
    bare = activecal.select(robot, levels=3, num_poses=12, restarts=1,
                            algorithm="fedorov", order="shortest").tour
    assert bare["moves_checked"] is False
    assert bare["moves_not_checked"] == "no cell="
    with pytest.raises(ValueError, match="order must be 'none' or 'shortest', "
                       "got 'fast'"):
        activecal.select(robot, levels=3, num_poses=12, order="fast")
