#!/usr/bin/env bash
# The figures of a bench/run.sh output folder in a few lines: medians,
# OpenCL / scalar ratios (of medians, same process), the papers' sizes next
# to the papers' times, fitted scaling exponents and peak memory.
#   bench/summary.sh OUT
set -euo pipefail
OUT=${1:?usage: bench/summary.sh OUT}

# Least-squares fit of log(y) = a + b log(x) over lines "x y": prints b
# (the exponent), and appends "NAME_b = ...; NAME_a = ..." to fits.gp for
# the plots.
fits=$OUT/fits.gp
: > "$fits"
fit() {
  awk -v name="$1" -v fits="$fits" '{ lx = log($1); ly = log($2); n++; sx += lx; sy += ly; sxx += lx * lx; sxy += lx * ly }
    END { if (n < 2 || n * sxx == sx * sx) { print "n/a"; exit }
          b = (n * sxy - sx * sy) / (n * sxx - sx * sx); a = (sy - b * sx) / n
          printf "%.2f", b; printf "%s_b = %.6g; %s_a = %.6g\n", name, b, name, a >> fits }'
}

if [[ -f $OUT/throughput.csv ]]; then
  echo "1. Matching throughput (candidates/s, medians; ratios to the scalar reference, same process)"
  awk -F, 'NR == 1 { next }
    { k = $4 "," $5 "," $6; med[k "," $3] = $10; reps = $7; if (!(k in seen)) { seen[k]; order[++n] = k } }
    END { printf "   %-3s %-3s %-10s %12s %12s %12s %8s %8s\n", "W", "R", "", "scalar", "opencl", "host", "opencl/s", "host/s"
          for (i = 1; i <= n; ++i) { split(order[i], a, ",");
            s = med[order[i] ",scalar"]; o = med[order[i] ",opencl"]; h = med[order[i] ",host"]
            printf "   %-3s %-3s %-10s %12.4g %12.4g %12.4g %8.2f %8.2f\n", a[1], a[2], a[3] ? "pruned" : "exhaustive", s, o, h, (s > 0 ? o / s : 0), (s > 0 ? h / s : 0) }
          printf "   (%s repetitions per cell)\n", reps }' "$OUT/throughput.csv"
fi

