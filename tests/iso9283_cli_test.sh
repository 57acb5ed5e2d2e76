#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# activecal_evaluate --iso9283 end to end: cycles to five commanded poses
# simulated by a seeded script (a known bias per pose and a known
# repeatability), the printed and JSON AP and RP against the script's own
# numpy computation (quaternions, not matrices), the HTML section's numbers
# against the JSON's; bad input (a pose of one cycle, a missing commanded
# column, a commanded matrix that is not a rotation): status 1, one line,
# nothing written.
#
#   tests/iso9283_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"
# numpy: the system Python's (the one the Python module is built for).
py=python3
/usr/bin/python3 -c "import numpy" 2>/dev/null && py=/usr/bin/python3

# The UR10 without --frames: the base frame is the device's, so the
# measured poses are the attained ones.
robot=(--robot="$data/ur10.urdf" --tip_link=tool0)

"$py" - <<'EOF'
import numpy as np
rng = np.random.default_rng(5)

def qmul(a, b):
    w1, x1, y1, z1 = a; w2, x2, y2, z2 = b
    return np.array([w1*w2 - x1*x2 - y1*y2 - z1*z2, w1*x2 + x1*w2 + y1*z2 - z1*y2,
                     w1*y2 - x1*z2 + y1*w2 + z1*x2, w1*z2 + x1*y2 - y1*x2 + z1*w2])

def qexp(d):
    a = np.linalg.norm(d)
    if a == 0: return np.array([1.0, 0, 0, 0])
    return np.concatenate([[np.cos(a / 2)], np.sin(a / 2) * d / a])

def qlog(q):
    q = q / np.linalg.norm(q)
    if q[0] < 0: q = -q
    s = np.linalg.norm(q[1:])
    return 2 * np.arctan2(s, q[0]) * q[1:] / s if s > 0 else np.zeros(3)

def qconj(q): return np.array([q[0], -q[1], -q[2], -q[3]])

def qmat(q):
    w, x, y, z = q
    return np.array([[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)],
                     [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)],
                     [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]])

sigma_m, sigma_rad, cycles = 30e-6, 50e-6, 10
rows, expected = [], {}
header = ("pose,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,"
          "qw,qx,qy,qz,commanded_x_m,commanded_y_m,commanded_z_m,"
          "commanded_qw,commanded_qx,commanded_qy,commanded_qz")
for k in range(5):
    name = "P%d" % (k + 1)
    q = rng.uniform(-1, 1, 6)
    xc = np.array([0.6, -0.2, 0.5]) + rng.uniform(-0.2, 0.2, 3)
    qc = qexp(rng.uniform(-2, 2, 3))
    bias_m = rng.uniform(-1e-3, 1e-3, 3)       # the pose's accuracy error
    bias_rad = rng.uniform(-1e-3, 1e-3, 3)
    xs, ds = [], []
    for c in range(cycles):
        x = xc + bias_m + sigma_m * rng.standard_normal(3)
        qa = qmul(qexp(bias_rad + sigma_rad * rng.standard_normal(3)), qc)
        if qa[0] < 0: qa = -qa
        rows.append(",".join([name] + ["%.17g" % v for v in q] +
                             ["%.17g" % v for v in x] + ["%.17g" % v for v in qa] +
                             ["%.17g" % v for v in xc] + ["%.17g" % v for v in qc]))
        xs.append(x)
        # ISO's angle deviations, log(R_j R_c^T), by quaternions.
        ds.append(qlog(qmul(qa, qconj(qc))))
    xs, ds = np.array(xs), np.array(ds)
    bary = xs.mean(axis=0)
    l = np.linalg.norm(xs - bary, axis=1)
    d_bar = ds.mean(axis=0)
    expected[name] = {
        "num_cycles": cycles,
        "ap_p_m": float(np.linalg.norm(bary - xc)),
        "ap_xyz_m": (bary - xc).tolist(),
        "rp_l_m": float(l.mean() + 3 * l.std(ddof=1)),
        "ap_abc_rad": d_bar.tolist(),
        "rp_abc_rad": (3 * ds.std(axis=0, ddof=1)).tolist(),
        "matrix": qmat(qc).tolist()}
