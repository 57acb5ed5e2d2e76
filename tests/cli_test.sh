#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Command-line tests of the programs: the README's calibration loop with the
# shipped PUMA file gives the same files as the built-in model, and every
# bad input ends with status 1 and one clear line on stderr, leaving no
# half-written output.
#
#   tests/cli_test.sh <build/apps dir> <data dir> <check_report_json>
set -uo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
check_report="$(cd "$(dirname "$3")" && pwd)/$(basename "$3")"
source "$here/cli_lib.sh"
cli_begin "$@"

expect_same() {
  [ -s "$1" ] || { echo "FAIL [same]: $1 is empty or missing"; failures=$((failures + 1)); return; }
  if cmp -s "$1" "$2"; then echo "ok   [same $1 $2]"; else
    echo "FAIL [same]: $1 and $2 differ"; failures=$((failures + 1)); fi
}

# --- The README loop, with the YAML file and with the built-in model. ---
run_loop() {  # <suffix> [--robot=...]
  local s="$1"
  shift
  "$apps/activecal_select" "$@" --algorithm=fedorov --restarts=4 \
    --poses_csv="poses$s.csv" --json_out="select$s.json" >/dev/null || return 1
  "$apps/activecal_simulate" "$@" --poses_csv="poses$s.csv" --noise_m=0.001 \
    --seed=3 --out="measurements$s.csv" >/dev/null || return 1
  "$apps/activecal_identify" "$@" --measurements="measurements$s.csv" \
    --validation_fraction=0.2 --model_out="calibrated$s.yaml" \
    --json_out="report$s.json" >/dev/null || return 1
}
if run_loop _yaml --robot="$data/puma560.yaml" && run_loop _builtin; then
  echo "ok   [loop runs]"
else
  echo "FAIL [loop runs]"; failures=$((failures + 1))
fi
expect_same poses_yaml.csv poses_builtin.csv
expect_same measurements_yaml.csv measurements_builtin.csv
# The calibrated models differ only in the comment naming the input.
grep -v '^#' calibrated_yaml.yaml >a.yaml
grep -v '^#' calibrated_builtin.yaml >b.yaml
expect_same a.yaml b.yaml
grep -v '"measurements"' report_yaml.json >a.json
grep -v '"measurements"' report_builtin.json >b.json
expect_same a.json b.json
# The calibrated model loads back and identifies again from it.
"$apps/activecal_identify" --robot=calibrated_yaml.yaml \
  --measurements=measurements_yaml.csv >/dev/null 2>&1 &&
  echo "ok   [calibrated model reloads]" ||
  { echo "FAIL [calibrated model reloads]"; failures=$((failures + 1)); }

# The report's correlation matrix, read back: unit diagonal, symmetric,
# covariance / (std std^T), positive semi-definite.
for r in report_yaml.json; do
  if out=$("$check_report" "$r"); then echo "ok   [correlation of $r]"; else
    echo "FAIL [correlation of $r]: $out" | head -5; failures=$((failures + 1)); fi
done
"$apps/activecal_identify" --json_out=report_sim.json >/dev/null 2>&1
if out=$("$check_report" report_sim.json); then echo "ok   [correlation of report_sim.json]"; else
  echo "FAIL [correlation of report_sim.json]: $out" | head -5; failures=$((failures + 1)); fi

# --- Determinism: every program's JSON is byte-identical for 1 and 2
# threads, apart from the wall-clock times kept under "timing". ---
strip_timing() { sed '/"timing": {/,/}/d' "$1"; }
for t in 1 2; do
  "$apps/activecal_select" --algorithm=fedorov --restarts=4 --threads=$t \
    --json_out=select_t$t.json >/dev/null
  "$apps/activecal_select" --algorithm=eae --threads=$t --json_out=eae_t$t.json >/dev/null
  "$apps/activecal_puma_paper" --threads=$t --random_designs=500 \
    --out_dir=paper_t$t >/dev/null
  "$apps/activecal_monte_carlo" --threads=$t --trials=40 \
    --poses_csv=poses_builtin.csv --json_out=mc_t$t.json >/dev/null
