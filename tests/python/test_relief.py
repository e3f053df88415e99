"""relief's Python package (issue 41): each engine on real data from
../shared/data gives the bytes the command line gives for the same input and
seed; bad arguments raise ReliefError naming them, never crash; two threads
run at once; a progress callback cancels; 200 calls do not grow memory.

Run by ctest (test_python) with the project's .venv:
  RELIEF=build/relief DATA=../shared/data .venv/bin/python -m pytest tests/python
"""
import os
import signal
import subprocess
import threading

import numpy as np
import pytest

import relief

from common import CLI, DATA, need


def cli(*args):
    if not os.access(CLI, os.X_OK):
        pytest.skip(f"{CLI}: the command line is not built")
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    return r


@pytest.fixture(scope="module")
def brick():
    """A 96 x 96 crop of the brick photograph and a 20 x 14 hole in it."""
    img = relief.read_image(need(os.path.join(DATA, "images", "brick.png")))[:96, :96].copy()
    mask = np.zeros(img.shape[:2], np.uint8)
    mask[40:54, 30:50] = 255
    return img, mask


def test_version_and_devices():
    assert relief.__version__.count(".") == 2
    assert isinstance(relief.devices(), list)
    assert "window" in relief.parameters("image_fill")


def test_image_fill_same_bytes_as_cli(brick, tmp_path):
    img, mask = brick
    relief.write_image(tmp_path / "in.png", img)
    relief.write_image(tmp_path / "mask.png", mask)
    cli("image-fill", tmp_path / "in.png", "--mask", tmp_path / "mask.png", "-o",
        tmp_path / "out.png", "--seed", 3, "--quiet")
    want = relief.read_image(tmp_path / "out.png")
    got, report = relief.image_fill(img, mask, seed=3, return_report=True)
    assert got.dtype == img.dtype and got.shape == img.shape
    assert np.array_equal(got, want)
    assert np.array_equal(got[mask == 0], img[mask == 0]), "pixels outside the mask changed"
    assert report["pixels"]["hole"] == int((mask != 0).sum())
    # The fill is textured, not flat: its local spread is that of the ring.
    hole = got[40:54, 30:50].astype(float)
    ring = got[34:60, 24:56].astype(float)
    assert hole.std() > 0.5 * ring.std()


def test_image_fill_dtypes(brick):
    img, mask = brick
    grey = img[:, :, 0] if img.ndim == 3 else img
    out16 = relief.image_fill(grey.astype(np.uint16) * 257, mask)
    assert out16.dtype == np.uint16 and out16.shape == grey.shape
    f = grey.astype(np.float32) / 255.0
    outf = relief.image_fill(f, mask != 0)
    assert outf.dtype == np.float32 and np.array_equal(outf[mask == 0], f[mask == 0])
    assert np.all(np.isfinite(outf)) and outf.min() >= 0 and outf.max() <= 1


def test_depth_fill_same_bytes_as_cli(tmp_path):
    z = relief.read_depth(need(os.path.join(DATA, "depth", "motorcycle_disp.pfm")))
    crop = np.ascontiguousarray(z[200:296, 300:396])
    crop[40:52, 30:44] = np.nan
    relief.write_depth(tmp_path / "in.pfm", crop)
    cli("depth-fill", tmp_path / "in.pfm", "-o", tmp_path / "out.pfm", "--quiet")
    want = relief.read_depth(tmp_path / "out.pfm")
    got = relief.depth_fill(crop, values="disparity")  # a PFM's, as the CLI reads it
    assert got.dtype == np.float32
    assert np.array_equal(np.isnan(got), np.isnan(want))
    assert np.array_equal(np.nan_to_num(got), np.nan_to_num(want))
    assert not np.isnan(got[40:52, 30:44]).any()
    known = ~np.isnan(crop)
    assert np.array_equal(got[known], crop[known])


