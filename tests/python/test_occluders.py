"""Occluders from depth in the Python package (issue 43): on the synthetic
RGB-D frame the API test writes (a brick wall and a floor, two boxes and a
sphere in front, a depth camera's noise), find_occluders and
remove_occluders give the command line's bytes, the mask's IoU against the
truth is at least 0.9, and bad arguments raise ReliefError naming them."""
import os
import subprocess

import numpy as np
import pytest

import relief

from common import CLI, DATA


@pytest.fixture(scope="module")
def frame(tmp_path_factory):
    tool = os.path.join(os.path.dirname(CLI), "tests", "test_api_occluders")
    if not os.access(tool, os.X_OK) or not os.access(CLI, os.X_OK):
        pytest.skip(f"{tool}: not built")
    d = tmp_path_factory.mktemp("rgbd")
    subprocess.run([tool, "--write", str(d)], check=True)
    return d, relief.read_image(str(d / "colour.png")), read_png16(d / "depth.png"), \
        relief.read_image(str(d / "truth.png")) != 0


def read_png16(path):
    z = relief.read_depth(str(path))  # metres, NaN missing
    return np.where(np.isnan(z), 0, np.rint(z * 5000.0)).astype(np.uint16)


def run(*args):
    r = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr


def test_find_matches_cli_and_truth(frame):
    d, colour, depth, truth = frame
    mask, report = relief.find_occluders(colour, depth, return_report=True)
    assert mask.dtype == bool and mask.shape == depth.shape
    iou = (mask & truth).sum() / (mask | truth).sum()
    assert iou >= 0.9, iou
    assert len(report["background"]["planes"]) == 2
    run("occluders", d / "colour.png", "--depth", d / "depth.png", "-o", d / "m.png", "--quiet")
    assert np.array_equal(relief.read_image(str(d / "m.png")) != 0, mask)


def test_remove_matches_cli(frame):
    d, colour, depth, truth = frame
    out = relief.remove_occluders(colour, depth)
    assert out.colour.shape == colour.shape and out.depth.dtype == np.uint16
    assert np.array_equal(out.depth[~out.mask], depth[~out.mask])
    assert np.all(out.depth[out.mask & truth] > 0)
    run("remove-occluders", d / "colour.png", "--depth", d / "depth.png", "-o", d / "c.png",
        "--depth-out", d / "z.png", "--quiet")
    assert np.array_equal(relief.read_image(str(d / "c.png")), out.colour)
    assert np.array_equal(read_png16(d / "z.png"), out.depth)
    # The same with the mask given: the same frame.
    again = relief.remove_occluders(colour, depth, out.mask)
    assert np.array_equal(again.depth, out.depth)
    # On one thread (issue 60: the finding's threads= bounds the fills too).
    one = relief.remove_occluders(colour, depth, threads=1)
    assert np.array_equal(one.colour, out.colour) and np.array_equal(one.depth, out.depth)


def test_views_match_cli(frame):
    d, colour, depth, truth = frame
    run("occluders", d / "dark_colour.png", "--depth", d / "dark_depth.png", "-o", d / "dv.png",
        "--views", f"{d / 'left.png'},{d / 'right.png'}", "--poses", d / "poses.txt", "--quiet")
    pose = [np.array([[1, 0, 0, t], [0, 1, 0, 0], [0, 0, 1, 0]], float) for t in (0.1, -0.1)]
    views = [(relief.read_image(str(d / n)), p) for n, p in zip(("left.png", "right.png"), pose)]
    dark_colour = relief.read_image(str(d / "dark_colour.png"))
    dark_depth = read_png16(d / "dark_depth.png")
    mask = relief.find_occluders(dark_colour, dark_depth, views=views)
    assert np.array_equal(relief.read_image(str(d / "dv.png")) != 0, mask)
    without = relief.find_occluders(dark_colour, dark_depth)
    assert (mask & truth).sum() / (mask | truth).sum() > (without & truth).sum() / (without | truth).sum()
    with pytest.raises(relief.ReliefError, match="pose"):
        relief.find_occluders(colour, depth, views=[(views[0][0], np.eye(3))])
    with pytest.raises(relief.ReliefError, match="frame's size"):
        relief.find_occluders(colour, depth, views=[(views[0][0][:-1], pose[0])])