done
for name in select eae mc; do
  strip_timing ${name}_t1.json >${name}_1.txt
  strip_timing ${name}_t2.json >${name}_2.txt
  expect_same ${name}_1.txt ${name}_2.txt
done
strip_timing paper_t1/paper_run.json >paper_1.txt
strip_timing paper_t2/paper_run.json >paper_2.txt
expect_same paper_1.txt paper_2.txt
for f in random_designs.csv eae_history.csv identification.csv certificate.csv; do
  expect_same paper_t1/$f paper_t2/$f
done

# --- --help shows the program's own flags (and --robot), not glog's. ---
for prog in activecal_select activecal_simulate activecal_identify \
  activecal_monte_carlo activecal_puma_paper; do
  "$apps/$prog" --help >help.txt 2>&1
  if grep -q -- "-robot" help.txt && ! grep -q -- "-logtostderr" help.txt &&
    [ "$(wc -l <help.txt)" -lt 200 ]; then
    echo "ok   [$prog --help: $(wc -l <help.txt) lines]"
  else
    echo "FAIL [$prog --help]: $(wc -l <help.txt) lines, glog flags or no --robot"
    failures=$((failures + 1))
  fi
done

# --- Every flag a program lists in --help is one it reads (issue 26:
# --parameter_set was listed by every program and ignored by simulate,
# active and monte_carlo; --parameter_set=bogus exited 0; active and the
# cell simulator now read it). ---
all_programs="activecal_select activecal_identify activecal_evaluate
  activecal_simulate activecal_compensate activecal_active
  activecal_monte_carlo activecal_puma_paper activecal_sim_cell"
for prog in $all_programs; do
  "$apps/$prog" --help >help.txt 2>&1
  # "  Flags from ../../apps/<file>.cc:" then "    -<flag> (...": each flag
  # with the file that defines it; that file must read FLAGS_<flag>.
  unread=$(awk '/Flags from /{f=$3; sub(/:$/, "", f); n=split(f, p, "/"); f=p[n]}
                /^    -[a-z0-9_]+ /{sub(/^    -/, ""); print f, $1}' help.txt |
    while read -r file flag; do
      src="$here/../apps/$file"
      if [ ! -f "$src" ] || [ "$(grep -c "FLAGS_$flag\b" "$src")" -lt 1 ]; then
        echo "--$flag ($file)"
      fi
    done)
  n=$(grep -cE '^    -[a-z0-9_]+ ' help.txt)
  if [ -z "$unread" ] && [ "$n" -gt 0 ]; then
    echo "ok   [$prog --help: every one of its $n flags is read]"
  else
    echo "FAIL [$prog --help lists flags it does not read: $unread]"
    failures=$((failures + 1))
  fi
done
# The shared flags: where a program has one, a bad value fails naming it;
# elsewhere the flag is unknown.
has_flag() {  # <program> <flag>: listed in --help
  "$apps/$1" --help >flag_help.txt 2>&1
  grep -qE "^    -$2 " flag_help.txt
}
for prog in $all_programs; do
  for flag in parameter_set strict_limits columns_strict; do
    case "$flag:$prog" in
      parameter_set:activecal_select | parameter_set:activecal_identify |\
        parameter_set:activecal_active | parameter_set:activecal_sim_cell |\
        parameter_set:activecal_simulate) want=yes ;;
      strict_limits:activecal_identify | strict_limits:activecal_evaluate) want=yes ;;
      columns_strict:activecal_identify | columns_strict:activecal_evaluate |\
        columns_strict:activecal_compensate) want=yes ;;
      *) want=no ;;
    esac
    if has_flag "$prog" "$flag"; then got=yes; else got=no; fi
    if [ "$want" != "$got" ]; then
      echo "FAIL [$prog --$flag: listed=$got, expected $want]"
      failures=$((failures + 1))
    elif [ "$got" = no ]; then
      expect_fail "$prog has no --$flag" "unknown command line flag '$flag'" \
        "$prog" --$flag=bogus
    elif [ "$flag" = parameter_set ]; then
      expect_fail "$prog --parameter_set=bogus" \
        "--parameter_set must be registration, offsets, full or file, got 'bogus'" \
        "$prog" --parameter_set=bogus
    else
      expect_fail "$prog --$flag=bogus" "illegal value 'bogus' specified for bool flag '$flag'" \
        "$prog" --$flag=bogus
    fi
  done