def test_read_depth_encodings(tmp_path):
    # A PGM's counts big-endian; NYU's raw disparities little-endian.
    (tmp_path / "d.pgm").write_bytes(b"P5\n3 1\n65535\n" + np.array([0, 5000, 768], ">u2").tobytes())
    z = relief.read_depth(tmp_path / "d.pgm")
    assert np.isnan(z[0, 0]) and z[0, 1] == np.float32(1.0)
    d = np.frombuffer(np.array([0, 5000, 768], ">u2").tobytes(), "<u2")
    nyu = relief.read_depth(tmp_path / "d.pgm", encoding="nyu")
    want = np.where(d < 2047, 351.3 / (1092.5 - d.astype(np.float64)), np.nan)
    want[want <= 0] = np.nan
    assert np.allclose(nyu[0], want, equal_nan=True)
    with pytest.raises(ValueError):
        relief.read_depth(tmp_path / "d.pgm", encoding="kinect")


def test_threads_give_the_default_result(brick, tmp_path):
    """threads= (issue 60): 1, 3 or the default (the CPUs this process may
    run on), the same arrays from each engine; out of range raises naming
    the parameter."""
    img, mask = brick
    want = relief.image_fill(img, mask, backend="host")
    for t in (1, 3):
        assert np.array_equal(relief.image_fill(img, mask, backend="host", threads=t), want)
    z = np.full((64, 64), 1500, np.uint16) + (np.arange(64, dtype=np.uint16) * 4)[None, :]
    z[20:30, 20:30] = 0
    assert np.array_equal(relief.depth_fill(z, threads=1), relief.depth_fill(z))
    cli("synth", "plane-waves", "-o", tmp_path / "cap.ply", "--vertices", 500)
    cap = relief.read_mesh(tmp_path / "cap.ply")
    same = lambda a, b: all((x is None and y is None) or np.array_equal(x, y)
                            for x, y in zip(a, b))
    assert same(relief.complete_mesh(cap.vertices, cap.faces, threads=1),
                relief.complete_mesh(cap.vertices, cap.faces))
    kw = dict(faces=cap.faces, iterations=2, max_hole=10)
    assert same(relief.complete_points(cap.vertices, threads=1, **kw),
                relief.complete_points(cap.vertices, **kw))
    with pytest.raises(relief.ReliefError, match="threads 65 out of range"):
        relief.image_fill(img, mask, threads=65)


def test_depth_fill_uint16_and_mask():
    z = np.full((64, 64), 1500, np.uint16) + (np.arange(64, dtype=np.uint16) * 4)[None, :]
    z[20:30, 20:30] = 0
    out = relief.depth_fill(z)
    assert out.dtype == np.uint16 and (out[20:30, 20:30] > 0).all()
    assert np.array_equal(out[z > 0], z[z > 0])
    mask = np.zeros(z.shape, bool)
    mask[40:44, 40:44] = True
    out2 = relief.depth_fill(out, mask)
    assert np.array_equal(out2[~mask], out[~mask])


def test_complete_points_same_bytes_as_cli(tmp_path):
    fert = need(os.path.join(DATA, "real", "fertility", "fertility.off"))
    cli("cut", fert, "-o", tmp_path / "cut.ply", "--ball", "5.48,31.18,10.73,8")
    cli("complete-points", tmp_path / "cut.ply", "-o", tmp_path / "out.ply", "--iterations", 2,
        "--quiet")
    want = relief.read_mesh(tmp_path / "out.ply")
    cut = relief.read_mesh(tmp_path / "cut.ply")
    pts, col, lab = relief.complete_points(cut.vertices, faces=cut.faces, iterations=2)
    assert col is None and lab.dtype == np.uint8
    assert np.array_equal(pts.astype(np.float32), want.vertices.astype(np.float32))
    assert np.array_equal(lab, want.labels)
    assert (lab == 1).sum() > 0 and np.array_equal(pts[: len(cut.vertices)], cut.vertices)


def test_complete_mesh_same_bytes_as_cli(tmp_path):
    cli("synth", "plane-waves", "-o", tmp_path / "cap.ply", "--seed", 1)
    cli("complete", tmp_path / "cap.ply", "-o", tmp_path / "out.ply", "--backend", "scalar",
        "--quiet")
    want = relief.read_mesh(tmp_path / "out.ply")
    cap = relief.read_mesh(tmp_path / "cap.ply")
    (v, f, c, lab), rep = relief.complete_mesh(cap.vertices, cap.faces, cap.colours,
                                               backend="scalar", return_report=True)
    assert np.array_equal(v.astype(np.float32), want.vertices.astype(np.float32))
    assert np.array_equal(f, want.faces) and np.array_equal(lab, want.labels)
    assert isinstance(rep, dict) and (lab == 1).sum() > 0