def test_views_of_their_own_camera(frame):
    """Views cropped (other sizes, other principal points) and given their
    intrinsics find what the frame's size views find (issue 63)."""
    d, colour, depth, truth = frame
    pose = [np.array([[1, 0, 0, t], [0, 1, 0, 0], [0, 0, 1, 0]], float) for t in (0.1, -0.1)]
    side = [relief.read_image(str(d / n)) for n in ("left.png", "right.png")]
    dark_colour = relief.read_image(str(d / "dark_colour.png"))
    dark_depth = read_png16(d / "dark_depth.png")
    cam = (262.5, 262.5, 159.5, 119.5)
    full = relief.find_occluders(dark_colour, dark_depth, intrinsics=cam,
                                 views=list(zip(side, pose)))
    same = relief.find_occluders(dark_colour, dark_depth, intrinsics=cam,
                                 views=[(s, p, cam) for s, p in zip(side, pose)])
    assert np.array_equal(same, full)
    crops = [(s[y:y + h, x:x + w], p, (262.5, 262.5, 159.5 - x, 119.5 - y))
             for s, p, (x, y, w, h) in zip(side, pose, ((24, 16, 272, 200), (8, 30, 300, 190)))]
    mask, report = relief.find_occluders(dark_colour, dark_depth, intrinsics=cam, views=crops,
                                         return_report=True)
    iou = lambda m: (m & truth).sum() / (m | truth).sum()
    assert abs(iou(mask) - iou(full)) < 0.02, (iou(mask), iou(full))
    front = report["views"]["in_front"]
    assert front["foreground"] > 3 * front["background"], front
    with pytest.raises(relief.ReliefError, match="intrinsics"):
        relief.find_occluders(dark_colour, dark_depth, views=[(crops[0][0], pose[0], (1, 2))])
    with pytest.raises(relief.ReliefError, match="another with the view's intrinsics"):
        relief.find_occluders(dark_colour, dark_depth, views=[(crops[0][0], pose[0])])


def test_read_pcd_office1(tmp_path):
    """A PCD's depth, colour and points from Python: find_occluders on
    office1.pcd gives the command line's mask (issue 63)."""
    path = os.path.join(DATA, "depth", "office1.pcd")
    if not os.path.exists(path):
        pytest.skip(f"{path}: not there")
    f = relief.read_pcd(path)
    assert f.depth.shape == (480, 640) and f.depth.dtype == np.float32
    assert f.colour.shape == (480, 640, 3) and f.colour.dtype == np.uint8
    assert f.points.shape == (480, 640, 3)
    seen = ~np.isnan(f.depth)
    assert np.array_equal(f.points[..., 2][seen], f.depth[seen])
    assert np.array_equal(relief.read_depth(path), f.depth, equal_nan=True)
    mask = relief.find_occluders(f.colour, f.depth, points=f.points)
    run("occluders", path, "-o", tmp_path / "m.png", "--quiet")
    assert np.array_equal(relief.read_image(str(tmp_path / "m.png")) != 0, mask)
    with pytest.raises(relief.ReliefError, match="not a PCD"):
        relief.read_pcd(os.path.join(DATA, "rgbd", "sequence", "depth", "00000.png"))


def test_bad_arguments(frame):
    _, colour, depth, _ = frame
    with pytest.raises(relief.ReliefError, match="same size"):
        relief.find_occluders(colour[:-1], depth)
    with pytest.raises(relief.ReliefError, match="window"):
        relief.find_occluders(colour, depth, window=60)
    with pytest.raises(relief.ReliefError, match="unknown parameter"):
        relief.find_occluders(colour, depth, no_such=1)
    with pytest.raises(relief.ReliefError, match="nothing to remove"):
        relief.remove_occluders(colour, depth, np.zeros(depth.shape, np.uint8))
    flat = np.full(depth.shape, 10000, np.uint16)  # a wall 2 m away, nothing in front
    with pytest.raises(relief.ReliefError, match="nothing in front"):
        relief.find_occluders(colour, flat)
