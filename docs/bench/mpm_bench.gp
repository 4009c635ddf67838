set terminal pngcairo size 900,600 font ',11'
set logscale xy
set grid
set key top right
set output 'mpm_bench.png'
set title 'MPM, CT a/W = 0.3, stationary crack: wall time against error'
set xlabel 'wall time per run [s]'
set ylabel '|error| [%]'
plot for [t=1:2] 'mpm_bench.dat' using 3:($2 == t ? abs($5) : 1/0) with linespoints pt 7 lw 2 \
       title sprintf('J vs E399, %d thread(s)', t), \
     for [t=1:2] '' using 3:($2 == t ? abs($6) : 1/0) with linespoints pt 5 lw 2 dt 2 \
       title sprintf('compliance vs Saxena-Hudak, %d thread(s)', t), \
     '' using 3:($2 == 1 ? abs($5) : 1/0):(sprintf('%s mm', stringcolumn(1))) \
       with labels offset 1,1 left notitle
