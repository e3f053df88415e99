"""Repair a folder of depth frames on a Dask cluster, one task per frame.

    .venv/bin/python python/examples/dask_depth_frames.py FRAMES_DIR OUT_DIR [SCHEDULER]

FRAMES_DIR holds depth frames relief reads (.pfm, .png 16-bit, organised
.pcd's depth); each repaired frame is written to OUT_DIR as a PFM under its
name. Without SCHEDULER (an address such as tcp://host:8786) a LocalCluster
of two single-threaded worker processes runs here; with one, the tasks go
to that cluster, whose workers need relief installed. A frame that fails
is reported with relief's message and does not stop the others; the exit
status is 1 when any failed.
"""
import os
import sys

from dask.distributed import Client, LocalCluster, as_completed

import relief


def repair(path, **params):
    """One frame: read, repair, return the filled depth (NaN where missing)."""
    return relief.depth_fill(relief.read_depth(path), **params)


def main(frames_dir, out_dir, scheduler=None):
    paths = sorted(os.path.join(frames_dir, f) for f in os.listdir(frames_dir)
                   if f.lower().endswith((".pfm", ".png", ".pcd")))
    cluster = None if scheduler else LocalCluster(n_workers=2, threads_per_worker=1)
    failed = 0
    with Client(scheduler or cluster) as client:
        futures = {client.submit(repair, p, pure=True): p for p in paths}
        for future in as_completed(futures):
            path = futures[future]
            name = os.path.splitext(os.path.basename(path))[0] + ".pfm"
            if future.status == "error":
                failed += 1
                print(f"{path}: failed: {future.exception()}", file=sys.stderr)
            else:
                relief.write_depth(os.path.join(out_dir, name), future.result())
                print(f"{path}: {name}", file=sys.stderr)
    if cluster:
        cluster.close()
    print(f"{len(paths) - failed} of {len(paths)} frames repaired", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
