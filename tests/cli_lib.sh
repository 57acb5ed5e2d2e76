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

# expect_fail <name> <text expected on stderr> <program> [flags...]
expect_fail() {
  local name="$1" want="$2"
  shift 2
  local prog="$1"
  shift
  "$apps/$prog" "$@" >out.txt 2>err.txt
  local status=$?
  local lines
  lines=$(wc -l <err.txt)
  if [ "$status" -ne 1 ]; then
    echo "FAIL [$name]: exit status $status, expected 1"; failures=$((failures + 1))
  elif [ "$lines" -ne 1 ]; then
    echo "FAIL [$name]: $lines lines on stderr, expected 1:"; cat err.txt
    failures=$((failures + 1))
  elif ! grep -qF -- "$want" err.txt; then
    echo "FAIL [$name]: stderr lacks '$want':"; cat err.txt
    failures=$((failures + 1))
  else
    echo "ok   [$name]: $(cat err.txt)"
  fi
}

