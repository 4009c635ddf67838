set terminal pngcairo size 900,600 font ',11'
set logscale xy
set grid
set key top right
set output 'dic_bench.png'
set title 'DIC (IC-GN), Sample 14 L1: time per point against RMS error of u'
set xlabel 'wall time per point [us]'
set ylabel 'RMS(u - exact) [px]'
plot for [s=1:2] for [t=1:2] 'dic_bench.dat' using 4:(($2 == s && $3 == t) ? $5 : 1/0) \
       with linespoints pt (s == 1 ? 7 : 5) lw 2 dt t \
       title sprintf('%s order, %d thread(s)', s == 1 ? 'first' : 'second', t), \
     '' using 4:(($3 == 1) ? $5 : 1/0):(sprintf('%sx%s', stringcolumn(1), stringcolumn(1))) \
       with labels offset 1,0.8 left notitle
