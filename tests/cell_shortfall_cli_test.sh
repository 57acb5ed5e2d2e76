#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# A cell that admits too few poses or none: activecal_select --pool=measurable
# stops at its cap on draws (--max_draws, or no pose in the first 1000
# draws) with one line giving the counts per rejection reason and exit 1,
# writing nothing; a cell whose table rejects every pose names the link
# and the obstacle (UR10 shoulder_link: 2.7 cm above a table at z = 0 with
# clearance_m 0.05).
#
#   tests/cell_shortfall_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# expect_error <name> <text> <program> [flags...]: exit status 1, one
# error line holding <text> (progress lines may come before it), no
# out.json.
expect_error() {
  local name="$1" want="$2"
  shift 2
  local prog="$1"
  shift
  rm -f out.json
  "$apps/$prog" "$@" --json_out=out.json >out.txt 2>err.txt
  local status=$?
  local errors
  errors=$(grep -c "error:" err.txt)
  if [ "$status" -ne 1 ]; then
    echo "FAIL [$name]: exit status $status, expected 1"; failures=$((failures + 1))
  elif [ "$errors" -ne 1 ] || [ "$(grep -v "so far)$" err.txt | wc -l)" -ne 1 ]; then
    echo "FAIL [$name]: expected one error line:"; cat err.txt
    failures=$((failures + 1))
  elif ! grep "error:" err.txt | grep -qF -- "$want"; then
    echo "FAIL [$name]: stderr lacks '$want':"; cat err.txt
    failures=$((failures + 1))
  elif [ -e out.json ]; then
    echo "FAIL [$name]: wrote out.json"; failures=$((failures + 1))
  else
    echo "ok   [$name]: $(grep "error:" err.txt)"
  fi
}

# table_cell_head <joint margin deg> <clearance m>: a cell's first lines,
# those margins, a self clearance of 1 cm and a table plane at z = 0.
table_cell_head() {
  printf 'joint_margin_deg: %s\nclearance_m: %s\nself_clearance_m: 0.01\nobstacles:\n  - {name: table, type: plane, normal: [0, 0, 1], offset_m: 0.0}\n' "$1" "$2"
}

# The table at the base's height: the shoulder link (its collision
# cylinder 2.7 cm above the base) is closer than clearance_m at every pose.
{ table_cell_head 3 0.05; cat <<'CELL'
device:
  type: laser_tracker
  xyz_m: [2.2, 0.4, 0.9]
  range_m: [1.0, 6.0]
targets:
  - {name: smr, xyz_m: [0, 0, 0.06], normal: [0, 0, 1], acceptance_deg: 30}
CELL
} >low_table.yaml
ur10=(--robot="$data/ur10.urdf" --tip_link=tool0 --cell=low_table.yaml)

# It never ended ("measurable poses: 0/5000 (239.6 s so far)").
expect_error "measurable pool of a cell that admits no pose" \
  "--pool=measurable: found no measurable pose in 1000 draws (the search gives up there; max_draws 50000);" \
  activecal_select "${ur10[@]}" --pool=measurable --pool_size=5000 --num_poses=30
grep "error:" err.txt | grep -qE "[0-9]+ inverse kinematics solutions checked, rejected: joint margin [0-9]+, self-collision [0-9]+, obstacle table [1-9][0-9]*, out of range [0-9]+, target facing away [0-9]+, line of sight blocked [0-9]+; [0-9]+ of 4000 solves failed; [0-9]+ of 1000 draws found no target point" &&
  ok "the line counts the rejections per reason" || { fail "counts"; cat err.txt; }
grep "error:" err.txt | grep -qF "link 'shoulder_link' collides with obstacle 'table' (0.0273 m apart, clearance_m 0.05)" &&
  ok "the line names the link and the obstacle, and their distance" ||
  { fail "link and obstacle named"; cat err.txt; }

# The same cell on a Sobol pool: every pose that reaches the obstacle
# checks is the shoulder's.
expect_error "sobol pool of a cell that admits no pose" \
  "every pose that reached the obstacle checks (" \
  activecal_select "${ur10[@]}" --pool=sobol --pool_size=2000 --num_poses=30
