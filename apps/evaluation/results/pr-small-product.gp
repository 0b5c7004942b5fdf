# gnuplot script written by cellguard-eval: precision-recall curves of pr-small-product.csv
set terminal pngcairo size 720,540 font 'sans,11'
set output 'apps/evaluation/results/pr-small-product.png'
set datafile separator ','
set title 'Precision-recall, small object (a 2x4 on a box), the product''s sensor model'
set xlabel 'recall'
set ylabel 'precision'
set xrange [0:1]
set yrange [0:1.02]
set grid
set key bottom left
f(m) = 'apps/evaluation/results/pr-small-product.csv'
plot f(0) skip 1 using (stringcolumn(1) eq 'thresholded' ? $7 : 1/0):(stringcolumn(1) eq 'thresholded' ? $6 : 1/0) with linespoints lw 2 pt 7 ps 0.5 lc rgb '#1f77b4' title 'thresholded', \
     f(0) skip 1 using (stringcolumn(1) eq 'probabilistic' ? $7 : 1/0):(stringcolumn(1) eq 'probabilistic' ? $6 : 1/0) with linespoints lw 2 pt 5 ps 0.5 lc rgb '#d62728' title 'probabilistic', \
     f(0) skip 1 using (stringcolumn(1) eq 'thresholded-baseline' ? $7 : 1/0):(stringcolumn(1) eq 'thresholded-baseline' ? $6 : 1/0) with linespoints lw 1.5 dt 2 pt 6 ps 0.5 lc rgb '#1f77b4' title 'thresholded-baseline', \
     f(0) skip 1 using (stringcolumn(1) eq 'probabilistic-baseline' ? $7 : 1/0):(stringcolumn(1) eq 'probabilistic-baseline' ? $6 : 1/0) with linespoints lw 1.5 dt 2 pt 4 ps 0.5 lc rgb '#d62728' title 'probabilistic-baseline'
