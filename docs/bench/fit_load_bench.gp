set terminal pngcairo size 760,480 enhanced font 'Sans,11'
set output 'fit_load_bench.png'
set datafile separator ','
set key bottom right
set grid
set title 'Load-displacement fit, truncated MDF test: time against sigma_c error'
set xlabel 'CPU time per fit [s]'
set ylabel 'sigma_c error over the draws [%]'
plot 'fit_load_bench_summary.csv' skip 1 u 10:3:(sprintf('%g mm', $1)) w labels offset 0,1 notitle, '' skip 1 u 10:3 w lp pt 7 t 'largest |error| (noisy draws)', '' skip 1 u 10:5 w lp pt 5 t 'SD (noisy draws)', '' skip 1 u 10:(abs($11)) w lp pt 9 t '|error| without noise'
