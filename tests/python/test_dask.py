"""relief on Dask (issue 41): a LocalCluster of two worker processes
repairs eight depth frames, one task each; the results equal the serial
ones, and a frame that fails comes back as a ReliefError (its status and
message intact) without stopping the others. The same with the example
script python/examples/dask_depth_frames.py over a folder."""
import os
import subprocess
import sys

import numpy as np
import pytest

import relief

distributed = pytest.importorskip("dask.distributed")

from common import DATA, ROOT, need


@pytest.fixture(scope="module")
def frames():
    z = relief.read_depth(need(os.path.join(DATA, "depth", "motorcycle_disp.pfm")))
    out = []
    for k in range(8):
        f = np.ascontiguousarray(z[100 + 30 * k:164 + 30 * k, 200:264])
        f[20:30, 24:34] = np.nan
        out.append(f)
    out[5] = np.full_like(out[5], np.nan)  # nothing known: relief refuses it
    return out


def test_local_cluster_equals_serial(frames):
    serial = []
    for f in frames:
        try:
            serial.append(relief.depth_fill(f))
        except relief.ReliefError as e:
            serial.append(e)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        futures = client.map(relief.depth_fill, frames, pure=False)
        distributed.wait(futures)
        for k, (fut, want) in enumerate(zip(futures, serial)):
            if isinstance(want, relief.ReliefError):
                assert fut.status == "error"
                got = fut.exception()
                assert isinstance(got, relief.ReliefError) and got.status == want.status
                assert str(got) == str(want)
            else:
                assert fut.status == "finished", fut.exception()
                got = fut.result()
                assert np.array_equal(np.isnan(got), np.isnan(want))
                assert np.array_equal(np.nan_to_num(got), np.nan_to_num(want)), f"frame {k}"


def test_example_script(frames, tmp_path):
    (tmp_path / "in").mkdir()
    (tmp_path / "out").mkdir()
    for k, f in enumerate(frames[:4]):
        relief.write_depth(tmp_path / "in" / f"frame{k}.pfm", f)
    relief.write_depth(tmp_path / "in" / "frame4.pfm", frames[5])
    r = subprocess.run([sys.executable, os.path.join(ROOT, "python", "examples",
                                                     "dask_depth_frames.py"),
                        str(tmp_path / "in"), str(tmp_path / "out")],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 1, r.stderr
    assert "4 of 5 frames repaired" in r.stderr and "frame4.pfm: failed:" in r.stderr
    for k in range(4):
        got = relief.read_depth(tmp_path / "out" / f"frame{k}.pfm")
        assert np.array_equal(np.nan_to_num(got), np.nan_to_num(relief.depth_fill(frames[k])))