open("cycles.csv", "w").write(header + "\n" + "\n".join(rows) + "\n")
import json
json.dump(expected, open("expected.json", "w"))
# Bad files: a pose of one cycle; no commanded_z_m; a commanded matrix that
# is not a rotation (a reflection).
lines = rows[:]
lines[0] = "lonely" + lines[0][2:]
open("one_cycle.csv", "w").write(header + "\n" + "\n".join(lines) + "\n")
cols = header.split(",")
drop = cols.index("commanded_z_m")
def without(line): f = line.split(","); del f[drop]; return ",".join(f)
open("no_z.csv", "w").write(without(header) + "\n" +
                            "\n".join(without(r) for r in rows) + "\n")
mheader = ",".join(cols[:17] + ["commanded_r%d%d" % (i, j) for i in (1, 2, 3) for j in (1, 2, 3)])
mrows = []
for i, r in enumerate(rows):
    f = r.split(",")
    m = np.array(expected[f[0]]["matrix"])
    if i == 13: m[2] = -m[2]
    mrows.append(",".join(f[:17] + ["%.17g" % v for v in m.ravel()]))
open("matrix.csv", "w").write(mheader + "\n" + "\n".join(mrows) + "\n")
EOF

"$apps/activecal_evaluate" "${robot[@]}" --measurements=cycles.csv --iso9283 \
  --before=none --json_out=iso.json --report_html=iso.html >out.txt 2>err.txt \
  && ok "evaluate --iso9283" || { fail "evaluate --iso9283"; cat err.txt; }
grep -q "ISO 9283 pose accuracy" out.txt && ok "table printed" || { fail "table printed"; cat out.txt; }
# The matrix form gives the same figures.
"$py" - <<'EOF' && ok "matrix form" || fail "matrix form"
import sys
rows = open("matrix.csv").read().splitlines()
rows[14] = rows[14].rsplit(",", 9)[0] + "," + ",".join(rows[13].rsplit(",", 9)[1:])
open("matrix_good.csv", "w").write("\n".join(rows) + "\n")
EOF
"$apps/activecal_evaluate" "${robot[@]}" --measurements=matrix_good.csv \
  --iso9283 --before=none --json_out=iso_matrix.json >/dev/null 2>err.txt \
  || { fail "evaluate matrix form"; cat err.txt; }

"$py" - <<'EOF' && ok "AP and RP equal numpy's" || fail "AP and RP equal numpy's"
import json, re, sys
exp = json.load(open("expected.json"))
got = json.load(open("iso.json"))["iso9283"]
mat = json.load(open("iso_matrix.json"))["iso9283"]
bad = []
assert [p["pose"] for p in got["poses"]] == ["P1", "P2", "P3", "P4", "P5"]
for p, pm in zip(got["poses"], mat["poses"]):
    e = exp[p["pose"]]
    w = p["without"]
    if p["num_cycles"] != e["num_cycles"]: bad.append((p["pose"], "cycles"))
    for key in ("ap_p_m", "rp_l_m"):
        if abs(w[key] - e[key]) > 1e-12: bad.append((p["pose"], key, w[key], e[key]))
        if abs(pm["without"][key] - e[key]) > 1e-12: bad.append((p["pose"], "matrix", key))
    for key in ("ap_xyz_m", "ap_abc_rad", "rp_abc_rad"):
        for a, b in zip(w[key], e[key]):
            if abs(a - b) > 1e-11: bad.append((p["pose"], key, a, b))
    # mm and mrad beside SI.
    if abs(w["ap_p_mm"] - 1e3 * w["ap_p_m"]) > 1e-12: bad.append("mm")
    # The biases are ~1 mm and 1 mrad: far above the figures' tolerance.
    if w["ap_p_m"] < 1e-4: bad.append((p["pose"], "no bias"))
# The printed table: AP_p and RP_l in mm with 3 decimals.
text = open("out.txt").read()
table = text.split("without the model")[1].split("with the model")[0]
for p in got["poses"]:
    m = re.search(r"^\s+%s\s+(\d+)\s+(\S+)\s+\S+\s+\S+\s+\S+\s+(\S+)" % p["pose"], table, re.M)
    if not m: bad.append(("no row", p["pose"])); continue
    if int(m.group(1)) != p["num_cycles"]: bad.append("printed cycles")
    if m.group(2) != "%.3f" % (p["without"]["ap_p_m"] * 1e3): bad.append(("printed AP_p", m.group(2)))
    if m.group(3) != "%.3f" % (p["without"]["rp_l_m"] * 1e3): bad.append(("printed RP_l", m.group(3)))
