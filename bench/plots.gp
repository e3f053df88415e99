# PNG plots of a bench/run.sh output folder:  gnuplot -e "out='bench-out'" bench/plots.gp
# Reads the CSV files and fits.gp (exponents fitted by bench/summary.sh).
if (!exists("out")) out = "bench-out"
set datafile separator ","
set terminal pngcairo size 900,600 noenhanced font ",10"
set grid
set key top left
if (strlen(system("test -s ".out."/fits.gp && echo y")) > 0) load out."/fits.gp"
nan = NaN
is(c, s) = strcol(c) eq s
ri(r) = r == 1 ? 0 : (r == 4 ? 1 : 2)
# The papers' times: paper 001 Table 1 (mono-scale), paper 000 section 6.
$paper << EOD
0.24,39.5
1.24,46800
EOD
has(f) = strlen(system("test -s ".out."/".f." && echo y")) > 0  # a case not run: no plot

if (has("throughput.csv")) {
# 1. Matching throughput: candidates per second, medians with min..max bars.
set output out."/throughput.png"
set title "Matching throughput (median, min..max): scalar vs OpenCL vs host threads"
set ylabel "candidates (sample x rotation) per second"
set logscale y
set xrange [-0.5:8.5]
set xtics ("W2 R1" 0, "W2 R4" 1, "W2 R8" 2, "W3 R1" 3, "W3 R4" 4, "W3 R8" 5, "W4 R1" 6, "W4 R4" 7, "W4 R8" 8)
x1(w, r, k) = (w - 2) * 3 + ri(r) + k
plot out."/throughput.csv" every ::1 using (x1($4, $5, -0.25)):(is(3, "scalar") && $6 == 0 ? $10 : nan):11:12 with yerrorbars lc rgb "#1f77b4" pt 7 title "scalar, exhaustive", \
     "" every ::1 using (x1($4, $5, -0.15)):(is(3, "opencl") && $6 == 0 ? $10 : nan):11:12 with yerrorbars lc rgb "#d62728" pt 7 title "OpenCL, exhaustive", \
     "" every ::1 using (x1($4, $5, -0.05)):(is(3, "host") && $6 == 0 ? $10 : nan):11:12 with yerrorbars lc rgb "#2ca02c" pt 7 title "host threads, exhaustive", \
     "" every ::1 using (x1($4, $5, 0.05)):(is(3, "scalar") && $6 == 1 ? $10 : nan):11:12 with yerrorbars lc rgb "#1f77b4" pt 5 title "scalar, pruned", \
     "" every ::1 using (x1($4, $5, 0.15)):(is(3, "opencl") && $6 == 1 ? $10 : nan):11:12 with yerrorbars lc rgb "#d62728" pt 5 title "OpenCL, pruned", \
     "" every ::1 using (x1($4, $5, 0.25)):(is(3, "host") && $6 == 1 ? $10 : nan):11:12 with yerrorbars lc rgb "#2ca02c" pt 5 title "host threads, pruned"
unset xrange
set xtics autofreq
}
if (has("papers.csv")) {
# 2. The papers' sizes: whole completion times against the papers'.
set output out."/papers.png"
set title "Whole completions at the papers' sizes (median, min..max) and the papers' times"
set ylabel "seconds"
set xrange [-0.5:1.5]
set xtics ("paper 001 cylinder (W2 R4)" 0, "paper 000 tree bark (W3 R4)" 1)
set style fill solid 0.6
set boxwidth 0.15
set yrange [0.1:*]
set format y "%g"
cx(s) = s eq "paper001-cylinder" ? 0 : 1  # --quick: the eighth-size bark sits in the bark's place
plot out."/papers.csv" every ::1 using (cx(strcol(1)) - 0.24):(is(15, "completion") && is(5, "scalar") ? $18 : nan) with boxes lc rgb "#1f77b4" title "scalar", \
     "" every ::1 using (cx(strcol(1)) - 0.24):(is(15, "completion") && is(5, "scalar") ? $18 : nan):19:20 with yerrorbars lc rgb "black" pt 0 notitle, \
     "" every ::1 using (cx(strcol(1)) - 0.08):(is(15, "completion") && is(5, "opencl") ? $18 : nan) with boxes lc rgb "#d62728" title "OpenCL", \
     "" every ::1 using (cx(strcol(1)) - 0.08):(is(15, "completion") && is(5, "opencl") ? $18 : nan):19:20 with yerrorbars lc rgb "black" pt 0 notitle, \
     "" every ::1 using (cx(strcol(1)) + 0.08):(is(15, "completion") && is(5, "host") ? $18 : nan) with boxes lc rgb "#2ca02c" title "host threads", \
     "" every ::1 using (cx(strcol(1)) + 0.08):(is(15, "completion") && is(5, "host") ? $18 : nan):19:20 with yerrorbars lc rgb "black" pt 0 notitle, \
     $paper using 1:2 with boxes lc rgb "#7f7f7f" title "paper (Pentium 4: 1.8 GHz for 001, 2.6 GHz for 000)"
unset xrange
set xtics autofreq
unset boxwidth
set style fill empty
set yrange [*:*]
}
if (has("scaling.csv")) {
# 3a. Scaling of time: stages and matching time per target, log-log.
set output out."/scaling_time.png"
set title "Scaling (cylinder-bark, W3 R4, pruned): stage times and matching time per target"
set xlabel "surface vertices (samples + targets)"
set ylabel "seconds (median)"
set logscale xy
set format x "%g"
set format y "%g"
set key outside right top
set terminal pngcairo size 1200,600 noenhanced font ",10"
ttl(name, lbl) = exists(name."_b") ? sprintf("%s, exponent %.2f", lbl, value(name."_b")) : lbl
line(name, x) = exists(name."_b") ? exp(value(name."_a") + value(name."_b") * log(x)) : nan
plot out."/scaling.csv" every ::1 using 10:(is(15, "per_target") && is(5, "scalar") ? $18 : nan) with points lc rgb "#1f77b4" pt 7 title "matching per target, scalar", \
     "" every ::1 using 10:(is(15, "per_target") && is(5, "opencl") ? $18 : nan) with points lc rgb "#d62728" pt 7 title "matching per target, OpenCL", \
     "" every ::1 using 10:(is(15, "smooth") && is(5, "scalar") ? $18 : nan) with points lc rgb "#2ca02c" pt 5 title ttl("smooth_scalar", "smooth completion (fit, targets, oversample, Delaunay)"), \
     "" every ::1 using 10:(is(15, "match_data") && is(5, "scalar") ? $18 : nan) with points lc rgb "#9467bd" pt 5 title ttl("md_scalar", "match data (float copy, grid)"), \
     "" every ::1 using 10:(is(15, "matcher_create") && is(5, "opencl") ? $18 : nan) with points lc rgb "#8c564b" pt 5 title "OpenCL matcher (kernel build, upload)", \
     "" every ::1 using 10:(is(15, "grow_setup") && is(5, "scalar") ? $18 : nan) with points lc rgb "#7f7f7f" pt 5 title "growth set-up (adjacency)", \
     out."/scaling_full.csv" every ::1 using 10:(is(15, "grow") && is(5, "scalar") ? $18 : nan) with points lc rgb "#1f77b4" pt 9 dt 2 title ttl("grow_scalar", "whole growth, scalar"), \
     line("grow_scalar", x) lc rgb "#1f77b4" dt 2 notitle, \
     "" every ::1 using 10:(is(15, "grow") && is(5, "opencl") ? $18 : nan) with points lc rgb "#d62728" pt 9 dt 2 title ttl("grow_opencl", "whole growth, OpenCL"), \
     line("grow_opencl", x) lc rgb "#d62728" dt 2 notitle

# 3d. The two searches: whole completions against the surface's size.
if (has("scaling_coherent.csv")) {
set output out."/scaling_search.png"
set title "Exhaustive against k-coherence search (cylinder-bark, W3 R4): whole completions"
full = has("scaling_full.csv") ? out."/scaling_full.csv" : out."/scaling_coherent.csv"
plot out."/scaling_coherent.csv" every ::1 using 10:(is(15, "completion") ? $18 : nan) with points lc rgb "#2ca02c" pt 7 title ttl("coherent", "coherent search, host backend: completion"), \
     line("coherent", x) lc rgb "#2ca02c" notitle, \
     full every ::1 using 10:(is(15, "grow") && is(5, "scalar") ? $18 : nan) with points lc rgb "#1f77b4" pt 9 title ttl("grow_scalar", "exhaustive, scalar: growth"), \
     line("grow_scalar", x) lc rgb "#1f77b4" dt 2 notitle, \
     full every ::1 using 10:(is(15, "grow") && is(5, "opencl") ? $18 : nan) with points lc rgb "#d62728" pt 9 title ttl("grow_opencl", "exhaustive, OpenCL: growth"), \
     line("grow_opencl", x) lc rgb "#d62728" dt 2 notitle, \
     600 with lines lc rgb "black" dt 3 title "10 minutes"
}

# 3b. Scaling of peak memory.
set output out."/scaling_memory.png"
set title "Peak resident memory of the set-up and matching (one backend per process)"
set ylabel "MiB (getrusage ru_maxrss)"
plot out."/scaling.csv" every ::1 using 10:(is(15, "smooth") && is(5, "scalar") ? $21 / 1024 : nan) with points lc rgb "#1f77b4" pt 7 title ttl("mem_scalar", "scalar (fit over the upper half)"), \
     line("mem_scalar", x) / 1024 lc rgb "#1f77b4" notitle, \
     "" every ::1 using 10:(is(15, "smooth") && is(5, "opencl") ? $21 / 1024 : nan) with points lc rgb "#d62728" pt 7 title ttl("mem_opencl", "OpenCL on PoCL (fit over the upper half)"), \
     line("mem_opencl", x) / 1024 lc rgb "#d62728" notitle, \
     2048 with lines lc rgb "black" dt 2 title "target: 2 GB at a million vertices"

# 3c. Matching time per target against samples, with the fitted line.
set output out."/scaling_per_target.png"
set title "Matching time per target (first boundary) against the samples"
set xlabel "samples"
set ylabel "seconds per target (median)"
plot out."/scaling.csv" every ::1 using 8:(is(15, "per_target") && is(5, "scalar") ? $18 : nan) with points lc rgb "#1f77b4" pt 7 title ttl("pt_scalar", "scalar"), \
     line("pt_scalar", x) lc rgb "#1f77b4" notitle, \
     "" every ::1 using 8:(is(15, "per_target") && is(5, "opencl") ? $18 : nan) with points lc rgb "#d62728" pt 7 title ttl("pt_opencl", "OpenCL"), \
     line("pt_opencl", x) lc rgb "#d62728" notitle
set terminal pngcairo size 900,600 noenhanced font ",10"
set key top left
unset format
unset logscale
unset xlabel
}
if (has("prune.csv")) {
# 4. Pruned against exhaustive.
set output out."/prune.png"
set title "Pruned against exhaustive on the same completion (paper 001 cylinder), growth time"
set ylabel "seconds (median, min..max)"
set xrange [-0.5:1.5]
set yrange [0:*]
set xtics ("exhaustive (--no-prune)" 0, "pruned (default)" 1)
set style fill solid 0.6
set boxwidth 0.3
plot out."/prune.csv" every ::1 using ($13 - 0.17):(is(15, "grow") && is(5, "scalar") ? $18 : nan) with boxes lc rgb "#1f77b4" title "scalar", \
     "" every ::1 using ($13 - 0.17):(is(15, "grow") && is(5, "scalar") ? $18 : nan):19:20 with yerrorbars lc rgb "black" pt 0 notitle, \
     "" every ::1 using ($13 + 0.17):(is(15, "grow") && is(5, "opencl") ? $18 : nan) with boxes lc rgb "#d62728" title "OpenCL (PoCL)", \
     "" every ::1 using ($13 + 0.17):(is(15, "grow") && is(5, "opencl") ? $18 : nan):19:20 with yerrorbars lc rgb "black" pt 0 notitle
}