def test_fill_mesh_holes_same_bytes_as_cli(tmp_path):
    vase = need(os.path.join(DATA, "real", "ggg_sfm", "blackVase.ply"))
    cli("cut", vase, "-o", tmp_path / "cut.ply", "--ball", "148.82,20.99,223.15,30")
    cli("depth-fill", tmp_path / "cut.ply", "-o", tmp_path / "out.ply", "--resolution", 96,
        "--quiet")
    cut = relief.read_mesh(tmp_path / "cut.ply")
    v, f, c, lab = relief.fill_mesh_holes(cut.vertices, cut.faces, cut.colours, resolution=96)
    # Written as the CLI writes, the same bytes (read back, a reader would
    # weld the copies of a split vertex the patches joined, left unused in
    # the arrays so that the input's vertices come first, in order).
    relief.write_mesh(tmp_path / "py.ply", v, f, c, lab)
    assert (tmp_path / "py.ply").read_bytes() == (tmp_path / "out.ply").read_bytes()
    assert (lab == 1).sum() > 0 and len(f) > len(cut.faces)


def test_fill_mesh_holes_sphere_cap(tmp_path):
    # Issue 61: a sphere's cap came back a flat, stepped plate that crossed
    # itself, 35 632 vertices added to a 2 989-vertex sphere. Now the cap is
    # closed by a faired patch at the sphere's density, near the sphere.
    cli("synth", "sphere-dimples", "-o", tmp_path / "s.ply", "--truth", tmp_path / "t.ply",
        "--vertices", 3000)
    cli("cut", tmp_path / "t.ply", "-o", tmp_path / "cap.ply", "--ball", "0,0,1,0.6")
    cap = relief.read_mesh(tmp_path / "cap.ply")
    v, f, _, lab = relief.fill_mesh_holes(cap.vertices, cap.faces, resolution=96, max_hole=2)
    new = v[lab == 1]
    assert 100 < len(new) < 800, len(new)  # the cut took 267 vertices
    radius = np.linalg.norm(new, axis=1)
    assert np.abs(radius - 1).max() < 0.1, np.abs(radius - 1).max()  # a flat lid sags 0.2
    edges = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    _, count = np.unique(edges, axis=0, return_counts=True)
    assert (count == 2).all(), "the filled sphere is not closed"


@pytest.mark.parametrize("call, words", [
    (lambda: relief.image_fill(np.zeros((8, 8), np.int32), np.zeros((8, 8))), "image: dtype"),
    (lambda: relief.image_fill(np.zeros((8, 8, 5), np.uint8), np.zeros((8, 8))), "channels"),
    (lambda: relief.image_fill(np.zeros((8, 8), np.uint8), np.zeros((8, 9))), "mask: shape"),
    (lambda: relief.image_fill(np.zeros((0, 8), np.uint8), np.zeros((0, 8))), "empty"),
    (lambda: relief.image_fill(np.zeros(8, np.uint8), np.zeros(8)), "dimensions"),
    (lambda: relief.image_fill(np.zeros((8, 8), np.uint8), np.ones((8, 8)), window=5), "every pixel"),
    (lambda: relief.image_fill(np.zeros((8, 8), np.uint8), np.zeros((8, 8)), window=4), "window"),
    (lambda: relief.image_fill(np.zeros((8, 8), np.uint8), np.zeros((8, 8)), colour=1),
     "unknown parameter 'colour'"),
    (lambda: relief.depth_fill(np.zeros((8, 8), np.int8)), "depth: dtype"),
    (lambda: relief.depth_fill(np.zeros((8, 8), np.float32), np.zeros((4, 4))), "mask: shape"),
    (lambda: relief.complete_mesh([[0, 0, 0], [np.nan, 0, 0], [0, 1, 0]], [[0, 1, 2]]),
     "vertex 1 is not finite"),
    (lambda: relief.complete_mesh(np.zeros((3, 2)), [[0, 1, 2]]), "vertices: shape"),
    (lambda: relief.complete_mesh(np.zeros((3, 3)), [[0, 1, 3]]), "faces: index 3"),
    (lambda: relief.complete_mesh(np.zeros((0, 3)), None), "vertices: shape"),
    (lambda: relief.fill_mesh_holes(np.eye(3), None), "faces: a mesh's holes"),
    (lambda: relief.complete_points(np.eye(3), colours=np.zeros((2, 3))), "colours: shape"),
    (lambda: relief.complete_points([["a", "b", "c"]]), "points"),
    (lambda: relief.read_mesh("/nonexistent/none.ply"), "none.ply"),
    (lambda: relief.image_fill(np.zeros((8, 8), np.uint8), np.zeros((8, 8)), progress=3),
     "progress"),
])
def test_bad_arguments_raise(call, words):
    with pytest.raises(relief.ReliefError) as e:
        call()
    assert words in str(e.value), str(e.value)
    assert e.value.status


