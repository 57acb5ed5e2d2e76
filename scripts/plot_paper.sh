#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Draws the figures of a activecal_puma_paper run with gnuplot, as PNG files
# in <out_dir>/plots:
#
#   fig2_random_oi_histogram.png   OI of the random designs (paper Fig. 2)
#   fig4a_selected_pose_levels.png joint levels of the selected poses (Fig. 4A)
#   fig4b_log_det_history.png      log10 det per selection step (Figs. 4B, 6)
#   identification_errors.png      parameter errors with +-2 std (Table IV)
#   certificate.png                each design's log10 det against the
#                                  certified upper bound (beyond the paper)
#
#   scripts/plot_paper.sh [out_dir]   (default paper_out)
set -euo pipefail
dir="${1:-paper_out}"
for f in random_designs.csv eae_history.csv eae_poses.csv identification.csv; do
  [ -s "$dir/$f" ] || { echo "plot_paper.sh: $dir/$f is missing: run activecal_puma_paper --out_dir=$dir first" >&2; exit 1; }
done
command -v gnuplot >/dev/null || { echo "plot_paper.sh: gnuplot is not installed (apt-get install gnuplot-nox)" >&2; exit 1; }
plots="$dir/plots"
mkdir -p "$plots"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT

# Parameter errors split by unit, converted to mrad and mm.
awk -F, 'NR>1 && $2=="rad" {print $1","$6*1000","$7*2000}' "$dir/identification.csv" >"$tmp/angles.csv"
awk -F, 'NR>1 && $2=="m"   {print $1","$6*1000","$7*2000}' "$dir/identification.csv" >"$tmp/lengths.csv"
eae_oi=$(tail -n 1 "$dir/eae_history.csv" | cut -d, -f7)
best_random_oi=$(awk -F, 'NR>1 && $3>m {m=$3} END {print m}' "$dir/random_designs.csv")
num_random=$(($(wc -l <"$dir/random_designs.csv") - 1))
upper=""
[ -s "$dir/certificate.csv" ] && upper=$(awk -F, 'NR==2 {print $3}' "$dir/certificate.csv")
eigen=""
[ -s "$dir/eae_eigen_oi_history.csv" ] && eigen="$dir/eae_eigen_oi_history.csv"

gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 1000,650 enhanced font "sans,12"
set grid
set key top left

# Fig. 2: histogram of the random designs' OI.
set output "$plots/fig2_random_oi_histogram.png"
set title "Fig. 2: OI of $num_random random 30-pose designs (paper: best 0.0963)"
set xlabel "observability index OI (dimensionless)"
set ylabel "number of designs"
binwidth = 0.0005
bin(x) = binwidth * floor(x / binwidth) + binwidth / 2
set style fill solid 0.6 border -1
set boxwidth binwidth
set arrow 1 from $best_random_oi, graph 0 to $best_random_oi, graph 0.9 nohead lw 2 lc rgb "red"
set label 1 sprintf("best random\n%.4f", $best_random_oi) at $best_random_oi, graph 0.95 center tc rgb "red"
set arrow 2 from $eae_oi, graph 0 to $eae_oi, graph 0.9 nohead lw 2 lc rgb "dark-green"
set label 2 sprintf("exchange-add-exchange\n%.4f", $eae_oi) at $eae_oi, graph 0.95 center tc rgb "dark-green"
set xrange [*:$eae_oi + 0.003]
plot "$dir/random_designs.csv" skip 1 using (bin(\$3)):(1.0) smooth freq with boxes lc rgb "steelblue" title "random designs"
unset arrow; unset label; set xrange [*:*]

# Fig. 4B / 6: log10 det per step.
set output "$plots/fig4b_log_det_history.png"
set title "Figs. 4B, 6: exchange-add-exchange, log10 det(X^T X) per step"
set xlabel "step (exchange or addition)"
set ylabel "log_{10} det(X^T X) (units of the parameters)"
set key bottom right
plot "$dir/eae_history.csv" skip 1 using 1:6 with linespoints pt 7 lw 2 title "determinant update" \
  $( [ -n "$eigen" ] && echo ", \"$eigen\" skip 1 using 1:6 with lines dt 2 lw 2 title \"eigenvalue OI\"" ) \
  $( [ -n "$upper" ] && echo ", $upper with lines lw 2 dt 3 lc rgb \"red\" title \"certified upper bound for 30 poses\"" )

# Fig. 4A: joint levels of the selected poses.
set output "$plots/fig4a_selected_pose_levels.png"
set title "Fig. 4A: joint levels of the 30 selected poses (0 = lower joint limit, 4 = upper)"
set xlabel "selected pose (order in the design)"
set ylabel "joint"
set yrange [0.5:6.5]
set ytics 1
set xrange [-1:30]
set cblabel "joint level"
set cbrange [0:4]
set cbtics 1
set palette defined (0 "navy", 1 "blue", 2 "grey80", 3 "orange", 4 "dark-red")
unset key
plot for [j=1:6] "$dir/eae_poses.csv" skip 1 using 1:(j):(column(2+j)) with points pt 5 ps 3.2 lc palette
set yrange [*:*]; set xrange [*:*]; set ytics autofreq

# Identification errors with +-2 std bars, angles and lengths apart.
set output "$plots/identification_errors.png"
set terminal pngcairo size 1200,800 enhanced font "sans,11"
unset title
set offsets 0.5, 0.5, 0, 0
set multiplot layout 2,1 title "Identification at the selected poses: estimate - true, with +-2 std bars"
set key top right
set xtics rotate by -45
set xzeroaxis lt -1
set ylabel "error (mrad)"
set xlabel ""
set xrange [*:*]
plot "$tmp/angles.csv" using 0:2:3:xticlabels(1) with yerrorbars pt 7 title "angles"
set ylabel "error (mm)"
set xlabel "parameter"
plot "$tmp/lengths.csv" using 0:2:3:xticlabels(1) with yerrorbars pt 7 lc rgb "dark-green" title "lengths"
unset multiplot
GP

if [ -n "$upper" ]; then
gnuplot <<GP
set datafile separator ","
set terminal pngcairo size 1000,650 enhanced font "sans,12"
set output "$plots/certificate.png"
set title "How close each design is to the best possible 30-pose design"
set ylabel "log_{10} det(X^T X)"
set grid ytics
set style fill solid 0.6 border -1
set boxwidth 0.5
set yrange [25:$upper + 0.5]
set key top left
plot "$dir/certificate.csv" skip 1 using 0:2:xticlabels(1) with boxes lc rgb "steelblue" title "design", \
     "" skip 1 using 0:(\$2 + 0.12):(sprintf("efficiency >= %.3f", \$4)) with labels notitle, \
     $upper with lines lw 2 dt 2 lc rgb "red" title "certified upper bound"
GP
fi
ls "$plots"/*.png
