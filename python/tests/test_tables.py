# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Tables (activecal/_tables.py): pandas DataFrames when pandas is
installed, dicts of numpy arrays without; the same columns and values."""
import subprocess
import sys

import numpy as np
import pytest

import activecal
from conftest import PUMA

try:
    import pandas
except ImportError:
    pandas = None


@pytest.fixture(scope="module")
def results():
    robot = activecal.load_robot(PUMA)
    design = activecal.select(robot, num_poses=12, levels=3, seed=1,
                              pool_size=200)
    measured = activecal.simulate(robot, design.joint_angles, noise_m=1e-4,
                                  seed=1, type="pose")
    estimate = activecal.identify(robot, measured, model_selection="none")
    comp = activecal.compensate(estimate.robot, program=measured.joints[:3],
                                nominal=robot)
    return robot, design, measured, estimate, comp


def columns(table):
    """A table's columns as {name: numpy array}, DataFrame or dict."""
    if pandas is not None and isinstance(table, pandas.DataFrame):
        return {c: table[c].to_numpy() for c in table.columns}
    assert isinstance(table, dict)
    return table


def check_tables(robot, design, measured, estimate, comp):
    t = columns(estimate.table())
    assert list(t) == ["name", "unit", "nominal", "estimate", "std",
                       "change"]
    assert list(t["name"]) == list(estimate.parameter_names)
    np.testing.assert_array_equal(t["estimate"], estimate.estimates)
    np.testing.assert_array_equal(t["std"], estimate.std)
    np.testing.assert_array_equal(t["nominal"], estimate.nominal)
    np.testing.assert_array_equal(t["change"],
                                  estimate.estimates - estimate.nominal)
    units = dict(zip(robot.parameter_names, robot.parameter_units))
    assert list(t["unit"]) == [units[n] for n in estimate.parameter_names]
    assert {"m", "rad"} <= set(t["unit"])

    t = columns(measured.table())
    n = len(measured)
    assert all(len(v) == n for v in t.values())
    assert list(t["type"]) == measured.types
    for j in range(6):
        np.testing.assert_array_equal(t[f"q{j + 1}"], measured.joints[:, j])
    np.testing.assert_array_equal(
        np.stack([t["x"], t["y"], t["z"]], axis=1), measured.positions)
    np.testing.assert_array_equal(
        np.stack([t["rx"], t["ry"], t["rz"]], axis=1), measured.rotations)
    assert np.isnan(t["distance"]).all()  # pose rows have none
    assert "q2_1" not in t                # no distance rows

    t = columns(design.table())
    np.testing.assert_array_equal(t["pose_index"], design.pose_indices)
    np.testing.assert_array_equal(t["q3"], design.joint_angles[:, 2])

    t = columns(comp.table())
    assert list(t["status"]) == comp.status
    np.testing.assert_array_equal(t["position_error_m"], comp.position_error_m)
    np.testing.assert_array_equal(t["target_y"], comp.target_points[:, 1])
    np.testing.assert_array_equal(t["q6"], comp.joint_angles[:, 5])

    curve = columns(estimate.model_selection_table())
    assert list(curve) == ["num_kept", "added", "ok", "training_rms_m",
                           "held_out_rms_m"]
    assert all(len(v) == len(estimate.model_selection_curve)
               for v in curve.values())


def test_tables(results):
    kind = type(results[3].table())
    if pandas is None:
        assert kind is dict
    else:
        assert kind is pandas.DataFrame
    check_tables(*results)


def test_model_selection_curve_table():
    robot = activecal.load_robot(PUMA)
    design = activecal.select(robot, num_poses=20, levels=3, seed=2,
                              pool_size=200)
    measured = activecal.simulate(robot, design.joint_angles, noise_m=1e-4,
                                  seed=2)
    estimate = activecal.identify(robot, measured, model_selection="cv",
                                  folds=3)
    t = columns(estimate.model_selection_table())
    curve = estimate.model_selection_curve
    assert len(curve) > 1
    np.testing.assert_array_equal(t["num_kept"],
                                  [p["num_kept"] for p in curve])
    np.testing.assert_array_equal(t["held_out_rms_m"],
                                  [p["held_out_rms_m"] for p in curve])


# The other case, in a subprocess: pandas hidden when it is installed, or
# (when it is not) the DataFrame path cannot be run and is skipped.
@pytest.mark.skipif(pandas is None, reason="pandas is not installed "
                    "(Debian: python3-pandas): only the dict tables run")
def test_tables_without_pandas():
    code = (
        "import sys; sys.modules['pandas'] = None\n"
        "import activecal, numpy as np\n"
        "robot = activecal.puma560()\n"
        "design = activecal.select(robot, num_poses=12, levels=3, seed=1,"
        " pool_size=200)\n"
        "t = design.table()\n"
        "assert type(t) is dict, type(t)\n"
        "assert list(t) == ['pose_index'] + [f'q{j}' for j in range(1, 7)]\n"
        "assert (t['pose_index'] == design.pose_indices).all()\n"
        "print('ok')\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stderr
    assert done.stdout == "ok\n"
