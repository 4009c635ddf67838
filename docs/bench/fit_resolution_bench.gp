set terminal pngcairo size 900,600 noenhanced
set output 'docs/bench/fit_resolution_bench.png'
set logscale xy
set xlabel 'wall time per fit with profiles [s] (2-core machine)'
set ylabel 'largest relative error against the truth (wrong verdict: 1)'
set key outside right
set grid
set title 'Default R-curve fit: fixed element sizes (labels, mm) and --resolution auto'
titles = 'recovery_1MPa truncated_0.45MPa flat_pb mdf_sample '
plot for [i=0:3] 'docs/bench/fit_resolution_bench_plot.dat' index 2*i using 1:2 with linespoints linetype i+1 pointtype 7 title word(titles, i+1), \
     for [i=0:3] 'docs/bench/fit_resolution_bench_plot.dat' index 2*i using 1:2:3 with labels offset 1.5,0.6 notitle, \
     for [i=0:3] 'docs/bench/fit_resolution_bench_plot.dat' index 2*i+1 using 1:2 with points linetype i+1 pointtype 5 pointsize 3 title word(titles, i+1).' auto'
