"""The Python package's costs, side by side in one run (issue 41):

1. the binding's overhead: relief.image_fill on an array against
   `relief image-fill` on the same PNG (a process, reading and writing the
   files), and against the same call's engine time (the report's seconds);
2. a Dask batch against a serial loop: eight depth frames repaired on a
   LocalCluster of two single-threaded worker processes, and one after the
   other in this process.

Medians of REPEAT runs (default 5), each pair run back to back; ratios
printed. This machine is shared: only the ratios mean much.

    .venv/bin/python bench/python.py [RELIEF_CLI] [DATA_DIR] [REPEAT]
"""
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import relief

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CLI = sys.argv[1] if len(sys.argv) > 1 else os.path.join(ROOT, "build", "relief")
DATA = sys.argv[2] if len(sys.argv) > 2 else os.path.join(ROOT, "..", "shared", "data")
REPEAT = int(sys.argv[3]) if len(sys.argv) > 3 else 5


def timed(fn):
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def binding(tmp):
    img = relief.read_image(os.path.join(DATA, "images", "brick.png"))[:256, :256].copy()
    mask = np.zeros(img.shape, np.uint8)
    mask[100:130, 90:140] = 255
    relief.write_image(os.path.join(tmp, "in.png"), img)
    relief.write_image(os.path.join(tmp, "mask.png"), mask)
    cmd = [CLI, "image-fill", os.path.join(tmp, "in.png"), "--mask", os.path.join(tmp, "mask.png"),
           "-o", os.path.join(tmp, "out.png"), "--quiet", "--backend", "scalar"]
    py, cli, engine = [], [], []
    for _ in range(REPEAT):
        out = {}
        py.append(timed(lambda: out.update(r=relief.image_fill(img, mask, backend="scalar",
                                                               return_report=True))))
        engine.append(out["r"][1]["seconds"]["total"])
        cli.append(timed(lambda: subprocess.run(cmd, check=True)))
    p, c, e = (statistics.median(x) for x in (py, cli, engine))
    print(f"image_fill 256 x 256, a 50 x 30 hole, scalar: Python {p:.3f} s, CLI {c:.3f} s "
          f"(CLI / Python {c / p:.2f}), engine {e:.3f} s (Python's overhead {p - e:+.4f} s)")


def dask_batch():
    from dask.distributed import Client, LocalCluster
    z = relief.read_depth(os.path.join(DATA, "depth", "motorcycle_disp.pfm"))
    frames = []
    for k in range(8):
        f = np.ascontiguousarray(z[40 * k:40 * k + 160, 200:360])
        f[60:80, 60:90] = np.nan
        frames.append(f)
    serial, batch = [], []
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                      dashboard_address=None) as cluster, Client(cluster) as client:
        client.gather(client.map(relief.depth_fill, frames[:2], pure=False))  # warm
        for _ in range(REPEAT):
            serial.append(timed(lambda: [relief.depth_fill(f) for f in frames]))
            batch.append(timed(lambda: client.gather(client.map(relief.depth_fill, frames,
                                                                pure=False))))
    s, b = statistics.median(serial), statistics.median(batch)
    print(f"depth_fill on 8 frames of 160 x 160: serial {s:.3f} s, Dask (2 workers) {b:.3f} s "
          f"(serial / Dask {s / b:.2f})")


if __name__ == "__main__":
    with tempfile.TemporaryDirectory() as tmp:
        binding(tmp)
    dask_batch()
