set terminal pngcairo size 900,600
set output 'fit_bench.png'
set logscale xy
set xlabel 'CPU time per fit [s] (reduced model, no profile)'
set ylabel 'largest relative parameter error'
set key outside right
set grid
set title 'Optimizers on the three issue-7 cases (wrong verdicts not shown)'
plot for [i=0:5] 'fit_bench_plot.dat' index i using 1:2 with points pointsize 2 pointtype (i+4) title word('ceres-lm bobyqa neldermead cobyla direct crs2', i+1)