def test_two_threads_at_once(brick):
    img, mask = brick
    serial = [relief.image_fill(img, mask, seed=s) for s in (1, 2)]
    got = [None, None]

    def run(k):
        got[k] = relief.image_fill(img, mask, seed=k + 1)

    threads = [threading.Thread(target=run, args=(k,)) for k in (0, 1)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert all(np.array_equal(a, b) for a, b in zip(got, serial))


def test_progress_cancels_and_raises(brick):
    img, mask = brick
    seen = []
    relief.image_fill(img, mask, progress=seen.append)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)
    with pytest.raises(relief.ReliefError) as e:
        relief.image_fill(img, mask, progress=lambda f: True)
    assert e.value.status == "cancelled"

    def boom(f):
        raise ValueError("stop here")

    with pytest.raises(ValueError, match="stop here"):
        relief.image_fill(img, mask, progress=boom)


def test_ctrl_c_cancels(brick):
    """SIGINT during a run (here from its progress callback, on the main
    thread, as Ctrl-C comes) ends it with KeyboardInterrupt; a later call
    runs as before."""
    img, mask = brick
    with pytest.raises(KeyboardInterrupt):
        relief.image_fill(img, mask, progress=lambda f: signal.raise_signal(signal.SIGINT))
    assert np.array_equal(relief.image_fill(img, mask), relief.image_fill(img, mask))


def test_no_memory_growth_over_200_calls():
    img = (np.arange(32 * 32, dtype=np.uint32).reshape(32, 32) * 2654435761 % 251).astype(np.uint8)
    mask = np.zeros((32, 32), np.uint8)
    mask[12:18, 12:18] = 1

    def rss():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")

    for _ in range(20):
        relief.image_fill(img, mask)
    before = rss()
    for _ in range(200):
        relief.image_fill(img, mask, return_report=True)
    grown = rss() - before
    assert grown < 8 << 20, f"resident memory grew by {grown / 2**20:.1f} MiB over 200 calls"


def test_depth_fill_edges_layers_and_colour():
    """A box 1.5 m away before a wall at 3 m with the camera's shadow beside
    it (issue 63): layers (the default) continue the wall into the shadow,
    across (paper 003) draws a ramp; a colour image parts the surfaces
    where its colour changes, and a wrong-sized one is refused."""
    rng = np.random.default_rng(3)
    z = np.full((64, 96), 3.0, np.float32)
    z[14:50, 24:52] = 1.5
    z += (0.003 * z * z * rng.uniform(-1, 1, z.shape)).astype(np.float32)
    hole = np.zeros(z.shape, bool)
    hole[14:50, 52:59] = True
    z[hole] = np.nan
    layers, rep = relief.depth_fill(z, return_report=True)
    across = relief.depth_fill(z, edges="across")
    assert np.abs(layers[hole] - 3.0).max() < 0.1
    assert (np.abs(across[hole] - 3.0) > 0.3).sum() > 20
    assert rep["layers"]["stepped_holes"] == 1 and rep["parameters"]["edges"] == "layers"
    colour = np.full(z.shape + (3,), 200, np.uint8)
    colour[14:50, 24:52] = (40, 40, 160)
    guided = relief.depth_fill(z, colour=colour)
    assert np.abs(guided[hole] - 3.0).max() < 0.1
    with pytest.raises(relief.ReliefError, match="same size"):
        relief.depth_fill(z, colour=colour[:10])