done

# --- Bad flags. ---
expect_fail "levels=1" "--levels=1" activecal_select --levels=1
sed 's/limits: \[-4.363323129985824, 1.2217304763960306\]/limits: [-6.283185307179586, 6.283185307179586]/' \
  "$data/puma560.yaml" >turn.yaml
if "$apps/activecal_select" --robot=turn.yaml --levels=3 --num_poses=30 >turn.txt 2>&1 &&
  grep -q "joint 1 (L1) spans a full turn: its 3 levels cover one turn" turn.txt; then
  echo "ok   [a full-turn range is sampled over one turn]"
else
  echo "FAIL [full-turn lattice]"; cat turn.txt; failures=$((failures + 1))
fi
# Issue 26: a robot with a continuous joint (the rail arm's j3) got no
# pool of any kind ("no finite range"); it is sampled over one turn.
for pool in lattice sobol random; do
  size=(--pool_size=500)
  [ $pool = lattice ] && size=()
  if "$apps/activecal_select" --robot="$here/data/arm7_rail.urdf" --tip_link=tcp \
    --pool=$pool --levels=2 "${size[@]}" --parameter_set=offsets \
    --num_poses=20 --poses_csv=rail_$pool.csv >rail.txt 2>rail.err &&
    [ "$(($(wc -l <rail_$pool.csv) - 1))" -eq 20 ] &&
    { [ $pool != lattice ] ||
      grep -q "note: joint 4 (j3) has no limits: its 2 levels cover one turn from -180 deg (a continuous joint)" rail.txt; }; then
    echo "ok   [a continuous joint: --pool=$pool designs]"
  else
    echo "FAIL [a continuous joint, --pool=$pool]"; cat rail.txt rail.err
    failures=$((failures + 1))
  fi
done
# Issue 26: a pool too large for memory was a std::bad_alloc (exit 134).
expect_fail "a sobol pool too large for memory" \
  "--pool_size: a pool of 100000000000 poses needs at least" \
  activecal_select --pool=sobol --pool_size=100000000000
expect_fail "a random pool too large for memory" \
  "--pool_size: a pool of 2000000000 poses needs at least" \
  activecal_select --pool=random --pool_size=2000000000
# Issue 26: --pool_size with the lattice was ignored (exit 0).
expect_fail "--pool_size with the lattice" \
  "--pool_size sizes a --pool=sobol, random or measurable pool; the lattice has --levels poses per joint" \
  activecal_select --pool_size=100000000000
expect_fail "a lattice too large for memory" \
  "--levels=31: a pool of 887503681 poses needs at least" \
  activecal_select --levels=31
expect_fail "num_poses=0" "--num_poses must be in [1, 15625]" activecal_select --num_poses=0
expect_fail "more poses than the pool" "--num_poses must be in [1, 15625]" \
  activecal_select --num_poses=20000
expect_fail "unknown algorithm" "--algorithm must be one of" activecal_select --algorithm=simplex
expect_fail "distance pool" "--measurement must be position or pose" \
  activecal_select --measurement=distance
expect_fail "monte carlo trials" "num_trials must be >= 3, got 1" \
  activecal_monte_carlo --trials=1 --poses_csv=poses_builtin.csv
expect_fail "stray argument" "unexpected argument 'fedorov'" activecal_select fedorov
expect_fail "unknown loss" "--robust_loss must be none, huber or cauchy" \
  activecal_identify --robust_loss=tukey
expect_fail "loss without scale" "needs robust_scale_m > 0" \
  activecal_identify --robust_loss=huber