# The HTML section's numbers are the JSON's.
html = open("iso.html").read()
for p in got["poses"]:
    for which in ("without", "with"):
        key = "iso9283.%s.%s.ap_p" % (p["pose"], which)
        m = re.search(r'data-key="%s" data-value="([^"]+)"' % re.escape(key), html)
        if not m or float(m.group(1)) != p[which]["ap_p_m"]: bad.append(("html", key))
if bad:
    print(bad); sys.exit(1)
EOF

# Bad input: one line, status 1, nothing written.
expect_fail "a pose of one cycle" "one_cycle.csv:2: pose: 'lonely' has 1 cycle" activecal_evaluate \
  "${robot[@]}" --measurements=one_cycle.csv --iso9283 --json_out=bad1.json
expect_fail "no commanded_z_m" "the header has commanded_x_m,commanded_y_m but not commanded_z_m" \
  activecal_evaluate "${robot[@]}" --measurements=no_z.csv --iso9283 --json_out=bad2.json
expect_fail "not a rotation" "matrix.csv:15: commanded_r11..commanded_r33: not a rotation matrix" \
  activecal_evaluate "${robot[@]}" --measurements=matrix.csv --iso9283 --json_out=bad3.json
expect_fail "bad registration" "--iso9283_registration must be robot or file" \
  activecal_evaluate "${robot[@]}" --measurements=cycles.csv --iso9283 \
  --iso9283_registration=tracker --json_out=bad4.json
for f in bad1.json bad2.json bad3.json bad4.json; do
  [ -e "$f" ] && fail "$f written" || ok "$f not written"
done

# activecal_select --iso9283_cube: the five poses, their points against
# the cube's geometry computed here, the pose labels.
"$apps/activecal_select" "${robot[@]}" --iso9283_cube=0.6,0.2,0.5,0.3 \
  --iso9283_orientation=0,1,0,0 --poses_csv=cube.csv \
  --iso9283_targets_csv=cube_targets.csv >cube.txt 2>err.txt \
  && ok "select --iso9283_cube" || { fail "select --iso9283_cube"; cat err.txt; }
"$py" - <<'EOF' && ok "cube points and labels" || fail "cube points and labels"
import csv, sys
import numpy as np
rows = list(csv.DictReader(open("cube_targets.csv")))
poses = list(csv.DictReader(open("cube.csv")))
c, h = np.array([0.6, 0.2, 0.5]), 0.15
c1, c2, c7, c8 = (c + h * np.array([-1, -1, -1]), c + h * np.array([1, -1, -1]),
                  c + h * np.array([1, 1, 1]), c + h * np.array([-1, 1, 1]))
want = [c, c1 + 0.1 * (c7 - c1), c2 + 0.1 * (c8 - c2), c7 + 0.1 * (c1 - c7),
        c8 + 0.1 * (c2 - c8)]
assert [r["pose"] for r in rows] == ["P1", "P2", "P3", "P4", "P5"]
assert [r["pose"] for r in poses] == ["P1", "P2", "P3", "P4", "P5"]
for r, w in zip(rows, want):
    got = np.array([float(r[k]) for k in ("x_m", "y_m", "z_m")])
    assert np.abs(got - w).max() < 1e-12, (got, w)
    # The tool turned 180 deg about x at every pose.
    assert abs(float(r["rx_rad"]) - np.pi) < 1e-12
for r, w in zip(poses, want):
    got = np.array([float(r[k]) for k in ("commanded_x_m", "commanded_y_m", "commanded_z_m")])
    assert np.abs(got - w).max() < 1e-12, (got, w)
    q = [float(r[k]) for k in ("commanded_qw", "commanded_qx", "commanded_qy", "commanded_qz")]
    assert np.abs(np.array(q) - [0, 1, 0, 0]).max() < 1e-15, q
