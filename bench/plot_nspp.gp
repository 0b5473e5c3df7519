# plot_nspp.gp -- time per point against n, one panel per distribution, our
# three algorithms and CGAL (called by bench/run).
#
# Variables given with -e: dir (one subdirectory per distribution holding
# <key>.dat files, columns n, median ms, ns per point), dists (space-
# separated distributions, one panel each), out (PNG file), title.
#
# Flat is linear; the rise at small n is the fixed cost of a call; at
# large n, the memory hierarchy. Both axes log scale, so that one slow
# series does not flatten the others.

set terminal pngcairo size 1500,1100 font ",9" noenhanced
set output out
set datafile separator whitespace
set grid xtics ytics lc rgb "#dddddd"
set logscale xy 10
set format x "%.0e"
set format y "%g"
set key top left font ",8"
label(k) = k eq "bowyer-watson" ? "Bowyer-Watson" : k eq "flip" ? "Lawson flip" : \
           k eq "fortune" ? "Fortune" : "CGAL"
colour(k) = k eq "bowyer-watson" ? "#1f77b4" : k eq "flip" ? "#2ca02c" : \
            k eq "fortune" ? "#d62728" : "#000000"
dash(k) = k eq "cgal" ? 2 : 1
count = words(dists)
cols = count < 3 ? count : 3
rows = (count + cols - 1) / cols
set multiplot layout rows, cols title "Time per point (ns per input point, median; log scale) -- ".title
keys = "bowyer-watson flip fortune cgal"
do for [i = 1:count] {
    d = word(dists, i)
    set title d
    set xlabel "points (n)"
    set ylabel "ns per point"
    plot for [k in keys] dir."/".d."/".k.".dat" using 1:3 with linespoints \
         dt dash(k) lc rgb colour(k) pt 7 ps 0.5 title label(k)
}
unset multiplot
