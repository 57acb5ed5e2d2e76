# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
"""iso9283: the ISO 9283 table of activecal_evaluate --iso9283, same numbers."""
import json

import pytest

import activecal
from conftest import UR10, program, run


@pytest.fixture(scope="module")
def cycles(tmp_path_factory):
    """The ISO cube's five poses on the UR10, 4 cycles each, simulated."""
    d = tmp_path_factory.mktemp("iso9283")
    robot = [f"--robot={UR10}", "--tip_link=tool0"]
    cube = d / "cube.csv"
    run([program("activecal_select"), *robot, "--iso9283_cube=0.6,0.2,0.5,0.3",
         "--iso9283_orientation=0,1,0,0", f"--poses_csv={cube}"])
    lines = [l for l in cube.read_text().splitlines(keepends=True)
             if l.strip() and not l.startswith("#")]
    repeated = d / "cube4.csv"
    repeated.write_text(lines[0] + "".join(l for l in lines[1:] for _ in range(4)))
    path = d / "cycles.csv"
    run([program("activecal_simulate"), *robot, f"--poses_csv={repeated}",
         "--type=pose", "--perturb_m=0.0005", "--perturb_rad=0.0005",
         "--noise_m=0.00002", "--rotation_noise_rad=0.00002", "--seed=3",
         f"--out={path}"])
    out = d / "iso.json"
    run([program("activecal_evaluate"), *robot, f"--measurements={path}",
         "--iso9283", f"--json_out={out}"])
    return path, json.loads(out.read_text())["iso9283"]


def test_the_table_is_the_programs(ur10, cycles):
    path, expected = cycles
    got = activecal.iso9283(ur10, str(path))
    assert [p["pose"] for p in got["poses"]] == ["P1", "P2", "P3", "P4", "P5"]
    assert all(p["num_cycles"] == 4 for p in got["poses"])
    # Figures a perturbed robot has: AP of the model error, not 0.
    assert min(p["without"]["ap_p_m"] for p in got["poses"]) > 1e-5
    assert got == expected


def test_parameters_change_the_base_frame_figures(ur10, cycles):
    path, expected = cycles
    p = ur10.nominal.copy()
    p[0] += 0.01  # the base frame's first value
    moved = activecal.iso9283(ur10, str(path), parameters=p)
    assert moved["poses"][0]["without"]["ap_p_m"] != \
        expected["poses"][0]["without"]["ap_p_m"]


def test_bad_cycles_name_file_line_and_field(ur10, cycles, tmp_path):
    path, _ = cycles
    lines = path.read_text().splitlines(keepends=True)
    header = next(i for i, l in enumerate(lines) if not l.startswith("#"))
    # The first cycle of P1 relabelled: a pose of one cycle.
    first = lines[header + 1]
    lines[header + 1] = first.replace(",P1,", ",lonely,")
    bad = tmp_path / "one.csv"
    bad.write_text("".join(lines))
    with pytest.raises(ValueError,
                       match=r"one\.csv:%d: pose: 'lonely' has 1 cycle" % (header + 2)):
        activecal.iso9283(ur10, str(bad))
