# plot.gp -- gnuplot script for the algorithm table (called by bench/run).
#
# Variables given with -e: dir (directory holding one data file per series,
# named <algorithm>_<distribution>.dat, columns: n median_ms ns_per_point),
# series (space-separated list of those names, without .dat), out_time and
# out_nspp (the two PNG files), title (a line naming machine and commit).
#
# Plot 1: median time of vor_compute against n, log-log: a straight line of
# slope 1 is linear growth; n log n bends slightly upwards.
# Plot 2: nanoseconds per point against n (both log): flat is linear; the
# rise at small n is the fixed cost per call; at large n, the memory
# hierarchy.

set terminal pngcairo size 1100,720 font ",10" noenhanced
set datafile separator whitespace
set key outside right top
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set logscale x 10
set format x "10^{%L}"
set xlabel "n (input points)"

dashes(s) = strstrt(s, "uniform") ? 1 : strstrt(s, "gaussian") ? 2 : 3
colour(s) = strstrt(s, "fortune") ? "#d62728" : \
            strstrt(s, "bowyer") ? "#1f77b4" : "#2ca02c"

set terminal pngcairo size 1100,720 font ",10" enhanced
set output out_time
set title "vor_compute, full diagram: median time (".title.")" noenhanced
set logscale y 10
set format y "10^{%L}"
set ylabel "milliseconds"
plot for [s in series] dir."/".s.".dat" using 1:2 with linespoints \
     dt dashes(s) lc rgb colour(s) pt 7 ps 0.6 title s noenhanced

set output out_nspp
set title "vor_compute, full diagram: time per point (".title.")" noenhanced
# Log scale here too: one slow series must not flatten all the others.
set format y "%g"
set ylabel "nanoseconds per input point (log scale)"
plot for [s in series] dir."/".s.".dat" using 1:3 with linespoints \
     dt dashes(s) lc rgb colour(s) pt 7 ps 0.6 title s noenhanced
