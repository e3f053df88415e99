#!/usr/bin/python3
"""depth-fill's waves (--batch N) against Efros and Leung's one pixel at a
time (--batch 1): the quality on holes cut where the truth is known, and
the speed of every backend, side by side in one run.

    bench/depth_batch.py RELIEF TOOL DEPTH_DIR OUT [--batch N] [--seeds K]
                         [--backends scalar,host,opencl] [--reps R]
                         [--only quality|speed]

TOOL is bench/depth_bench_tool. The holes are bench/depth_fill.py's (a disc
of radius 24, a 5-pixel scratch, a rectangle) in office1.pcd and
motorcycle_disp.pfm, filled alone (--mask), for the variants plain and
decompose, with K seeds each (the draw is random: a wave changes which
windows tie, so single runs differ either way); every output is measured by
depth_bench_tool measure (RMS over the cut, the slope jump at the rim
against the truth's own, the roughness ratio). The means over the seeds,
and their spread, are printed for both batches. Then the whole office1
frame (its own missing pixels) is filled on each backend at both batches,
R repetitions alternating, medians and ratios to scalar at --batch 1, and
every backend's bytes at a batch compared with scalar's.
"""
import argparse
import json
import os
import statistics
import subprocess
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from png_row import write_png  # noqa: E402
from pfm import read_pfm, write_pfm  # noqa: E402


def holes(shape, cx, cy, rect):
    """depth_fill.py's holes, drawn with numpy: a disc of radius 24, a
    5-pixel scratch from (w/6, h/3) to (5w/6, 2h/3), a rectangle."""
    h, w = shape
    y, x = np.mgrid[0:h, 0:w].astype(np.float64)
    disc = (x - cx) ** 2 + (y - cy) ** 2 <= 24 * 24
    ax, ay, bx, by = w // 6, h // 3, w * 5 // 6, h * 2 // 3
    t = np.clip(((x - ax) * (bx - ax) + (y - ay) * (by - ay)) /
                float((bx - ax) ** 2 + (by - ay) ** 2), 0, 1)
    scratch = (x - ax - t * (bx - ax)) ** 2 + (y - ay - t * (by - ay)) ** 2 <= 2.5 ** 2
    rx, ry, rw, rh = rect
    box = np.zeros(shape, bool)
    box[ry:ry + rh, rx:rx + rw] = True
    return {"disc": disc, "scratch": scratch, "rect": box}


def run(cmd):
    r = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if r.returncode:
        sys.exit("depth_batch: %s: exit %d\n%s" % (" ".join(cmd), r.returncode, r.stderr))
    return r.stdout


def quality(a, batches):
    frames = {
        "office1": (os.path.join(a.depth, "office1.pcd"), 320, 150, (430, 300, 48, 36)),
        "motorcycle": (os.path.join(a.depth, "motorcycle_disp.pfm"), 420, 260,
                       (260, 320, 70, 50)),
    }
    table = {}
    for name, (src, cx, cy, rect) in frames.items():
        base = os.path.join(a.out, name)
        run([a.tool, "pfm", src, base + ".pfm"])
        truth = read_pfm(base + ".pfm")
        for hole, m in holes(truth.shape, cx, cy, rect).items():
            case = "%s_%s" % (base, hole)
            cut = m & np.isfinite(truth)
            mask = np.repeat((cut * 255).astype(np.uint8)[:, :, None], 3, axis=2)
            write_png(case + "_mask.png", mask)
            write_pfm(case + "_maskf.pfm", cut.astype(np.float32))
            write_pfm(case + "_in.pfm", np.where(cut, np.nan, truth).astype(np.float32))
            for variant in ("plain", "decompose"):
                for b in batches:
                    rows = []
                    for seed in range(1, a.seeds + 1):
                        o = "%s_%s_b%d_s%d.pfm" % (case, variant, b, seed)
                        run([a.relief, "depth-fill", case + "_in.pfm", "--mask",
                             case + "_mask.png", "-o", o, "--variant", variant, "--batch",
                             str(b), "--seed", str(seed), "--backend", "scalar", "--quiet"])
                        rows.append(json.loads(run([a.tool, "measure", o, base + ".pfm",
                                                    case + "_maskf.pfm"])))
                    table[(name, hole, variant, b)] = rows
    print("| frame | hole | variant | batch | RMS (mean, min..max over %d seeds) | "
          "slope jump (truth) | roughness |" % a.seeds)
    print("| --- | --- | --- | --- | --- | --- | --- |")
    for (name, hole, variant, b), rows in table.items():
        rms = [r["rms"] for r in rows]
        print("| %s | %s | %s | %d | %.4g (%.4g..%.4g) | %.2f (%.2f) | %.2f |" % (
            name, hole, variant, b, statistics.mean(rms), min(rms), max(rms),
            statistics.mean(r["slope_jump"] for r in rows), rows[0]["truth_slope_jump"],
            statistics.mean(r["roughness_ratio"] for r in rows)), flush=True)
    for b in batches[1:]:
        ratio = [statistics.mean(r["rms"] for r in table[k[:3] + (b,)]) /
                 statistics.mean(r["rms"] for r in table[k[:3] + (batches[0],)])
                 for k in table if k[3] == batches[0]]
        print("batch %d / batch %d, mean RMS ratio over the %d cases: %.3f (%.3f..%.3f)" % (
            b, batches[0], len(ratio), statistics.mean(ratio), min(ratio), max(ratio)))


def speed(a, batches):
    office = os.path.join(a.depth, "office1.pcd")
    backends = a.backends.split(",")
    times = {(be, b): [] for be in backends for b in batches}
    for _ in range(a.reps):
        for b in batches:
            for be in backends:
                o = os.path.join(a.out, "office1_full_b%d_%s.pcd" % (b, be))
                t = time.perf_counter()
                run([a.relief, "depth-fill", office, "-o", o, "--batch", str(b), "--backend",
                     be, "--quiet"])
                times[(be, b)].append(time.perf_counter() - t)
    ref = statistics.median(times[("scalar", batches[0])]) if "scalar" in backends else None
    print("| office1, decompose | " + " | ".join(backends) + " | bytes |")
    print("| --- |" + " --- |" * (len(backends) + 1))
    for b in batches:
        same = all(open(os.path.join(a.out, "office1_full_b%d_%s.pcd" % (b, be)), "rb").read()
                   == open(os.path.join(a.out, "office1_full_b%d_%s.pcd" % (b, backends[0])),
                           "rb").read() for be in backends)
        cells = []
        for be in backends:
            med = statistics.median(times[(be, b)])
            cells.append("%.2f s" % med + (" (%.2f)" % (ref / med) if ref else ""))
        print("| --batch %d | %s | %s |" % (b, " | ".join(cells), "same" if same else "DIFFER"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("relief")
    ap.add_argument("tool")
    ap.add_argument("depth")
    ap.add_argument("out")
    ap.add_argument("--batch", type=int, default=64)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--backends", default="scalar,host,opencl")
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--only", choices=["quality", "speed"], default="")
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    batches = [1, a.batch]
    if a.only != "speed":
        quality(a, batches)
    if a.only != "quality":
        speed(a, batches)


if __name__ == "__main__":
    main()
