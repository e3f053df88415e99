"""What the package promises at its edges (issue 60, docs/limits.md):

- the interpreter's exit with a call in flight in a daemon thread cancels
  and waits for it, never std::terminate (exit 134);
- relief.cancel_all() and a call's cancel= event cancel calls in other
  threads, and Ctrl-C reaches them as docs/python.md wires it;
- max_memory is checked from the arrays' shapes before anything is copied;
- a value the engine's dtype cannot hold is refused, never read as missing.
"""
import concurrent.futures
import os
import resource
import signal
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import relief

# A fill that runs for seconds on the scalar backend: a 300 x 300 hole.
RNG = np.random.default_rng(1)
IMG = RNG.integers(0, 255, (600, 600, 3), dtype=np.uint8)
HOLE = np.zeros(IMG.shape[:2], np.uint8)
HOLE[100:400, 100:400] = 1

EXIT_SCRIPT = """
import sys, threading, time
import numpy as np, relief
relief._EXIT_WAIT_S = float(sys.argv[2])
rng = np.random.default_rng(1)
img = rng.integers(0, 255, (600, 600, 3), dtype=np.uint8)
hole = np.zeros(img.shape[:2], np.uint8); hole[100:400, 100:400] = 1
# A frame large enough (about 1 s a call here) that the plain case's exit
# rarely comes while its thread, a call just ended, waits for the GIL to
# start the next: at 720 x 960 (0.3 s a call) a loaded CI caught it there
# once, with no call in flight to report.
y, x = np.mgrid[0:1440, 0:1920]
colour = rng.integers(0, 255, (1440, 1920, 3), dtype=np.uint8)
depth = (2000 + x + y // 2).astype(np.uint16)
started = threading.Event()

def progress(f):
    started.set()
    if sys.argv[1] == "python":  # in the user's Python when the exit comes
        time.sleep(0.2)

def run():
    if sys.argv[1] == "plain":   # no progress steps: runs to its end, then parks
        while True:
            started.set()
            relief.find_occluders(colour, depth)
    relief.image_fill(img, hole, backend="scalar", progress=progress)

threading.Thread(target=run, daemon=True).start()
started.wait()
if sys.argv[1] == "plain":  # the GIL let go, so the thread enters its call even on a
    time.sleep(0.3)         # loaded machine (a call lasts about 1 s)
# A finalisation long enough for the worker's next progress step, which
# took the GIL of a finalising interpreter before issue 60 (exit 134).
junk = [{"k": i} for i in range(1_000_000)]
"""


@pytest.mark.parametrize("case, wait, runs", [("library", 5, 10), ("python", 0, 4),
                                             ("plain", 0, 4)])
def test_exit_with_a_call_in_flight(tmp_path, case, wait, runs):
    """A daemon thread's fill in the library (10 runs; 10 of 10 ended in
    exit 134 before issue 60), in its progress callback's Python, or a call
    without progress steps (waited for 0 s, so left running) when the main
    thread ends: exit 0, no terminate, no fatal error."""
    script = tmp_path / "exit.py"
    script.write_text(EXIT_SCRIPT)
    for run in range(runs):
        t0 = time.monotonic()
        r = subprocess.run([sys.executable, str(script), case, str(wait)], capture_output=True,
                           text=True, timeout=60)
        took = time.monotonic() - t0
        assert r.returncode == 0, f"run {run}: exit {r.returncode}\n{r.stderr}"
        assert "terminate called" not in r.stderr and "Fatal Python error" not in r.stderr, \
            r.stderr
        assert took < 20, f"run {run}: the exit took {took:.1f} s"
        if case == "plain":
            assert "still running" in r.stderr, r.stderr


def _fill_in_thread(**kw):
    """A long fill in a thread; (thread, started event, result dict)."""
    started, result = threading.Event(), {}

    def run():
        try:
            relief.image_fill(IMG, HOLE, backend="scalar", progress=lambda f: started.set(), **kw)
            result["status"] = "done"
        except relief.ReliefError as e:
            result["status"], result["message"] = e.status, str(e)

    t = threading.Thread(target=run)
    t.start()
    return t, started, result


def test_cancel_all_reaches_every_thread():
    runs = [_fill_in_thread() for _ in range(2)]
    for _, started, _ in runs:
        assert started.wait(30)
    t0 = time.monotonic()
    relief.cancel_all()
    for t, _, result in runs:
        t.join(10)
        assert not t.is_alive()
        assert result["status"] == "cancelled", result
        assert "relief.cancel_all()" in result["message"], result
    assert time.monotonic() - t0 < 2
    small = relief.image_fill(IMG[:48, :48], HOLE[:48, :48] * 0)  # later calls run
    assert np.array_equal(small, IMG[:48, :48])


def test_cancel_event():
    stop = threading.Event()
    t, started, result = _fill_in_thread(cancel=stop)
    assert started.wait(30)
    t0 = time.monotonic()
    stop.set()
    t.join(10)
    assert result["status"] == "cancelled" and "cancel event" in result["message"], result
    assert time.monotonic() - t0 < 2
    with pytest.raises(relief.ReliefError) as e:  # set before: cancelled at once
        relief.depth_fill(np.where(HOLE != 0, np.nan, 1.0), cancel=stop)
    assert e.value.status == "cancelled"
    with pytest.raises(relief.ReliefError, match="is_set"):
        relief.image_fill(IMG, HOLE, cancel=True)


