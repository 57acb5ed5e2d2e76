#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Draws the curve of an activecal_select --target_rms_m run: the predicted
# task RMS position error of the design of each size the search tried,
# with the target, as a PNG.
#
#   scripts/plot_task_rms.sh curve.csv target_m out.png [label]
#
# curve.csv is what --curve_csv wrote (num_poses,predicted_task_rms_m).
set -euo pipefail
[ $# -ge 3 ] || { echo "usage: plot_task_rms.sh curve.csv target_m out.png [label]" >&2; exit 1; }
csv="$1"; target="$2"; out="$3"; label="${4:-designs}"
[ -s "$csv" ] || { echo "plot_task_rms.sh: $csv is missing or empty: run activecal_select --target_rms_m=... --curve_csv=$csv first" >&2; exit 1; }
command -v gnuplot >/dev/null || { echo "plot_task_rms.sh: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 900,600 enhanced font "sans,12"
set output "$out"
set grid
set logscale y
set title "Predicted task RMS position error against the number of poses"
set xlabel "poses in the design"
set ylabel "predicted task RMS (mm)"
plot "$csv" skip 1 using 1:(\$2*1000) with linespoints pt 7 lw 2 title "$label", \
     ($target*1000) with lines lw 2 dt 2 lc rgb "red" title sprintf("target %.4g mm", $target*1000)
GP
