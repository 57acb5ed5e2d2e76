#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# A program killed by SIGTERM, SIGINT or SIGHUP while it writes an output
# leaves no temporary behind and the old file as it was (#24: "kill -TERM
# mid-write leaves temps"), and still dies of the signal (exit status 128 +
# the signal's number, as without the handler).
#
# The temporary of --json_out is made a FIFO before the program starts
# (exec keeps the starter's pid, so its name is known), so that the program
# blocks in opening it, where the test kills it: no timing involved. The
# starter gives the program the signals' default actions (a background job
# of a script inherits SIGINT ignored), or SIGHUP ignored as nohup does,
# which must stay so.
#
#   tests/killed_outputs_cli_test.sh <build/apps dir> <data dir>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
source "$here/cli_lib.sh"
cli_begin "$@"

# Waits until process $1 sleeps in opening a FIFO (Linux: wchan); 1 when
# it does not within $2 s (default 60).
wait_blocked_on_fifo() {
  local k
  for ((k = 0; k < ${2:-60} * 10; ++k)); do
    [[ "$(cat "/proc/$1/wchan" 2>/dev/null)" == wait_for_partner ]] && return 0
    sleep 0.1
  done
  return 1
}

# The kernel names where a process sleeps only where /proc/<pid>/wchan is
# readable and not hidden (it reads 0 under some kernel settings): a shell
# blocked in opening a FIFO of its own for writing shows whether it does.
wchan_names_fifo_opens() {
  mkfifo probe.fifo || return 1
  (exec 3>probe.fifo) &
  local probe=$! shown=1
  wait_blocked_on_fifo "$probe" 10 && shown=0
  kill -KILL "$probe" 2>/dev/null
  wait "$probe" 2>/dev/null
  rm -f probe.fifo
  return $shown
}

if ! wchan_names_fifo_opens; then
  echo "killed_outputs_cli_test: /proc/<pid>/wchan does not name a FIFO open here; skipped"
  exit 77  # ctest: skipped (SKIP_RETURN_CODE)
fi

# start <dir> <SIGHUP: default|ignore> <program and flags...>: in the
# background, its pid in $pid.
start() {
  python3 - "$@" <<'PY' &
import os, signal, sys
folder, hup, program = sys.argv[1], sys.argv[2], sys.argv[3:]
for s in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
    signal.signal(s, signal.SIG_DFL)
if hup == "ignore":
    signal.signal(signal.SIGHUP, signal.SIG_IGN)
os.mkfifo(f"{folder}/r.json.activecal-{os.getpid()}.tmp")
os.execv(program[0], program)
PY
  pid=$!
}

for signal in TERM INT HUP; do
  dir="$signal"
  mkdir "$dir"
  echo '{"old": true}' >"$dir/r.json"
  start "$dir" default "$apps/activecal_identify" --num_poses=40 \
    --json_out="$dir/r.json" --model_out="$dir/m.yaml" >"$dir/out" 2>"$dir/err"
  if ! wait_blocked_on_fifo "$pid"; then
    fail "SIG$signal: activecal_identify never opened its temporary"
    kill -KILL "$pid" 2>/dev/null
    continue
  fi
  kill -"$signal" "$pid"
  wait "$pid"
  status=$?
  number=$(kill -l "$signal")
  [[ $status -eq $((128 + number)) ]] &&
    ok "SIG$signal: the program dies of the signal (status $status)" ||
    fail "SIG$signal: status $status, expected $((128 + number))"
  left=$(ls -A "$dir" | grep -v -x -e out -e err -e r.json)
  [[ -z "$left" ]] && ok "SIG$signal: no temporary left" ||
    fail "SIG$signal: left behind: $left"
  [[ "$(cat "$dir/r.json")" == '{"old": true}' ]] &&
    ok "SIG$signal: the old output is as it was" ||
    fail "SIG$signal: the old output changed"
  [[ ! -e "$dir/m.yaml" ]] && ok "SIG$signal: no other output written" ||
    fail "SIG$signal: --model_out written"
done

# Under nohup (SIGHUP ignored when it starts) the program ignores SIGHUP.
mkdir nohup
start nohup ignore "$apps/activecal_identify" --num_poses=40 \
  --json_out=nohup/r.json >nohup/out 2>nohup/err
if wait_blocked_on_fifo "$pid"; then
  kill -HUP "$pid"
  sleep 0.5
  kill -0 "$pid" 2>/dev/null && ok "an ignored SIGHUP stays ignored (nohup)" ||
    fail "the program died of a SIGHUP it was started ignoring"
  kill -TERM "$pid" 2>/dev/null
  wait "$pid"
  [[ -z "$(ls -A nohup | grep -v -x -e out -e err -e r.json)" ]] &&
    ok "nohup: SIGTERM still removes the temporary" || fail "nohup: temporary left"
else
  fail "nohup: activecal_identify never opened its temporary"
  kill -KILL "$pid" 2>/dev/null
fi

cli_end
