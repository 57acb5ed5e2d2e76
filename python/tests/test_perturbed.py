# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""Robot.perturbed: the library's PerturbParameters, as activecal_simulate
--perturb_m --perturb_rad --seed uses it (the same values for a seed)."""
import numpy as np
import pytest

import activecal
from conftest import PUMA, UR10, program, run


def test_perturbed_moves_the_free_parameters_only_by_their_unit(puma):
    full = activecal.load_robot(UR10, tip_link="tool0").with_parameter_set(
        "full")
    p = full.perturbed(0.001, 0.002, seed=5)
    units = np.array(full.parameter_units)
    moved = p != full.nominal
    assert not moved[~full.free].any()
    assert moved[full.free & (units != "1")].all()
    d = (p - full.nominal)[full.free]
    u = units[full.free]
    # Lengths in mm, angles in 2 mrad: the spread says which is which.
    assert 0.0005 < np.std(d[u == "m"]) < 0.002
    assert 0.001 < np.std(d[u == "rad"]) < 0.004
    # Seeded: the same seed, the same values; another, others.
    assert np.array_equal(p, full.perturbed(0.001, 0.002, seed=5))
    assert not np.array_equal(p, full.perturbed(0.001, 0.002, seed=6))
    assert np.array_equal(full.perturbed(0, 0), full.nominal)


def test_perturbed_is_what_activecal_simulate_simulates_from(tmp_path, puma):
    simulate = program("activecal_simulate")
    poses = tmp_path / "poses.csv"
    poses.write_text("q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad\n"
                     "0.1,0.2,0.3,0.4,0.5,0.6\n")
    true_model = tmp_path / "true.yaml"
    run([simulate, "--robot=" + PUMA, "--poses_csv=" + str(poses),
         "--perturb_m=0.001", "--perturb_rad=0.002", "--seed=3",
         "--true_model_out=" + str(true_model),
         "--out=" + str(tmp_path / "m.csv")])
    written = activecal.load_robot(str(true_model)).true_parameters
    want = puma.perturbed(0.001, 0.002, seed=3,
                          parameters=puma.true_parameters)
    assert np.array_equal(written, want)


def test_perturbed_bad_values(puma):
    with pytest.raises(ValueError, match="perturb_m must be >= 0"):
        puma.perturbed(-1.0, 0.0)
    with pytest.raises(ValueError, match="perturb_rad must be >= 0"):
        puma.perturbed(0.0, float("nan"))
