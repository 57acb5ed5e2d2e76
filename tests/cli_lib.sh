# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Shared by the command-line tests: expects `apps` (the programs' folder)
# and `failures` (a counter) in the caller.

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

