# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Shared by the command-line tests: the programs' folder in `apps`, the
# data folder in `data`, a temporary folder to work in, the failures
# counted in `failures`.
#
#   here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
#   source "$here/cli_lib.sh"
#   cli_begin "$@"        # apps=$1, data=$2 (absolute), cd to a temp folder
#   ...
#   cli_end               # "<test>: N failure(s)"; the status: N == 0

failures=${failures:-0}

# cli_workdir: a fresh temporary folder in $work, removed when the script
# exits; the script runs in it (every file a test writes lands there).
cli_workdir() {
  work="$(mktemp -d)"
  trap 'rm -rf "$work"' EXIT
  cd "$work" || exit 1
}

# cli_begin <apps dir> [<data dir>] ...: $apps and $data as absolute
# paths (the arguments after the second are the script's), then
# cli_workdir.
#
# Progress lines appear after a step has run 2 s, so a slow machine (a
# sanitizer build) would print lines a fast one does not: the tests run with
# them off (ACTIVECAL_PROGRESS_AFTER_S, app_common.h), and the tests of the
# progress lines set it again after cli_begin.
cli_begin() {
  export ACTIVECAL_PROGRESS_AFTER_S=1000000
  apps="$(cd "$1" && pwd)" || exit 1
  if [ $# -ge 2 ]; then data="$(cd "$2" && pwd)" || exit 1; fi
  cli_workdir
}

# cli_end: the count of failures, and the script's status (0: none).
cli_end() {
  echo "$(basename "$0" .sh): $failures failure(s)"
  exit $((failures > 0))
}

# joint_columns <measurements CSV> <poses CSV>: the six joint columns
# (q1_rad..q6_rad) of a measurements file's rows as a poses file.
joint_columns() {
  python3 - "$1" "$2" <<'PY'
import csv, sys
rows = list(csv.DictReader(l for l in open(sys.argv[1]) if not l.startswith("#")))
cols = ["q%d_rad" % j for j in range(1, 7)]
with open(sys.argv[2], "w") as f:
    f.write(",".join(cols) + "\n")
    for r in rows:
        f.write(",".join(r[c] for c in cols) + "\n")
PY
}

# two_target_cell: data/cells/ur10e_table.yaml without its targets in
# base.yaml, and with two (smr on top, side on the +x face) in two.yaml.
two_target_cell() {
  sed '/^targets:/,$d' "$data/cells/ur10e_table.yaml" >base.yaml
  { cat base.yaml; cat <<'YAML'
targets:
  - {name: smr, xyz_m: [0, 0, 0.06], normal: [0, 0, 1], acceptance_deg: 30}
  - {name: side, xyz_m: [0.05, 0, 0.03], normal: [1, 0, 0], acceptance_deg: 30}
YAML
  } >two.yaml
}

# ok <name>, fail <name>: one line each; fail counts in $failures.
ok() { echo "ok   [$1]"; }
fail() { echo "FAIL [$1]"; failures=$((failures + 1)); }

# fail_because <name> <why> [<file>]: a FAIL line with the reason, then the
# file's text; counted in $failures.
fail_because() {
  echo "FAIL [$1]: $2"
  [ $# -lt 3 ] || cat "$3"
  failures=$((failures + 1))
}

# run_prog <program> [flags...]: runs $apps/<program> with its stdout in
# out.txt and its stderr in err.txt; its exit status is run_prog's.
run_prog() {
  local prog="$1"
  shift
  "$apps/$prog" "$@" >out.txt 2>err.txt
}

# expect_fail <name> <text expected on stderr> <program> [flags...]
expect_fail() {
  local name="$1" want="$2"
  shift 2
  run_prog "$@"
  local status=$? lines
  lines=$(wc -l <err.txt)
  if [ "$status" -ne 1 ]; then
    fail_because "$name" "exit status $status, expected 1"
  elif [ "$lines" -ne 1 ]; then
    fail_because "$name" "$lines lines on stderr, expected 1:" err.txt
  elif ! grep -qF -- "$want" err.txt; then
    fail_because "$name" "stderr lacks '$want':" err.txt
  else
    echo "ok   [$name]: $(cat err.txt)"
  fi
}

# expect_run <name> <stdout file> <stderr file> <program> [flags...]: ok
# <name> where the program exits 0, else fail <name> and its stderr.
expect_run() {
  local name="$1" out="$2" err="$3" prog="$4"
  shift 4
  if "$apps/$prog" "$@" >"$out" 2>"$err"; then
    ok "$name"
  else
    fail "$name"; cat "$err"
  fi
}

# expect_ok <name> <text expected on stdout> <program> [flags...]: status 0,
# nothing on stderr, the text on stdout.
expect_ok() {
  local name="$1" want="$2"
  shift 2
  run_prog "$@"
  local status=$?
  if [ "$status" -ne 0 ]; then
    fail_because "$name" "exit status $status:" err.txt
  elif [ -s err.txt ]; then
    fail_because "$name" "stderr is not empty:" err.txt
  elif ! grep -qF -- "$want" out.txt; then
    fail_because "$name" "stdout lacks '$want':" out.txt
  else
    echo "ok   [$name]: $(grep -F -- "$want" out.txt)"
  fi
}

# figaroh_ur10e: the FIGAROH UR10e measurements in $m, the UR10e flags
# (URDF, tip, rotation weight) in the array $ur.
figaroh_ur10e() {
  m="$data/figaroh_ur10e/measurements.csv"
  ur=(--robot="$data/ur10e.urdf" --tip_link=tool0 --rotation_weight=0.1)
}

# puma_table_cell <tests/data dir>: that folder (absolute) in $tdata, the
# PUMA in $puma, its table cell in $cell and the active loop's flags for
# it in the array $loop.
puma_table_cell() {
  tdata="$(cd "$1" && pwd)" || exit 1
  puma="$data/puma560.yaml"
  cell="$tdata/puma_table_cell.yaml"
  loop=(--robot="$puma" --levels=3 --max_rounds=3 --restarts=1 --threads=2)
}