grep "error:" err.txt | grep -qF "link 'shoulder_link' collides with obstacle 'table' (0.0273 m apart, clearance_m 0.05); is 'table' clear of the robot's base" &&
  ok "the sobol pool's line names the link and the obstacle" ||
  { fail "sobol: link and obstacle"; cat err.txt; }

# A healthy cell under a cap too small: 5 draws give ~10 poses, fewer than
# --num_poses.
ur10e=(--robot="$data/ur10e.urdf" --tip_link=tool0
  --cell="$data/cells/ur10e_table.yaml" --pool=measurable --pool_size=100)
expect_error "max_draws reached with too few poses" \
  "measurable poses in 5 draws (max_draws); " \
  activecal_select "${ur10e[@]}" --max_draws=5 --num_poses=30
grep "error:" err.txt | grep -qE "found [0-9]+ of 100 measurable poses in 5 draws \(max_draws\); [0-9]+ inverse kinematics solutions checked, rejected: joint margin [0-9]+, self-collision [0-9]+, obstacle table [0-9]+, obstacle wall [0-9]+, .* \(raise --max_draws, or fix the cell\)$" &&
  ok "the capped line gives the counts and what to do" || { fail "capped line"; cat err.txt; }
# Enough poses for the design under the cap: the run goes on, with the note.
if "$apps/activecal_select" "${ur10e[@]}" --max_draws=5 --num_poses=9 \
  --json_out=few.json >few.txt 2>few.err; then
  grep -q "note: found [0-9]* of 100 measurable poses in 5 draws (max_draws)" few.txt &&
    python3 -c "import json; d = json.load(open('few.json')); assert d['measurable_pool']['draws'] == 5, d['measurable_pool']" &&
    ok "a cap that leaves enough poses: a note, the design" ||
    { fail "capped but enough"; cat few.txt; }
else
  fail "capped but enough"; cat few.err
fi

expect_fail "max_draws without the measurable pool" \
  "--max_draws caps the draws of --pool=measurable, got --pool=sobol" \
  activecal_select "${ur10e[@]/--pool=measurable/--pool=sobol}" --max_draws=5
expect_fail "negative max_draws" "--max_draws must be >= 0, got -1" \
  activecal_select "${ur10e[@]}" --max_draws=-1

# Two targets facing apart (z and x, 25 deg acceptance): each feasible pose
# sees one, 3 equations, so 10 poses give 30 for the 34 parameters. Every
# algorithm refuses up front, counting the rows the poses give (not 6 per
# pose): fedorov returned 12 poses, greedy a false singular-start message.
{ table_cell_head 5 0.03; cat <<'EOF'
device: {type: laser_tracker, xyz_m: [2.5, -0.5, 1.2], range_m: [1.5, 5.0]}
targets:
  - {name: front, xyz_m: [0, 0, 0.05], normal: [0, 0, 1], acceptance_deg: 25}
  - {name: side, xyz_m: [0.06, 0, 0.02], normal: [1, 0, 0], acceptance_deg: 25}
EOF
} >apart.yaml
for algorithm in fedorov detmax greedy; do
  expect_error "select --algorithm=$algorithm, targets seen one at a time" \
    "10 poses give 30 equations, fewer than the 34 parameters: every such design is singular (a feasible pose sees at most 1 of the 2 targets)" \
    activecal_select --robot="$data/kuka_iiwa14.urdf" --cell=apart.yaml \
    --pool=sobol --pool_size=4096 --num_poses=10 --algorithm=$algorithm \
    --threads=2 --poses_csv=apart.csv
done
"$apps/activecal_select" --robot="$data/kuka_iiwa14.urdf" --cell=apart.yaml \
  --pool=sobol --pool_size=4096 --num_poses=12 --algorithm=fedorov \
  --threads=2 --poses_csv=apart.csv \
  --json_out=apart.json >apart.out 2>&1 &&
  python3 -c "import json; assert json.load(open('apart.json'))['num_poses'] == 12" &&
  ok "... 12 poses (36 equations) are designed" || { fail "select 12 poses"; cat apart.out; }

cli_end
