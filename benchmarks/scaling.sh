#!/usr/bin/env bash
# Time and peak memory of activecal_select --algorithm=fedorov (Jacobians,
# approximate design, certificate and exchanges included) against pool size
# (levels per joint) and design size. Prints a Markdown table.
#
#   benchmarks/scaling.sh [build_dir]      (needs GNU time: apt-get install time)
set -euo pipefail
build="${1:-build}"
select="$build/apps/activecal_select"
[ -x "$select" ] || { echo "scaling.sh: build first (./run.sh build)" >&2; exit 1; }
[ -x /usr/bin/time ] || { echo "scaling.sh: needs GNU time (apt-get install time)" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
echo "| levels | pool | poses | seconds | peak MiB | log10 det | efficiency >= | Jacobians s | approx. design s |"
echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
for levels in ${LEVELS:-5 7 10}; do
  for poses in ${POSES:-30 60 145}; do
    /usr/bin/time -f "%e %M" -o "$tmp/time" "$select" --levels=$levels \
      --num_poses=$poses --algorithm=fedorov --json_out="$tmp/out.json" \
      > /dev/null
    read -r secs kb < "$tmp/time"
    python3 - "$tmp/out.json" "$levels" "$poses" "$secs" "$kb" <<'PY'
import json, sys
j = json.load(open(sys.argv[1]))
levels, poses, secs, kb = sys.argv[2:]
print(f"| {levels} | {j['pool_size']} | {poses} | {float(secs):.1f} | {int(kb)/1024:.0f} | "
      f"{j['log10_det']:.4f} | {j['efficiency_lower_bound']:.4f} | "
      f"{j['timing']['jacobian_seconds']:.1f} | {j['timing']['approximate_seconds']:.1f} |")
PY
  done
done