expect_fail "validation fraction" "--validation_fraction must be in [0, 0.9]" \
  activecal_identify --validation_fraction=2
expect_fail "simulate without poses" "--poses_csv is required" activecal_simulate --out=x.csv
expect_fail "simulate type" "--type must be position, pose or distance" \
  activecal_simulate --poses_csv=poses_yaml.csv --out=x.csv --type=angle
expect_fail "negative noise" "noise standard deviation must be finite and >= 0" \
  activecal_simulate --poses_csv=poses_yaml.csv --out=x.csv --noise_m=-1

# --- Bad files. ---
expect_fail "missing robot file" "--robot: nope.yaml: cannot open the robot file" \
  activecal_select --robot=nope.yaml
sed 's/alpha: -1.4524/alpha: -1.45x24/' "$data/puma560.yaml" >typo.yaml
expect_fail "typo in robot file" "typo.yaml:31:12: links[0].alpha: expected a number, got '-1.45x24'" \
  activecal_select --robot=typo.yaml
grep -v 'true:' "$data/puma560.yaml" >notruth.yaml
expect_fail "no true values" "has no true values to simulate from" \
  activecal_simulate --robot=notruth.yaml --poses_csv=poses_yaml.csv --out=x.csv
expect_fail "missing measurements" "--measurements: nope.csv: cannot open the file" \
  activecal_identify --measurements=nope.csv
sed '5s/^\(\([^,]*,\)\{7\}\)[^,]*/\1abc/' measurements_yaml.csv >bad.csv  # x_m of row 4
expect_fail "bad measurement value" "bad.csv:5:" activecal_identify --measurements=bad.csv
head -5 measurements_yaml.csv >few.csv
expect_fail "too few measurements" "the 4 measurements: too few equations: 12 measurement rows for 27 free parameters" \
  activecal_identify --measurements=few.csv
head -10 measurements_yaml.csv >nine.csv
expect_fail "zero degrees of freedom" "27 measurement rows for 27 free parameters leave 0 degrees of freedom" \
  activecal_identify --measurements=nine.csv
printf 'pose_index,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n0,0,0,0,0,0,0\n1,0,0,0,0,0,0\n' >dup.csv
expect_fail "duplicate pool poses" "dup.csv:3: row: duplicate pose: the same joint values as line 2" \
  activecal_select --pool_csv=dup.csv --num_poses=1
# Issue 26: two pool rows of the same label were accepted silently.
printf 'pose_index,q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n4,0,0,0,0,0,0\n5,10,0,0,0,0,0\n4,20,0,0,0,0,0\n' >duplabel.csv
expect_fail "duplicate pool labels" "--pool_csv: duplabel.csv:4: pose_index: 4 is also the label of line 2 (the labels of a pool name its poses, each once)" \
  activecal_select --pool_csv=duplabel.csv --num_poses=1
printf 'q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n0,0,0,0,0,400\n' >range.csv
expect_fail "joint out of range" "range.csv:2: row: joint 6 (L6) value 6.98132 rad (400 deg) is outside its range [-176, 356] deg" \
  activecal_simulate --poses_csv=range.csv --out=x.csv
printf 'q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n0,0,0,0,0,0\n10,0,0,0,0,0\n10,0,0,0,0,0\n' >same.csv
expect_fail "distance between identical poses" "--type=distance: poses 2 and 3 of same.csv (data rows) are identical" \
  activecal_simulate --poses_csv=same.csv --out=x.csv --type=distance
printf 'q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n0,0,0,0,0,0\n0,0,0,0,0,-60\n0,0,0,0,0,300\n' >turn6.csv
expect_fail "distance between coinciding points" "measurement 1: its two poses put the measured point at the same place" \
  activecal_simulate --poses_csv=turn6.csv --out=x.csv --type=distance
