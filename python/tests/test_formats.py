# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Formats users already have: a tracker export read through a column map
(read_measurements(column_map=)), and the UR ROS driver's kinematics file
(Estimate.write_ur_calibration, activecal_identify --ur_calibration_out)."""
import numpy as np
import pytest
import yaml

import activecal
from conftest import (SOURCE_DIR, perturbed_session, program,
                      puma_measurements, run)

UR10E = str(SOURCE_DIR / "data" / "ur10e.urdf")


def test_column_map_reads_a_german_export(tmp_path):
    puma, m = puma_measurements(12, 200)
    own = tmp_path / "own.csv"
    activecal.write_measurements(puma, own, m, millimetres=True,
                                 joint_degrees=True)
    lines = own.read_text().splitlines()
    header = lines[0].split(",")
    renamed = [{"x_mm": "X", "y_mm": "Y", "z_mm": "Z"}.get(c, c)
               for c in header]
    german = tmp_path / "export.csv"
    german.write_text("\n".join([";".join(renamed)] + [
        line.replace(",", ";").replace(".", ",") for line in lines[1:]]) +
        "\n")
    cmap = tmp_path / "map.yaml"
    cmap.write_text('delimiter: ";"\ndecimal: ","\n'
                    "columns: {x_mm: X, y_mm: Y, z_mm: Z}\n")
    mapped = activecal.read_measurements(puma, german, column_map=cmap)
    back = activecal.read_measurements(puma, own)
    np.testing.assert_array_equal(mapped.joints, back.joints)
    np.testing.assert_array_equal(mapped.positions, back.positions)
    with pytest.raises(ValueError, match="map.yaml:3: columns: x_cm: not an "
                                         "activecal column"):
        cmap.write_text('delimiter: ";"\ndecimal: ","\ncolumns: {x_cm: X}\n')
        activecal.read_measurements(puma, german, column_map=cmap)


@pytest.fixture(scope="module")
def ur10e_fit(tmp_path_factory):
    ur = activecal.load_robot(UR10E, tip_link="tool0")
    m, _ = perturbed_session(ur, 5e-4, np.sin, num_poses=30, noise_m=2e-5,
                             pool_size=300)
    csv = tmp_path_factory.mktemp("ur") / "ur10e.csv"
    activecal.write_measurements(ur, csv, m)
    return ur, csv, activecal.identify(ur, m, model_selection="none")


def test_ur_calibration_as_the_program(ur10e_fit, tmp_path):
    ur, csv, estimate = ur10e_fit
    run([program("activecal_identify"), f"--robot={UR10E}",
         "--tip_link=tool0", f"--measurements={csv}", "--model_selection=none",
         f"--ur_calibration_out={tmp_path / 'program.yaml'}"])
    worst_m, worst_rad = estimate.write_ur_calibration(tmp_path / "py.yaml")
    assert 0 <= worst_m <= 1e-9 and 0 <= worst_rad <= 1e-9

    def body(p):
        return [l for l in p.read_text().splitlines() if not l.startswith("#")]
    assert body(tmp_path / "py.yaml") == body(tmp_path / "program.yaml")
    k = yaml.safe_load((tmp_path / "py.yaml").read_text())["kinematics"]
    assert list(k) == ["shoulder", "upper_arm", "forearm", "wrist_1",
                       "wrist_2", "wrist_3", "hash"]
    # Calibrated, not nominal: the forearm is no longer exactly -0.6127 m.
    assert k["forearm"]["x"] != -0.6127
    assert abs(k["forearm"]["x"] + 0.6127) < 0.01


def test_ur_calibration_refuses_another_robot(tmp_path):
    puma, m = puma_measurements(30, 300)
    estimate = activecal.identify(puma, m, model_selection="none")
    with pytest.raises(ValueError, match="the robot is not a UR"):
        estimate.write_ur_calibration(tmp_path / "x.yaml")
    assert not (tmp_path / "x.yaml").exists()
