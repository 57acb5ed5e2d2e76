# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Tables of activecal's results: pandas DataFrames when pandas is
installed, otherwise dicts of numpy arrays (column name -> 1-D array, every
column of one length) that pandas.DataFrame(...) would take as they are.

Each table is built from the object's properties only (no other numbers):
Estimate.table(), Estimate.model_selection_table(), Measurements.table(),
Design.table(), Compensation.table().
"""
import numpy as np


def _frame(columns):
    """A DataFrame of `columns` (a dict of equal-length 1-D arrays) with
    pandas, the dict itself without."""
    try:
        import pandas
    except ImportError:
        return columns
    return pandas.DataFrame(columns)


def _joint_columns(columns, prefix, joints, names=None):
    joints = np.asarray(joints, dtype=float)
    for j in range(joints.shape[1] if joints.ndim == 2 else 0):
        name = names[j] if names is not None else f"q{j + 1}"
        columns[f"{prefix}{name}"] = joints[:, j]


def estimate_table(self):
    """The identified parameters: name, unit, nominal, estimate, std,
    change (estimate - nominal), one row per parameter in `parameter_names`
    order (SI units)."""
    names = list(self.parameter_names)
    all_names = list(self.robot.parameter_names)
    units = list(self.robot.parameter_units)
    unit = [units[all_names.index(n)] for n in names]
    estimates = np.asarray(self.estimates, dtype=float)
    nominal = np.asarray(self.nominal, dtype=float)
    return _frame({
        "name": np.array(names, dtype=object),
        "unit": np.array(unit, dtype=object),
        "nominal": nominal,
        "estimate": estimates,
        "std": np.asarray(self.std, dtype=float),
        "change": estimates - nominal,
    })


def model_selection_table(self):
    """The model selection curve: num_kept, added, ok, training_rms_m,
    held_out_rms_m, one row per step (empty for model_selection='none')."""
    curve = self.model_selection_curve
    keys = ("num_kept", "added", "ok", "training_rms_m", "held_out_rms_m")
    kinds = (int, object, bool, float, float)
    return _frame({k: np.array([p[k] for p in curve], dtype=t)
                   for k, t in zip(keys, kinds)})


def measurements_table(self):
    """One row per measurement: type, marker, q1..qN (the joint readings),
    x, y, z (the measured point, m), rx, ry, rz (the rotation vector of a
    pose row, rad), distance (m), the second pose's joints (distance rows,
    q2_1..), sigma_x, sigma_y, sigma_z (m), sigma_rad. NaN where a row has
    no such value."""
    columns = {
        "type": np.array(self.types, dtype=object),
        "marker": np.asarray(self.markers, dtype=int),
    }
    _joint_columns(columns, "", self.joints)
    for k, axis in enumerate("xyz"):
        columns[axis] = self.positions[:, k]
    for k, axis in enumerate(("rx", "ry", "rz")):
        columns[axis] = self.rotations[:, k]
    columns["distance"] = np.asarray(self.distances, dtype=float)
    joints2 = np.asarray(self.joints2, dtype=float)
    if joints2.size and not np.isnan(joints2).all():
        for j in range(joints2.shape[1]):
            columns[f"q2_{j + 1}"] = joints2[:, j]
    for k, axis in enumerate("xyz"):
        columns[f"sigma_{axis}"] = self.sigma_m[:, k]
    columns["sigma_rad"] = np.asarray(self.sigma_rad, dtype=float)
    return _frame(columns)


def design_table(self):
    """One row per selected pose: pose_index (in the pool), q1..qN."""
    columns = {"pose_index": np.asarray(self.pose_indices, dtype=np.int64)}
    _joint_columns(columns, "", self.joint_angles)
    return _frame(columns)


def compensation_table(self):
    """One row per target: status, message, position_error_m,
    rotation_error_rad, target_x/y/z (m), q1..qN (the compensated joints)."""
    columns = {
        "status": np.array(self.status, dtype=object),
        "message": np.array(self.messages, dtype=object),
        "position_error_m": np.asarray(self.position_error_m, dtype=float),
        "rotation_error_rad": np.asarray(self.rotation_error_rad, dtype=float),
    }
    for k, axis in enumerate("xyz"):
        columns[f"target_{axis}"] = self.target_points[:, k]
    _joint_columns(columns, "", self.joint_angles)
    return _frame(columns)


def attach(module):
    """Adds the table methods to the extension's classes."""
    module.Estimate.table = estimate_table
    module.Estimate.model_selection_table = model_selection_table
    module.Measurements.table = measurements_table
    module.Design.table = design_table
    module.Compensation.table = compensation_table
