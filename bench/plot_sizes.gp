# plot_sizes.gp -- one distribution: time against n for our three
# algorithms and every peer on the same axes (called by bench/run).
#
# Variables given with -e: dir (one data file per series, <key>.dat, columns
# n, median ms, ns per point), keys (space-separated series present, in the
# order of the legend), dist (the distribution's name), out (PNG file),
# title (machine and commit).
#
# Log-log: a straight line of slope 1 is linear growth; n log n bends
# slightly upwards. Ours are solid, the peers dashed.

set terminal pngcairo size 1000,650 font ",10" noenhanced
set output out
set datafile separator whitespace
set key outside right top
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set logscale xy 10
set format x "%.0e"
set format y "%g"
set xlabel "points (n)"
set ylabel "milliseconds, median (log scale)"
set title "Points: ".dist." -- time to compute, ours and the peers\n".title

label(k) = k eq "bowyer-watson" ? "Bowyer-Watson (ours)" : \
           k eq "flip" ? "Lawson flip (ours)" : \
           k eq "fortune" ? "Fortune (ours)" : \
           k eq "cgal" ? "CGAL Delaunay_triangulation_2" : \
           k eq "boost" ? "Boost.Polygon Voronoi" : \
           k eq "qhull" ? "qhull (Delaunay)" : \
           k eq "delaunator" ? "delaunator (JS)" : \
           k eq "d3-delaunay" ? "d3-delaunay Voronoi (JS)" : k
colour(k) = k eq "bowyer-watson" ? "#1f77b4" : k eq "flip" ? "#2ca02c" : \
            k eq "fortune" ? "#d62728" : k eq "cgal" ? "#000000" : \
            k eq "boost" ? "#9467bd" : k eq "qhull" ? "#8c564b" : \
            k eq "delaunator" ? "#e377c2" : "#7f7f7f"
ours(k) = k eq "bowyer-watson" || k eq "flip" || k eq "fortune"
dash(k) = ours(k) ? 1 : 2
width(k) = ours(k) ? 2 : 1.5

plot for [k in keys] dir."/".k.".dat" using 1:2 with linespoints \
     dt dash(k) lw width(k) lc rgb colour(k) \
     pt 7 ps 0.6 title label(k)
