set terminal pngcairo size 900,600 font ',11'
set logscale xy
set grid
set key top right
set output 'reduced_bench.png'
set title 'Reduced model (CT, linear law): time per R curve against error, one core'
set xlabel 'time per R curve [ms] (median)'
set ylabel 'largest error at a = 46, 54, 62, 70 mm [%]'
plot 'reduced_bench.dat' using 2:3 with linespoints pt 7 lw 2 title 'R - J_{tip,c}', \
     '' using 2:4 with linespoints pt 5 lw 2 title 'R', \
     '' using 2:3:(sprintf('h = %s mm', stringcolumn(1))) with labels offset 1,1 left notitle