def test_ctrl_c_cancels_worker_threads_as_documented():
    """docs/python.md's recipe: the main thread waits on an executor's
    futures; Ctrl-C's KeyboardInterrupt sets the calls' cancel event, and
    every call, running or queued, ends at once."""
    stop, started = threading.Event(), threading.Event()

    def fill(seed):
        return relief.image_fill(IMG, HOLE, backend="scalar", seed=seed, cancel=stop,
                                 progress=lambda f: started.set())

    timer = None
    t0 = time.monotonic()
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        futures = [pool.submit(fill, seed) for seed in range(6)]
        assert started.wait(30)
        timer = threading.Timer(0.1, os.kill, (os.getpid(), signal.SIGINT))
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            try:
                [f.result() for f in futures]
            except KeyboardInterrupt:
                stop.set()
                raise
    timer.join()
    assert time.monotonic() - t0 < 10
    for f in futures:
        assert isinstance(f.exception(), relief.ReliefError)
        assert f.exception().status == "cancelled"


def _peak_rss():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB


@pytest.mark.parametrize("call", [
    lambda: relief.image_fill(np.broadcast_to(np.zeros((1, 1, 3), np.uint8), (20000, 20000, 3)),
                              np.broadcast_to(np.uint8(1), (20000, 20000)), max_memory="64M"),
    lambda: relief.image_fill(np.broadcast_to(np.float32(0.5), (20000, 20000)),
                              np.broadcast_to(np.uint8(1), (20000, 20000)), max_memory="1G"),
    lambda: relief.depth_fill(np.broadcast_to(np.float64(1.5), (20000, 20000)),
                              np.broadcast_to(np.uint8(1), (20000, 20000)), max_memory="1G"),
    lambda: relief.depth_fill(np.broadcast_to(np.uint16(0), (60000, 60000)), max_memory="1G"),
])
def test_memory_refused_before_any_copy(call):
    """Arrays of 1.2 to 7.2 GB that take no memory (np.broadcast_to) are
    refused by max_memory at once, and the peak resident memory does not
    grow by a copy of them."""
    before = _peak_rss()
    t0 = time.monotonic()
    with pytest.raises(relief.ReliefError) as e:
        call()
    assert e.value.status == "nomem" and "over the limit" in str(e.value), str(e.value)
    assert time.monotonic() - t0 < 2
    grown = _peak_rss() - before
    assert grown < 64 << 20, f"peak resident memory grew by {grown / 2**20:.0f} MiB"


def test_side_over_the_limit_refused_before_any_copy():
    with pytest.raises(relief.ReliefError, match="height 70000 out of range"):
        relief.image_fill(np.broadcast_to(np.uint8(0), (70000, 8)), np.zeros((70000, 8), bool))


@pytest.mark.parametrize("value, words", [
    (1e300, "depth[3, 4] = 1e+300 is over float32's largest"),
    (-1e300, "depth[3, 4] = -1e+300 is over float32's largest"),
    (4e38, "depth[3, 4] = 4e+38 is over float32's largest"),
    (1e-50, "depth[3, 4] = 1e-50 rounds to 0 in float32"),
])
def test_depth_float32_cannot_hold_is_refused(value, words):
    z = np.ones((32, 32))
    z[10:14, 10:14] = np.nan  # NaN: missing, as documented
    z[3, 4] = value
    with pytest.raises(relief.ReliefError) as e:
        relief.depth_fill(z)
    assert e.value.status == "range" and words in str(e.value), str(e.value)
    with pytest.raises(relief.ReliefError, match=r"depth\[3, 4\]"):
        relief.write_depth("/nonexistent/never.pfm", z)


def test_missing_stays_missing_and_float32_extremes_pass():
    z = np.ones((32, 32))
    z[10:14, 10:14] = np.nan
    z[20, 20] = np.inf  # inf and 0 are missing too
    z[21, 21] = 0.0
    out = relief.depth_fill(z)
    assert np.isfinite(out[10:14, 10:14]).all() and np.isfinite(out[20, 20])
    big = np.full((32, 32), 1e30, np.float32)  # float32 input is never refused
    big[10:14, 10:14] = np.nan
    assert np.isfinite(relief.depth_fill(big)[10:14, 10:14]).all()


def test_other_conversions_refuse_what_they_cannot_hold(tmp_path):
    d = np.full((16, 16), 1000, np.uint16)
    with pytest.raises(relief.ReliefError, match="png_scale 1e-40"):
        relief.depth_fill(d, png_scale=1e-40)  # 1000 / 1e-40 is over float32's range
    with pytest.raises(relief.ReliefError, match="png_scale 1e"):
        relief.depth_fill(d, png_scale=1e60)  # 1000 / 1e60 rounds to 0: missing
    pts = np.zeros((16, 16, 3))
    pts[2, 3, 1] = 1e300
    with pytest.raises(relief.ReliefError, match=r"points\[2, 3, 1\] = 1e\+300"):
        relief.find_occluders(np.zeros((16, 16, 3), np.uint8), d, points=pts)
    for labels, words in (([0, 1, 256], "labels[2] = 256"), ([0, -1, 1], "labels[1] = -1"),
                          ([0, 0.5, 1], "labels[1] = 0.5")):
        with pytest.raises(relief.ReliefError) as e:
            relief.write_mesh(tmp_path / "m.ply", np.eye(3), [[0, 1, 2]], labels=labels)
        assert words in str(e.value), str(e.value)
    assert not (tmp_path / "m.ply").exists()


def test_float32_image_of_the_widest_range_keeps_its_pixels():
    """The 16-bit scale of a float32 image is computed in float64: a range
    wider than float32's largest no longer overflows to inf."""
    f = np.linspace(-3e38, 3e38, 64 * 64, dtype=np.float32).reshape(64, 64)
    mask = np.zeros(f.shape, np.uint8)
    mask[20:30, 20:30] = 1
    out = relief.image_fill(f, mask, window=5)
    assert np.array_equal(out[mask == 0], f[mask == 0])
    assert np.isfinite(out).all()
