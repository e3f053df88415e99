#!/usr/bin/env python3
"""Image hole filling against its own references and against OpenCV.

For each image of ../shared/data/images and each hole (a disc, a thin
scratch, a 20 % rectangle), cut where the truth is known, run
  relief image-fill with the scalar scorer, with OpenCL, and --exhaustive
  OpenCV's cv2.inpaint, Telea and Navier-Stokes (the diffusion baseline
  paper 004 compares with)
in one script, and print for each: wall time (median of REPEAT runs for
relief's pyramid, one run otherwise), RMS error over the hole against the
removed pixels, and a texture statistic: the mean local standard
deviation (5 x 5) over the hole, divided by the truth's (1: as textured as
the truth; a blur gives less). Writes OUT/image_fill.csv.
  bench/image_fill.py RELIEF IMAGES_DIR OUT [--repeat N] [--no-exhaustive]
"""
import csv
import os
import statistics
import subprocess
import sys
import time

import cv2
import numpy as np


def holes(w, h):
    """name -> mask (uint8, 255 = hole)."""
    out = {}
    m = np.zeros((h, w), np.uint8)
    cv2.circle(m, (w // 2, h // 2), min(w, h) // 16, 255, -1)
    out["disc"] = m
    m = np.zeros((h, w), np.uint8)
    cv2.line(m, (int(w * 0.2), int(h * 0.3)), (int(w * 0.8), int(h * 0.7)), 255, 5)
    out["scratch"] = m
    m = np.zeros((h, w), np.uint8)
    rw, rh = int(w * 0.2 ** 0.5), int(h * 0.2 ** 0.5)
    m[(h - rh) // 2:(h - rh) // 2 + rh, (w - rw) // 2:(w - rw) // 2 + rw] = 255
    out["rect20"] = m
    return out


def local_sd(img):
    f = img.astype(np.float64)
    if f.ndim == 3:
        f = f.mean(axis=2)
    mu = cv2.blur(f, (5, 5))
    mu2 = cv2.blur(f * f, (5, 5))
    return np.sqrt(np.maximum(mu2 - mu * mu, 0))


def measure(result, truth, mask):
    sel = mask > 0
    d = result.astype(np.float64) - truth.astype(np.float64)
    rms = float(np.sqrt(np.mean(d[sel] ** 2)))
    tex = float(local_sd(result)[sel].mean() / max(local_sd(truth)[sel].mean(), 1e-9))
    return rms, tex


def run_relief(relief, src, mask_path, out, extra, repeat):
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        r = subprocess.run([relief, "image-fill", src, "--mask", mask_path, "-o", out,
                            "--quiet"] + extra, capture_output=True, text=True)
        times.append(time.perf_counter() - t0)
        if r.returncode != 0:
            raise SystemExit("relief failed: %s" % r.stderr)
    return statistics.median(times)


def main():
    relief, images, out = sys.argv[1], sys.argv[2], sys.argv[3]
    repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 3
    exhaustive = "--no-exhaustive" not in sys.argv
    os.makedirs(out, exist_ok=True)
    rows = []
    names = ["brick.png", "grass.png", "gravel.png", "coffee.png", "chelsea.png",
             "astronaut.png", "rocket.jpg"]
    for name in names:
        path = os.path.join(images, name)
        truth = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        h, w = truth.shape[:2]
        stem = os.path.splitext(name)[0]
        for hole, m in holes(w, h).items():
            mask_path = os.path.join(out, "%s_%s_mask.png" % (stem, hole))
            cv2.imwrite(mask_path, m)
            res = {}
            for method, extra, n in (("relief scalar", ["--backend", "scalar"], repeat),
                                     ("relief opencl", ["--backend", "opencl"], repeat),
                                     ("relief exhaustive", ["--backend", "scalar",
                                                            "--exhaustive"], 1)):
                if method == "relief exhaustive" and (not exhaustive or hole == "rect20"):
                    continue
                o = os.path.join(out, "%s_%s_%s.png" % (stem, hole, method.split()[1]))
                t = run_relief(relief, path, mask_path, o, extra, n)
                res[method] = (t, cv2.imread(o, cv2.IMREAD_UNCHANGED))
            for method, flag in (("opencv telea", cv2.INPAINT_TELEA),
                                 ("opencv ns", cv2.INPAINT_NS)):
                t0 = time.perf_counter()
                r = cv2.inpaint(truth, m, 3, flag)
                res[method] = (time.perf_counter() - t0, r)
                cv2.imwrite(os.path.join(out, "%s_%s_%s.png" % (stem, hole,
                                                               method.split()[1])), r)
            same = np.array_equal(res["relief scalar"][1], res["relief opencl"][1])
            for method, (t, r) in res.items():
                rms, tex = measure(r, truth, m)
                rows.append(dict(image=name, hole=hole, pixels=int((m > 0).sum()),
                                 method=method, seconds="%.3f" % t, rms="%.2f" % rms,
                                 texture="%.3f" % tex, identical_backends=int(same)))
                print("%-14s %-8s %-18s %8.3f s  rms %7.2f  texture %.3f" %
                      (name, hole, method, t, rms, tex), flush=True)
    with open(os.path.join(out, "image_fill.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)


if __name__ == "__main__":
    main()
