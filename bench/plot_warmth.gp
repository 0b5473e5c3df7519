# plot_warmth.gp -- the same computation cold and warm: time per point
# against n (called by bench/run).
#
# Variables given with -e: dir (files <algo>_<mode>.dat, columns n, ns per
# point; mode cold, warm-same or warm-varied), out (PNG file), title.
#
# cold: each run in a fresh process on new points; warm-same: one process
# repeating one input (what the size table's median is); warm-varied: one
# process, a new input each run.

set terminal pngcairo size 1000,650 font ",10" noenhanced
set output out
set datafile separator whitespace
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set logscale x 10
set logscale y 2
set format y "%g"
set key outside right top
set xlabel "points (n)"
set ylabel "ns per point, median (log scale)"
set title "Cold and warm runs of the same computation (uniform points)\n".title
algos = "bowyer-watson flip fortune"
modes = "cold warm-varied warm-same"
label(a) = a eq "bowyer-watson" ? "Bowyer-Watson" : a eq "flip" ? "Lawson flip" : "Fortune"
colour(a) = a eq "bowyer-watson" ? "#1f77b4" : a eq "flip" ? "#2ca02c" : "#d62728"
dash(m) = m eq "cold" ? 1 : m eq "warm-varied" ? 2 : 3
plot for [a in algos] for [m in modes] dir."/".a."_".m.".dat" using 1:2 \
     with linespoints dt dash(m) lc rgb colour(a) pt 7 ps 0.5 title label(a).", ".m