printf 'type,q1_rad,q2_rad,q3_rad,q4_rad,q5_rad,q6_rad,x_m,y_m,z_m,q1_rad_2,q2_rad_2,q3_rad_2,q4_rad_2,q5_rad_2,q6_rad_2,distance_m\ndistance,0,0,0,0,0,0,,,,0,0,0,0,0,0,0.5\n' >samed.csv
expect_fail "measured distance between identical poses" "samed.csv:2: row: a distance between two identical poses" \
  activecal_identify --measurements=samed.csv
printf 'q1_deg,q2_deg,q3_deg,q4_deg,q5_deg,q6_deg\n' >empty.csv
expect_fail "empty pool" "empty.csv:1: header: no poses after the header" \
  activecal_select --pool_csv=empty.csv

# --- Unidentifiable parameters: refused, or fixed with --auto_fix. ---
awk '/^base:/{b=1} b&&/free:/{sub(/beta\]/,"beta, d]"); b=0} {print}' \
  "$data/puma560.yaml" >based.yaml
expect_fail "unidentifiable" "not identifiable" activecal_identify --robot=based.yaml \
  --measurements=measurements_yaml.csv
grep -q "or pass --auto_fix" err.txt && grep -q "B.d" err.txt &&
  echo "ok   [unidentifiable message names B.d and --auto_fix]" ||
  { echo "FAIL [unidentifiable message]"; failures=$((failures + 1)); }
if "$apps/activecal_identify" --robot=based.yaml --measurements=measurements_yaml.csv \
  --auto_fix --json_out=autofix.json >err.txt 2>&1 &&
  grep -q "auto_fix.*holding them at their nominal values" err.txt &&
  grep -q '"auto_fixed"' autofix.json; then
  echo "ok   [--auto_fix]: $(cat err.txt)"
else
  echo "FAIL [--auto_fix]"; cat err.txt; failures=$((failures + 1))
fi

# --auto_fix with --model_out: the fixed parameters are named in the output
# and in a comment of the file (they are no longer in its 'free'). B.d and
# L1.d move the point along the same axis: which of the two is held depends
# on the pivoting of the data's Jacobian, so either is right.
"$apps/activecal_identify" --robot=based.yaml --measurements=measurements_yaml.csv \
  --auto_fix --model_out=autofix.yaml >autofix.txt 2>/dev/null
if grep -Eq "^# .*held fixed at their nominal values.*(B|L1)\.d" autofix.yaml &&
  grep -Eq "holding them at their nominal values.*(B|L1)\.d" autofix.txt; then
  echo "ok   [--auto_fix names B.d or L1.d in --model_out and the output]"
else
  echo "FAIL [--auto_fix --model_out]"; head -3 autofix.yaml; failures=$((failures + 1))
fi
# A robot file in degrees: the table shows angles in degrees, unit named.
perl -pe 's/angle_unit: rad/angle_unit: deg/;
  s/\b(gamma|alpha|beta|rx|ry|rz): (-?[0-9.eE+-]+)/"$1: ".($2*45\/atan2(1,1))/ge;
  s/limits: \[(\S+), (\S+)\]/"limits: [".($1*45\/atan2(1,1)).", ".($2*45\/atan2(1,1))."]"/e' \
  "$data/puma560.yaml" >deg.yaml
"$apps/activecal_identify" --robot=deg.yaml --measurements=measurements_yaml.csv >deg.txt 2>&1
if grep -q "^B.gamma *deg *93.73" deg.txt && grep -q "^B.a *m *19.88" deg.txt; then
  echo "ok   [table in the robot file's angle unit]"
else
  echo "FAIL [table in the robot file's angle unit]"; head -3 deg.txt; failures=$((failures + 1))
fi

# --- No half-written output: a failing write leaves the old file alone. ---
echo "keep me" >kept.json
expect_fail "unwritable output" "--model_out: cannot write 'no_such_dir/m.yaml'" \
  activecal_identify --json_out=kept.json --model_out=no_such_dir/m.yaml
[ "$(cat kept.json)" = "keep me" ] && echo "ok   [old output kept]" ||
  { echo "FAIL [old output kept]"; failures=$((failures + 1)); }

cli_end
