set terminal pngcairo size 900,600
set output '/work/main/out/bench/mpm_growth_bench.png'
set logscale xy
set xlabel 'wall time per R curve [s] (one thread)'
set ylabel 'largest |R_{energy} error| vs reduced model (0.25 mm) [%]'
set key outside right
set grid
set title 'MPM crack growth, CT, linear softening: 5 / 2.5 / 1.25 mm cells'
titles = 'full 0.45 MPa|full 1 MPa|half 0.45 MPa|half 1 MPa'
plot for [i=0:3] '/work/main/out/bench/mpm_growth_bench_plot.dat' index i using 1:2 with linespoints pointsize 1.5 title system(sprintf("echo '%s' | cut -d'|' -f%d", titles, i+1)), '' using 1:2:3 with labels offset 1,0.7 notitle
