#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Time and peak memory of activecal_select --algorithm=fedorov (Jacobians,
# approximate design, certificate and exchanges included) against pool size
# and design size. Prints Markdown tables: the PUMA lattice (levels per
# joint) and sampled pools of any robot.
#
#   benchmarks/scaling.sh [build_dir]      (needs GNU time: apt-get install time)
#
# Environment: LEVELS ("5 7 10"), POSES ("30 60 145"): the lattice table;
# SAMPLED ("robot:pool:size:poses ..."; default the KUKA iiwa 14 at 10^6
# and 10^7 Sobol poses, 100 poses): the sampled table ("" skips it);
# THREADS (0: all).
set -euo pipefail
build="${1:-build}"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
select="$build/apps/activecal_select"
[ -x "$select" ] || { echo "scaling.sh: build first (./run.sh build)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "scaling.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
threads="${THREADS:-0}"

row() {  # label args... : one table row from the run's JSON and GNU time
  local label="$1"; shift
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$select" "$@" --threads="$threads" \
    --algorithm=fedorov --json_out="$tmp/out.json" > /dev/null
  read -r secs kb < "$tmp/time"
  python3 - "$tmp/out.json" "$label" "$secs" "$kb" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
label, secs, kb = sys.argv[2:]
t = j['timing']
print(f"| {label} | {j['pool_size']} | {j['num_poses']} | {j['pool_storage']} | "
      f"{float(secs):.1f} | {int(kb)/1024:.0f} | {j['log10_det']:.4f} | "
      f"{j['efficiency_lower_bound']:.4f} | {t['jacobian_seconds']:.1f} | "
      f"{t['approximate_seconds']:.1f} | {t['selection_seconds']:.1f} |")
PY
}

echo "| pool | poses in pool | design | storage | seconds | peak MiB | log10 det | efficiency >= | Jacobians s | approx. design s | exchanges s |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for levels in ${LEVELS-5 7 10}; do
  for poses in ${POSES-30 60 145}; do
    row "PUMA lattice, $levels levels" --levels="$levels" --num_poses="$poses"
  done
done
for spec in ${SAMPLED-$here/data/kuka_iiwa14.urdf:sobol:1000000:100 $here/data/kuka_iiwa14.urdf:sobol:10000000:100}; do
  IFS=: read -r robot pool size poses <<< "$spec"
  row "$(basename "$robot" .urdf) $pool" --robot="$robot" --pool="$pool" \
    --pool_size="$size" --num_poses="$poses"
done
