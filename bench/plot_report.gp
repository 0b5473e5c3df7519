# plot_report.gp -- the course report's experiment beside ours: time against
# N for the three algorithms on the report's three distributions, the
# report's Python figures dashed, ours solid (called by bench/run).
#
# Variables given with -e: dir (files report_<dist>_<algo>.dat and
# ours_<dist>_<algo>.dat, columns N, ms), out (PNG file), title.
# Panels: the report's distribution names, with ours in brackets.

set terminal pngcairo size 1500,520 font ",9" noenhanced
set output out
set datafile separator whitespace
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set logscale xy 10
set format y "%g"
set key top left font ",8"
set xlabel "points (N)"
set ylabel "milliseconds (log scale)"
algos = "bowyer-watson flip fortune"
label(a) = a eq "bowyer-watson" ? "Bowyer-Watson" : a eq "flip" ? "Lawson flip" : "Fortune"
colour(a) = a eq "bowyer-watson" ? "#1f77b4" : a eq "flip" ? "#2ca02c" : "#d62728"
set multiplot layout 1, 3 title "The course report's experiment (Python, dashed) and ours (C, solid) -- ".title
panels = "random:pixels gaussian:gaussian uniform:uniform"
do for [i = 1:3] {
    p = word(panels, i)
    rd = p[1:strstrt(p, ":") - 1]
    od = p[strstrt(p, ":") + 1:]
    set title "report: ".rd."   (ours: ".od.")"
    plot for [a in algos] dir."/report_".rd."_".a.".dat" using 1:2 with linespoints \
             dt 2 lc rgb colour(a) pt 6 ps 0.5 title label(a)." (report)", \
         for [a in algos] dir."/ours_".od."_".a.".dat" using 1:2 with linespoints \
             dt 1 lw 2 lc rgb colour(a) pt 7 ps 0.5 title label(a)." (ours)"
}
unset multiplot