EOF
expect_fail "cube of 3 values" "--iso9283_cube: expected cx,cy,cz,edge_m" \
  activecal_select "${robot[@]}" --iso9283_cube=0.6,0.2,0.5 --poses_csv=bad5.csv
expect_fail "cube out of reach" "--iso9283_cube: P1 at (5600.0, 200.0, 500.0) mm (base frame): unreachable" \
  activecal_select "${robot[@]}" --iso9283_cube=5.6,0.2,0.5,0.3 --poses_csv=bad6.csv
for f in bad5.csv bad6.csv; do
  [ -e "$f" ] && fail "$f written" || ok "$f not written"
done


# The cube's poses, each run 3 times, simulated and evaluated directly:
# activecal_simulate carries the pose label and the commanded pose of each
# row to its measurement, so evaluate --iso9283 reads its output with no
# join. The robot is the nominal one (perturbed by 1e-12) with 20 um /
# 20 urad noise: each pose's AP is the mean of 3 cycles' noise (a row's
# commanded pose carried to another row would be 100s of mm off), RP_l the
# noise's scale.
"$py" - <<'EOF'
lines = [l for l in open("cube.csv") if l.strip() and not l.startswith("#")]
open("cube3.csv", "w").write(lines[0] + "".join(l for l in lines[1:] for _ in range(3)))
EOF
"$apps/activecal_simulate" "${robot[@]}" --poses_csv=cube3.csv --type=pose \
  --perturb_m=1e-12 --perturb_rad=1e-12 --noise_m=0.00002 --rotation_noise_rad=0.00002 \
  --seed=7 --out=sim_cycles.csv >sim.out 2>sim.err &&
  ok "simulate reads the cube's poses CSV" || { fail "simulate reads the cube's poses CSV"; cat sim.err; }
"$apps/activecal_evaluate" "${robot[@]}" --measurements=sim_cycles.csv --iso9283 \
  --before=none --json_out=sim_iso.json >sim_eval.out 2>sim_eval.err &&
  ok "evaluate --iso9283 reads simulate's output directly" ||
  { fail "evaluate --iso9283 reads simulate's output directly"; cat sim_eval.err; }
"$py" - <<'EOF' && ok "simulated cycles: 5 poses of 3 cycles, each row's commanded pose the cube's, AP at the noise" ||
import csv, json, sys
cube = list(csv.DictReader(l for l in open("cube.csv") if not l.startswith("#")))
rows = list(csv.DictReader(l for l in open("sim_cycles.csv") if not l.startswith("#")))
keys = ["commanded_%s" % k for k in ("x_m", "y_m", "z_m", "qw", "qx", "qy", "qz")]
bad = []
if len(rows) != 15: bad.append("%d rows" % len(rows))
for i, r in enumerate(rows[:15]):
    c = cube[i // 3]
    if r.get("pose") != c["pose"]: bad.append("row %d: pose %s" % (i, r.get("pose"))); continue
    # The quaternion's sign is free (q and -q are one rotation).
    dot = sum(float(r[k]) * float(c[k]) for k in keys[3:])
    for k in keys:
        s = (1 if dot >= 0 else -1) if k[10] == "q" else 1
        if abs(float(r[k]) - s * float(c[k])) > 1e-12: bad.append("row %d: %s" % (i, k))
try:
    poses = json.load(open("sim_iso.json"))["iso9283"]["poses"]
except Exception as e:
    poses = []; bad.append("no ISO JSON: %s" % e)
if [p["pose"] for p in poses] != ["P1", "P2", "P3", "P4", "P5"]: bad.append("labels")
for p in poses:
    w = p["without"]
    if p["num_cycles"] != 3: bad.append("%s: %d cycles" % (p["pose"], p["num_cycles"]))
    if not w["ap_p_m"] < 1e-4: bad.append("%s: AP_p %g m" % (p["pose"], w["ap_p_m"]))
    if not 1e-6 < w["rp_l_m"] < 3e-4: bad.append("%s: RP_l %g m" % (p["pose"], w["rp_l_m"]))
if bad:
    print(bad[:5]); sys.exit(1)
EOF
  fail "simulated cycles: 5 poses of 3 cycles, each row's commanded pose the cube's, AP at the noise"

cli_end