if [[ -f $OUT/papers.csv ]]; then
  echo "2. The papers' sizes (whole completion: smooth + match data + matcher + growth; seconds)"
  awk -F, 'NR == 1 { next } $15 == "completion" {
      k = $1; b = $5; med[k, b] = $18; lo[k, b] = $19; hi[k, b] = $20; reps[k, b] = $17
      sam[k] = $8; tar[k] = $9; w[k] = $11; r[k] = $12; same[k] = $25
      if (!(k in seen)) { seen[k]; order[++n] = k } }
    END { paper["paper001-cylinder"] = 39.5; pnote["paper001-cylinder"] = "paper 001 Table 1, mono-scale, Pentium 4 1.8 GHz"
          paper["paper000-bark"] = 46800; pnote["paper000-bark"] = "paper 000: about 13 h, Pentium 4 2.6 GHz"
          for (i = 1; i <= n; ++i) { k = order[i]
            printf "   %s: %s samples, %s targets, W %s, R %s; outputs identical across backends: %s\n", k, sam[k], tar[k], w[k], r[k], same[k]
            for (j = 1; j <= 3; ++j) { b = j == 1 ? "scalar" : j == 2 ? "opencl" : "host"
              if ((k, b) in med) printf "     %-7s median %9.2f s (min %.2f, max %.2f, %s reps)%s\n", b, med[k, b], lo[k, b], hi[k, b], reps[k, b],
                 (k in paper) ? sprintf("; %.0fx faster than the paper'"'"'s %.1f s", paper[k] / med[k, b], paper[k]) : "" }
            if ((k, "scalar") in med && (k, "opencl") in med) printf "     scalar / OpenCL: %.2f\n", med[k, "scalar"] / med[k, "opencl"]
            if ((k, "scalar") in med && (k, "host") in med) printf "     scalar / host: %.2f\n", med[k, "scalar"] / med[k, "host"]
            if (k in paper) printf "     (%s)\n", pnote[k] } }' "$OUT/papers.csv"
fi

if [[ -f $OUT/prune.csv ]]; then
  echo "4. Pruned against exhaustive (growth medians, seconds)"
  awk -F, 'NR == 1 { next } $15 == "grow" { g[$5, $13] = $18; same[$13] = $25 }
    END { for (j = 1; j <= 3; ++j) { b = j == 1 ? "scalar" : j == 2 ? "opencl" : "host"
            if ((b, 0) in g && (b, 1) in g)
              printf "   %-7s exhaustive %8.2f s, pruned %8.2f s: pruning %.2fx faster\n", b, g[b, 0], g[b, 1], g[b, 0] / g[b, 1] }
          for (p = 0; p <= 1; ++p) if (("scalar", p) in g && ("opencl", p) in g)
            printf "   %s: scalar / OpenCL %.2f\n", p ? "pruned" : "exhaustive", g["scalar", p] / g["opencl", p]
          printf "   outputs identical across backends: exhaustive %s, pruned %s\n", same[0], same[1] }' "$OUT/prune.csv"
fi

if [[ -f $OUT/scaling.csv ]]; then
  echo "3. Scaling (cylinder-bark, W 3, R 4, pruned; x = surface vertices, samples + targets)"
  for b in scalar opencl; do
    pt=$(awk -F, -v b=$b '$5 == b && $15 == "per_target" { print $8, $18 }' "$OUT/scaling.csv" | fit pt_$b)
    sm=$(awk -F, -v b=$b '$5 == b && $15 == "smooth" { print $10, $18 }' "$OUT/scaling.csv" | fit smooth_$b)
    md=$(awk -F, -v b=$b '$5 == b && $15 == "match_data" { print $10, $18 }' "$OUT/scaling.csv" | fit md_$b)
    # Memory: the exponent over the upper half of the sizes, where fixed
    # costs (the OpenCL runtime, the binary) no longer dominate.
    mem=$(awk -F, -v b=$b '$5 == b && $15 == "smooth" { print $10, $21 }' "$OUT/scaling.csv" |
          sort -n | awk '{ l[NR] = $0 } END { for (i = int(NR / 2) + 1; i <= NR; ++i) print l[i] }' | fit mem_$b)
    echo "   $b: exponents: matching time per target vs samples $pt; smooth $sm; match data $md; peak memory $mem (upper half of the sizes)"
    # Linear in the vertices: peak = fixed + per-vertex x n, least squares.
    awk -F, -v b=$b '$5 == b && $15 == "smooth" { x = $10; y = $21 / 1024; n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
      END { if (n < 2) exit; k = (n * sxy - sx * sy) / (n * sxx - sx * sx); c = (sy - k * sx) / n
            printf "   %s: peak memory, linear fit: %.0f MiB + %.2f KiB per vertex: %.0f MiB at 1 000 000 vertices\n", b, c, k * 1024, c + k * 1e6 }' "$OUT/scaling.csv"
    awk -v b=$b -F'[=;]' '$1 ~ "^mem_" b "_b" { printf "   %s: peak memory at 1 000 000 vertices by that fit: %.0f MiB\n", b, exp($4 + $2 * log(1e6)) / 1024 }' "$fits"
  done
  awk -F, 'NR == 1 { next } $15 == "smooth" { k = $5 " " $10; if ($10 > big[$5]) { big[$5] = $10; rss[$5] = $21; sam[$5] = $8; tar[$5] = $9 } }
           $15 == "per_target" { pt[$5 " " $10] = $18 }
    END { for (b in big) printf "   %s at %d vertices (%d samples, %d targets): peak resident memory %.0f MiB; matching %.3g s per target\n",
            b, big[b], sam[b], tar[b], rss[b] / 1024, pt[b " " big[b]] }' "$OUT/scaling.csv"
  if [[ -f $OUT/scaling_full.csv ]]; then
    # Calibrate the extrapolation: growth time over (per-target matching time
    # at the first boundary x targets), where both were measured.
    awk -F, 'FNR == 1 { f++; next }
      f == 1 && $15 == "per_target" { pt[$5 " " $7] = $18 }
      f == 2 && $15 == "grow" { g[$5 " " $7] = $18; tg[$5 " " $7] = $9; sc[$5 " " $7] = $22 }
      f == 1 && $15 == "smooth" { big[$5] = $10 > big[$5] ? $10 : big[$5] }
      f == 1 { if ($15 == "per_target" && $10 >= bigv[$5]) { bigv[$5] = $10; bigpt[$5] = $18; bigt[$5] = $9 } }
      END { for (k in g) if (k in pt) { split(k, a, " "); c[a[1]] += g[k] / (pt[k] * tg[k]); nc[a[1]]++
              printf "   %s, %s-vertex truth: growth %.3g s measured; %.3g s x %d targets = %.3g s from the first boundary (factor %.2f; %s scorings)\n",
                a[1], a[2], g[k], pt[k], tg[k], pt[k] * tg[k], g[k] / (pt[k] * tg[k]), sc[k] }
            for (b in c) printf "   %s: growth at %d vertices extrapolated: %.3g s x %d targets x %.2f = %.3g s (%.1f h)\n",
              b, bigv[b], bigpt[b], bigt[b], c[b] / nc[b], bigpt[b] * bigt[b] * c[b] / nc[b], bigpt[b] * bigt[b] * c[b] / nc[b] / 3600 }' \
      "$OUT/scaling.csv" "$OUT/scaling_full.csv"
    for b in scalar opencl; do
      gr=$(awk -F, -v b=$b '$5 == b && $15 == "grow" { print $10, $18 }' "$OUT/scaling_full.csv" | fit grow_$b)
      echo "   $b: whole growth time vs surface vertices: exponent $gr"
    done
  fi
fi

if [[ -f $OUT/scaling_coherent.csv ]]; then
  echo "3b. Scaling of the k-coherence search (cylinder-bark, W 3, R 4, host backend; whole completions)"
  awk -F, 'NR > 1 && $15 == "completion" { printf "   %d vertices (%d samples, %d targets): completion %.3g s, growth %s, peak memory %.0f MiB\n", $10, $8, $9, $18, g[$10], $21 / 1024 }
           NR > 1 && $15 == "grow" { g[$10] = sprintf("%.3g s", $18) }' "$OUT/scaling_coherent.csv"
  ct=$(awk -F, 'NR > 1 && $15 == "completion" { print $10, $18 }' "$OUT/scaling_coherent.csv" | fit coherent)
  cm=$(awk -F, 'NR > 1 && $15 == "completion" { print $10, $21 }' "$OUT/scaling_coherent.csv" | fit coherent_mem)
  echo "   exponents vs surface vertices: completion time $ct, peak memory $cm"
  awk -F, 'NR > 1 && $15 == "completion" && $18 <= 600 && $10 > v { v = $10 } END { if (v) printf "   largest surface completed within 10 minutes: %d vertices (measured)\n", v }' \
    "$OUT/scaling_coherent.csv"
  # The exhaustive search's, from its whole-growth fit (scaling_full.csv).
  if [[ -f $OUT/scaling_full.csv ]]; then
    for b in scalar opencl; do
      awk -F, -v b=$b '$5 == b && $15 == "completion" { x = log($10); y = log($18); n++; sx += x; sy += y; sxx += x * x; sxy += x * y }
        END { if (n < 2) exit; k = (n * sxy - sx * sy) / (n * sxx - sx * sx); c = (sy - k * sx) / n
              printf "   exhaustive, %s: completion time ~ vertices^%.2f; 10 minutes at about %.0f vertices (extrapolated from %d sizes)\n", b, k, exp((log(600) - c) / k), n }' \
        "$OUT/scaling_full.csv"
    done
  fi
fi

if [[ -f $OUT/hierarchy.csv ]]; then
  echo "5. mono-scale against hierarchical completion (same capture and backend)"
  awk -F, 'NR == 1 { next }
    $12 == 1 { mono[$1] = $14; mmsi[$1] = $18; order[++n] = $1; sz[$1] = $8 " samples, " $9 " targets" }
    $12 > 1 { hier[$1] = $14; hmsi[$1] = $18; lv[$1] = $12 }
    END { for (i = 1; i <= n; ++i) { c = order[i]
            printf "   %s (%s): mono %.3g s, %d levels %.3g s: %.2fx; MSI difference %.2f %% / %.2f %%\n",
              c, sz[c], mono[c], lv[c], hier[c], mono[c] / hier[c], mmsi[c], hmsi[c] } }' "$OUT/hierarchy.csv"
fi
