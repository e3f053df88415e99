"""relief: fill what scans, depth frames and photographs miss, with detail
sampled from the capture itself (non-parametric sampling).

numpy arrays in, new numpy arrays out; the inputs are never written.
Images are (H, W) or (H, W, C) with channels last, and a mask is (H, W)
where non-zero means *fill*, as ``cv2.inpaint`` and
``skimage.restoration.inpaint_biharmonic`` take them. Meshes are an
(N, 3) array of vertex positions and an (M, 3) array of vertex indices per
triangle, counter-clockwise seen from outside; colours are (N, 3) floats in
[0, 1] (uint8 is taken as 0..255).

Every engine takes its parameters as keyword arguments, by the names of the
command line's options with ``_`` for ``-`` (``min_window=5``,
``max_memory="4G"``); ``relief.parameters("image_fill")`` lists them with
their help. ``threads=N`` bounds the host threads of a call (0, the
default: the CPUs this process may run on, its affinity); the result is the
same for any N. ``progress`` is a callable taking the fraction done (0 to 1);
returning True cancels the run; ``cancel`` is an object whose ``is_set()``
says to cancel (a ``threading.Event``), and :func:`cancel_all` cancels
every call in flight, from any thread. The GIL is released while an engine
runs, so several threads may run engines at once; Ctrl-C cancels a run on
the main thread (KeyboardInterrupt); a call in flight in a daemon thread
when the interpreter exits is cancelled and waited for. ``max_memory`` is
checked from the arrays' shapes before anything is copied, and a value the
engine's dtype cannot hold is refused, never read as missing. Any failure
raises :class:`ReliefError`, whose ``status`` names its kind ("range",
"usage", "mesh", "cancelled", ...).
The same input and seed give the same bytes as the command line, whatever
the backend. Every function is pure and picklable (module-level, numpy in
and out, ReliefError pickles whole), so Dask, multiprocessing or
concurrent.futures can run it on other processes or machines.
"""
import atexit
from collections import namedtuple
import json
import os
import sys

import numpy as np

from . import _relief

__all__ = ["ReliefError", "Mesh", "cancel_all", "image_fill", "depth_fill", "complete_mesh",
           "fill_mesh_holes", "complete_points", "find_occluders", "remove_occluders", "Removed",
           "read_mesh", "write_mesh", "read_image", "write_image",
           "read_depth", "read_pcd", "Frame", "write_depth",
           "devices", "parameters", "__version__"]

__version__ = _relief.version()

Mesh = namedtuple("Mesh", "vertices faces colours normals labels")
Mesh.__doc__ = """A mesh or point cloud as relief reads and returns it: vertices (N, 3)
float64; faces (M, 3) int32 or None for a point cloud; colours (N, 3) float32
in [0, 1], normals (N, 3) float64 and labels (N,) uint8 (0 captured,
1 added by relief), each None when absent."""


class ReliefError(RuntimeError):
    """A relief call failed; ``status`` names the kind ("range", "usage", "io",
    "format", "parse", "mesh", "nomem", "device", "cancelled", ...) and the
    message says what and where."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status

    def __reduce__(self):  # pickled whole, as Dask sends a worker's failure back
        return (ReliefError, (self.status, str(self)))


def _fail(status, message):
    raise ReliefError(status if isinstance(status, str) else _relief.status_name(status), message)


def _mesh(arrays):
    """The extension's arrays as a Mesh, faces as int32 (what Open3D's
    Vector3iVector takes; it crashes on uint32) or None without any."""
    v, f, c, n, lab = arrays
    f = f.astype(np.int32) if f is not None and len(f) else None
    return Mesh(v, f, c, n, lab)


def _check(result):
    status, message = result[0], result[1]
    if status != 0:
        _fail(status, message)
    return result[2:]


def _text(value):
    if isinstance(value, (bool, np.bool_)):
        return "yes" if value else "no"
    if isinstance(value, (list, tuple, np.ndarray)):
        return ",".join(repr(float(v)) for v in np.ravel(value))
    return str(value)


def _params(params):
    return {name: _text(value) for name, value in params.items() if value is not None}


def _report(text, wanted):
    return json.loads(text) if wanted and text else None


def _progress(progress):
    if progress is not None and not callable(progress):
        _fail("usage", "progress must be a callable taking the fraction done, or None")
    return progress


def _cancel(cancel):
    if cancel is not None and not callable(getattr(cancel, "is_set", None)):
        _fail("usage", f"cancel: {type(cancel).__name__} has no is_set(); expected an object "
              "such as threading.Event, or None")
    return cancel


# ------------------------------------------------------------ cancelling

def cancel_all():
    """Cancel every relief call in flight, in any thread: each raises
    ReliefError with status "cancelled" at its next progress step
    (find_occluders and the readers and writers have none: they run to
    their end). Calls that start afterwards run as usual. Safe from any
    thread and from a signal handler; Ctrl-C reaches only a call on the
    main thread by itself, so a program that runs relief in other threads
    calls this (or sets the calls' ``cancel`` event) on KeyboardInterrupt
    (docs/python.md shows how)."""
    _relief.cancel_all()


# Seconds the exit waits for the calls in flight to see their cancel.
_EXIT_WAIT_S = 5.0


def _at_exit():
    """Before Python finalises (atexit runs while daemon threads live): no
    call starts any more, those in flight are cancelled and waited for, and
    one that returns later parks its thread rather than take the GIL of a
    finalising interpreter (which would end it through std::terminate)."""
    left = _relief.at_exit(_EXIT_WAIT_S)
    if left:
        print(f"relief: {left} call{'s' if left > 1 else ''} without progress steps (as "
              f"find_occluders) still running {_EXIT_WAIT_S:g} s into the interpreter's exit; "
              "ended with the process", file=sys.stderr)


atexit.register(_at_exit)
if hasattr(os, "register_at_fork"):  # a child has none of its parent's calls
    os.register_at_fork(after_in_child=_relief.after_fork_in_child)


def _array(name, value, ndim=None):
    try:
        a = np.asarray(value)
    except Exception as e:  # a ragged list, an object that is no array
        _fail("usage", f"{name}: not an array ({e})")
    if a.dtype == object:
        _fail("usage", f"{name}: not a numeric array (dtype object)")
    if ndim is not None and a.ndim not in ndim:
        _fail("usage", f"{name}: {a.ndim} dimensions, expected {' or '.join(map(str, ndim))}")
    return a


def _mask_view(mask, shape, name="mask"):
    """The mask checked against the image's (H, W), not yet copied."""
    m = _array(name, mask, (2, 3))
    if m.ndim == 3 and m.shape[2] == 1:
        m = m[:, :, 0]
    if m.shape != tuple(shape):
        _fail("usage", f"{name}: shape {m.shape}, expected {tuple(shape)} (the image's height and width)")
    return m


def _colour_view(colour, shape, name="colour"):
    """A registered colour image as the engines take it: uint8 (H, W, 3),
    grey repeated, alpha dropped."""
    c = _array(name, colour, (2, 3))
    if c.dtype != np.uint8:
        _fail("usage", f"{name}: dtype {c.dtype}, expected uint8")
    if c.ndim == 2:
        c = np.repeat(c[:, :, None], 3, axis=2)
    if c.shape[2] not in (3, 4):
        _fail("usage", f"{name}: {c.shape[2]} channels, expected 3 (RGB) or 4 (RGBA)")
    if c.shape[:2] != tuple(shape):
        _fail("usage", f"{name}: shape {c.shape[:2]}, depth {tuple(shape)}: they must be the "
              "same size (registered)")
    return np.ascontiguousarray(c[:, :, :3])


def _mask_bits(m):
    """A checked mask as the engines take it: uint8, 1 = fill."""
    return np.ascontiguousarray(m != 0, dtype=np.uint8)


def _mask(mask, shape, name="mask"):
    return _mask_bits(_mask_view(mask, shape, name))


def _float32(name, a, zero_missing=False, note=""):
    """``a`` as a new C-ordered float32 array, refusing what float32 cannot
    hold: a finite value over 3.4e38 in magnitude (it would become inf,
    which relief reads as missing) and, where ``zero_missing``, a non-zero
    value that rounds to 0. NaN and inf stay what they were. ``note`` says
    where the values came from."""
    with np.errstate(over="ignore", under="ignore"):
        z = np.array(a, dtype=np.float32, order="C", copy=True)
    if np.can_cast(a.dtype, np.float32, "safe"):
        return z
    lost = np.isinf(z) & np.isfinite(a)
    if zero_missing:
        lost |= (z == 0) & (a != 0) & np.isfinite(a)
    n = int(np.count_nonzero(lost))
    if n:
        i = np.unravel_index(int(np.flatnonzero(lost)[0]), a.shape)
        why = ("rounds to 0 in float32, and 0 is missing" if z[i] == 0 else
               "is over float32's largest, 3.4e38: it would become inf, which is missing")
        _fail("range", f"{name}[{', '.join(map(str, map(int, i)))}] = {float(a[i]):g}{note} "
              f"{why} ({n} value{'s' if n > 1 else ''} float32 cannot hold)")
    return z


# ------------------------------------------------------------------ images

def image_fill(image, mask, *, method="wexler", window=17, seed=1, backend="auto",
               progress=None, cancel=None, return_report=False, **params):
    """Fill the pixels of ``image`` where ``mask`` is non-zero: a 1-D pass
    where a gap's ends agree and are smooth, then, with ``method="wexler"``
    (the default), multi-scale patch voting (Wexler et al. 2007 with
    PatchMatch's search; ``patch``, ``em_steps``, ``pm_steps``), or with
    ``method="jain"`` paper 004's copy-paste of windows matched coarse to
    fine (``window`` and its other parameters).

    image: (H, W) or (H, W, C), C 1 to 4 (grey, grey + alpha, RGB, RGBA),
    uint8, uint16 or float32 (float is filled on a 16-bit scale of its own
    range outside the mask; the pixels outside the mask keep their values).
    mask: (H, W), non-zero = fill. window: jain's starting window, odd pixels.
    Returns a new array like ``image`` (and the report as a dict when
    ``return_report``). Alpha is not matched; a filled pixel becomes opaque.
    ``max_memory`` is checked from the shapes before anything is copied.
    """
    progress, cancel = _progress(progress), _cancel(cancel)
    img = _array("image", image, (2, 3))
    if img.dtype not in (np.uint8, np.uint16, np.float32):
        _fail("usage", f"image: dtype {img.dtype}, expected uint8, uint16 or float32")
    planar = img.ndim == 2
    work = img[:, :, None] if planar else img
    if not 1 <= work.shape[2] <= 4:
        _fail("usage", f"image: {work.shape[2]} channels, expected 1 to 4")
    if work.shape[0] < 1 or work.shape[1] < 1:
        _fail("usage", f"image: shape {img.shape} is empty")
    m = _mask_view(mask, work.shape[:2])
    kw = _params(dict(params, method=method, window=window, seed=seed, backend=backend))
    _check(_relief.image_fill_check_memory(*work.shape, kw))
    m = _mask_bits(m)
    lo = scale = None
    if img.dtype == np.float32:
        known = work[m == 0]
        if known.size and not np.all(np.isfinite(known)):
            _fail("range", "image: a pixel outside the mask is NaN or infinite")
        lo = float(known.min()) if known.size else 0.0
        hi = float(known.max()) if known.size else 1.0
        scale = (hi - lo) if hi > lo else 1.0
        # In float64: the span of two float32 values may overflow float32.
        out = np.rint((np.nan_to_num(work.astype(np.float64)) - lo) / scale * 65535.0)
        out = np.ascontiguousarray(out.clip(0, 65535), dtype=np.uint16)
    else:
        out = np.array(work, order="C", copy=True)
    (report,) = _check(_relief.image_fill(out, m, kw, progress, cancel))
    if lo is not None:
        filled = (lo + out.astype(np.float64) / 65535.0 * scale).astype(np.float32)
        out = np.where(m[:, :, None] != 0, filled, work)
    out = out[:, :, 0] if planar else out
    return (out, _report(report, True)) if return_report else out


def _depth_dtype(d):
    if d.dtype not in (np.uint16, np.float32, np.float64):
        _fail("usage", f"depth: dtype {d.dtype}, expected uint16, float32 or float64")


def _depth_in(d, png_scale):
    """A depth array as the engines take it: float32 metres (or the input's
    units), NaN missing; uint16 is a depth PNG's values, png_scale per
    metre, 0 missing. A known depth float32 cannot hold (over 3.4e38, or
    rounding to 0, which is missing) is refused."""
    _depth_dtype(d)
    if d.dtype == np.uint16:
        if not png_scale > 0:
            _fail("range", f"png_scale {png_scale}: expected values per metre > 0")
        return _float32("depth", np.where(d == 0, np.nan, d / np.float64(png_scale)),
                        zero_missing=True, note=f" (the PNG's value / png_scale {png_scale:g})")
    return _float32("depth", d, zero_missing=True)


def _depth_out(d, z, filled, png_scale):
    """The engine's z back in d's dtype: uint16 takes z where `filled` (a
    filled depth rounds to at least 1; still missing stays 0) and keeps d's
    values elsewhere; floats are z."""
    if d.dtype != np.uint16:
        return z.astype(d.dtype)
    v = np.rint(np.nan_to_num(z, nan=0.0) * np.float64(png_scale))
    v = np.where(filled & (v < 1) & ~np.isnan(z), 1, v)
    return np.where(filled, np.clip(v, 0, 65535), d).astype(np.uint16)


def depth_fill(depth, mask=None, *, colour=None, variant="decompose", seed=1, backend="auto",
               png_scale=5000.0, progress=None, cancel=None, return_report=False, **params):
    """Repair a depth frame (paper 003): its missing pixels (0, NaN or inf,
    or non-zero in ``mask``) inside the capture are filled; those outside it
    (a camera's invalid margin) stay missing. A hole across a depth step is
    filled surface by surface (``edges="auto"``, the default, takes
    ``"layers"`` for depths and ``"across"``, paper 003's ramp, for
    ``values="disparity"``); ``colour``, the frame's registered (H, W, 3)
    uint8 image, parts the surfaces where its colour changes.

    depth: (H, W) uint16 (a depth PNG's values, ``png_scale`` per metre, 0
    missing) or float32 / float64 (NaN missing; a finite float64 that
    float32 cannot hold is refused). Returns a new array of the same dtype:
    uint16 keeps 0 where still missing, floats NaN; a filled uint16 depth
    is at least 1 and at most 65535. ``max_memory`` is checked from the
    shape before anything is copied.
    """
    progress, cancel = _progress(progress), _cancel(cancel)
    d = _array("depth", depth, (2,))
    _depth_dtype(d)
    if d.size == 0:
        _fail("usage", f"depth: shape {d.shape} is empty")
    m = None if mask is None else _mask_view(mask, d.shape)
    kw = _params(dict(params, variant=variant, seed=seed, backend=backend))
    _check(_relief.depth_fill_check_memory(*d.shape, kw))
    z = _depth_in(d, png_scale)
    m = None if m is None else _mask_bits(m)
    c = None if colour is None else _colour_view(colour, d.shape)
    (report,) = _check(_relief.depth_fill(z, m, c, kw, progress, cancel))
    filled = (d == 0) | (m != 0 if m is not None else False)
    out = _depth_out(d, z, filled, png_scale)
    return (out, _report(report, True)) if return_report else out


# --------------------------------------------------------------- occluders

Removed = namedtuple("Removed", "colour depth points mask")
Removed.__doc__ = """What remove_occluders returns: the colour (H, W, 3) uint8, the depth
(the input's dtype), the points (H, W, 3) float32 or None, and the mask
used (H, W) bool."""


def _rgbd(colour, depth, points, png_scale):
    """The frame's arrays for the extension: z float32 (NaN missing), rgb
    uint8 (H, W, 3), xyz float32 (H, W, 3) or None."""
    d = _array("depth", depth, (2,))
    rgb = _colour_view(colour, d.shape)
    if d.size == 0:
        _fail("usage", f"depth: shape {d.shape} is empty")
    z = _depth_in(d, png_scale)
    xyz = None
    if points is not None:
        xyz = _float32("points", _array("points", points, (3,)))
        if xyz.shape != rgb.shape[:2] + (3,):
            _fail("usage", f"points: shape {xyz.shape}, expected {rgb.shape[:2] + (3,)}")
    return d, z, xyz, np.array(rgb, order="C", copy=True)


def _views(views, shape):
    """views: [(colour (H, W, 3) uint8, pose (3, 4)[, intrinsics]), ...] as
    two lists: the colours, and each pose flattened with the view's
    intrinsics after it (0s: the frame's camera)."""
    colours, poses = [], []
    for k, view in enumerate(views or ()):
        try:
            colour, pose, *cam = view
        except (TypeError, ValueError):
            _fail("usage", f"views[{k}]: expected a (colour, pose) pair or a (colour, pose, "
                  "intrinsics) triple")
        if len(cam) > 1:
            _fail("usage", f"views[{k}]: {len(view)} items, expected (colour, pose[, intrinsics])")
        c = _array(f"views[{k}] colour", colour, (3,))
        own = bool(cam) and cam[0] is not None
        if c.dtype != np.uint8 or c.shape[2] < 3 or (not own and c.shape[:2] != tuple(shape)):
            _fail("usage", f"views[{k}] colour: {c.dtype} {c.shape}, expected uint8 "
                  f"{tuple(shape) + (3,)} (the frame's size; another with the view's intrinsics)")
        m = np.array(_array(f"views[{k}] pose", pose, (2,)), dtype=np.float64, order="C")
        if m.shape != (3, 4):
            _fail("usage", f"views[{k}] pose: shape {m.shape}, expected (3, 4): [R | t]")
        k4 = np.zeros(4)
        if own:
            k4 = np.asarray(cam[0], dtype=np.float64).ravel()
            if k4.shape != (4,):
                _fail("usage", f"views[{k}] intrinsics: {k4.shape[0]} values, expected 4: "
                      "fx, fy, cx, cy")
        colours.append(np.ascontiguousarray(c[:, :, :3]))
        poses.append(np.concatenate([m.ravel(), k4]))
    return colours, poses


def _intrinsics(params, intrinsics):
    if intrinsics is not None:
        params = dict(params, intrinsics=intrinsics)
    return params


def find_occluders(colour, depth, *, points=None, intrinsics=None, views=None,
                   png_scale=5000.0, seed=1, return_report=False, **params):
    """The occluders of an RGB-D frame (paper 004, section 2.1): the points
    in front of the background (planes found by RANSAC), grown by colour.

    colour: (H, W, 3) uint8 (RGBA's alpha ignored; grey repeated). depth:
    (H, W) uint16 (``png_scale`` per metre, 0 missing) or float (metres,
    NaN missing). points: (H, W, 3) an organised cloud's xyz (the camera is
    fitted to them), or None with ``intrinsics`` (fx, fy, cx, cy; default a
    Kinect's scaled to the width). views: registered neighbouring views,
    [(colour, pose)] or [(colour, pose, intrinsics)], pose (3, 4) [R | t]
    with x_view = R x + t (paper 004's eq. 2.1), intrinsics the view's fx,
    fy, cx, cy (then its colour may be of any size; without them the view
    is seen through the frame's camera, of its size). Returns an (H, W) bool mask, True on the occluders (and the
    report as a dict when ``return_report``).
    """
    _, z, xyz, rgb = _rgbd(colour, depth, points, png_scale)
    colours, poses = _views(views, z.shape)
    kw = _params(_intrinsics(dict(params, seed=seed), intrinsics))
    report, mask = _check(_relief.find_occluders(z, xyz, rgb, colours, poses, kw))
    mask = np.asarray(mask).reshape(z.shape).astype(bool)
    return (mask, _report(report, True)) if return_report else mask


def remove_occluders(colour, depth, mask=None, *, points=None, intrinsics=None, views=None,
                     png_scale=5000.0, seed=1, colour_params=None, depth_params=None,
                     cancel=None, return_report=False, **params):
    """The frame without its occluders: ``mask`` (or the one find_occluders
    finds with ``params``) filled in colour by image_fill and in depth by
    depth_fill on the residual about the background, so the points behind
    lie on the wall with its own roughness. Arguments as find_occluders;
    colour_params and depth_params go to the two fills. Returns a
    :class:`Removed` (and the report when ``return_report``); the pixels
    outside the mask keep their values. ``cancel`` (or :func:`cancel_all`,
    or Ctrl-C on the main thread) stops the two fills.
    """
    cancel = _cancel(cancel)
    d, z, xyz, rgb = _rgbd(colour, depth, points, png_scale)
    m = None if mask is None else _mask(mask, z.shape)
    colours, poses = _views(views, z.shape)
    kw = _params(_intrinsics(dict(params, seed=seed), intrinsics))
    # threads= bounds the two fills too, unless their own params say
    fills = {"threads": params["threads"]} if params.get("threads") is not None else {}
    report, used = _check(_relief.remove_occluders(
        z, xyz, rgb, m, colours, poses, kw,
        _params(dict(dict(fills, **(colour_params or {})), seed=seed)),
        _params(dict(dict(fills, **(depth_params or {})), seed=seed)), cancel))
    used = np.asarray(used).reshape(z.shape).astype(bool)
    out = _depth_out(d, z, used, png_scale)
    result = Removed(rgb, out, xyz, used)
    return (result, _report(report, True)) if return_report else result


# ------------------------------------------------------------------ meshes

def _vertices(name, vertices):
    v = _array(name, vertices, (2,))
    if v.shape[0] < 1 or v.shape[1:] != (3,):
        _fail("usage", f"{name}: shape {v.shape}, expected (N, 3) with N >= 1")
    if not np.issubdtype(v.dtype, np.number):
        _fail("usage", f"{name}: dtype {v.dtype}, expected numbers")
    v = np.ascontiguousarray(v, dtype=np.float64)
    bad = np.flatnonzero(~np.isfinite(v).all(axis=1))
    if bad.size:
        _fail("range", f"{name}: vertex {bad[0]} is not finite ({v[bad[0]].tolist()})")
    return v


def _faces(faces, n):
    if faces is None:
        return None
    f = _array("faces", faces, (2,))
    if f.shape[0] == 0:
        return None
    if f.shape[1:] != (3,) or not np.issubdtype(f.dtype, np.integer):
        _fail("usage", f"faces: shape {f.shape} dtype {f.dtype}, expected (M, 3) integers")
    if f.min() < 0 or f.max() >= n:
        _fail("range", f"faces: index {int(f.min() if f.min() < 0 else f.max())} out of "
              f"range for {n} vertices")
    return np.ascontiguousarray(f, dtype=np.uint32)


def _per_vertex(name, value, n, dtype):
    if value is None:
        return None
    a = _array(name, value, (2,))
    if a.shape != (n, 3):
        _fail("usage", f"{name}: shape {a.shape}, expected ({n}, 3)")
    if name == "colours" and a.dtype == np.uint8:
        a = a / 255.0
    with np.errstate(over="ignore"):  # checked below, as the engine gets them
        a = np.ascontiguousarray(a, dtype=dtype)
    if name == "colours":
        if not np.all(np.isfinite(a)) or a.min() < 0 or a.max() > 1:
            _fail("range", "colours: expected floats in [0, 1] (or uint8)")
    elif not np.all(np.isfinite(a)):
        _fail("range", f"{name}: not finite (or over {np.dtype(dtype).name}'s range)")
    return a


def _mesh_result(result, return_report):
    """A mesh engine's (vertices, faces, colours, labels), and its report
    when asked for."""
    report, arrays = _check(result)
    out = _mesh(arrays)
    mesh = (out.vertices, out.faces, out.colours, out.labels)
    return (mesh, _report(report, True)) if return_report else mesh


def complete_mesh(vertices, faces, colours=None, *, base="auto", seed=1, backend="auto",
                  progress=None, cancel=None, return_report=False, **params):
    """Complete a capture with relief and colour grown from it (papers 000
    and 001): over a fitted plane, sphere or cylinder, or the capture's own
    smoothed surface (``base``). Returns (vertices, faces, colours, labels):
    the capture's vertices first (label 0), then the new ones (label 1);
    colours None when the capture has none."""
    progress, cancel = _progress(progress), _cancel(cancel)
    v = _vertices("vertices", vertices)
    f = _faces(faces, len(v))
    c = _per_vertex("colours", colours, len(v), np.float32)
    kw = _params(dict(params, base=base, seed=seed, backend=backend))
    return _mesh_result(_relief.complete_mesh(v, f, c, kw, progress, cancel), return_report)


def fill_mesh_holes(vertices, faces, colours=None, *, resolution=None, seed=1, backend="auto",
                    progress=None, cancel=None, return_report=False, **params):
    """Fill a mesh's holes through the six depth images of its bounding box
    (paper 003, ``relief depth-fill`` on a mesh): the holes the hole model
    fills (``max_hole``, ``hole_mask="ball:X,Y,Z,R"``; a vessel's mouth and a
    scan's border stay open, a notch a ball selects in a border is closed by
    its chord) are each closed by a faired patch made from the rim's own
    edges, given the repaired solid's relief where it lies within 3 voxels;
    ``skin=True`` zips the solid's skin into the rims instead (paper 003's
    surface); ``solid=True`` returns the whole closed solid.
    ``resolution``: voxels along the box's longest side. Returns (vertices,
    faces, colours, labels): the input's first, in order, then the patches'
    (label 1)."""
    progress, cancel = _progress(progress), _cancel(cancel)
    v = _vertices("vertices", vertices)
    f = _faces(faces, len(v))
    if f is None:
        _fail("usage", "faces: a mesh's holes need its triangles")
    c = _per_vertex("colours", colours, len(v), np.float32)
    kw = _params(dict(params, resolution=resolution, seed=seed, backend=backend))
    return _mesh_result(_relief.fill_mesh_holes(v, f, c, kw, progress, cancel), return_report)


def complete_points(points, colours=None, normals=None, *, faces=None, seed=1,
                    progress=None, cancel=None, return_report=False, **params):
    """Fill the holes of a point set (paper 002): the holes the hole model
    fills (``max_hole``, ``hole_mask="ball:X,Y,Z,R"``) get new points on a
    smooth base with detail copied from the capture. ``faces`` (a mesh's
    triangles) make its boundary loops the holes. Returns (points, colours,
    labels): the input's points first (label 0), then the new ones."""
    progress, cancel = _progress(progress), _cancel(cancel)
    v = _vertices("points", points)
    f = _faces(faces, len(v))
    c = _per_vertex("colours", colours, len(v), np.float32)
    n = _per_vertex("normals", normals, len(v), np.float64)
    kw = _params(dict(params, seed=seed))
    report, arrays = _check(_relief.complete_points(v, f, c, n, None, kw, progress, cancel))
    out = _mesh(arrays)
    result = (out.vertices, out.colours, out.labels)
    return (result, _report(report, True)) if return_report else result


# ------------------------------------------------------------------- files

def read_mesh(path):
    """Read a PLY, OBJ, OFF or STL mesh (or a PLY point cloud), repaired as
    relief reads every mesh: a :class:`Mesh`."""
    (arrays,) = _check(_relief.read_mesh(os.fspath(path)))
    return _mesh(arrays)


def write_mesh(path, vertices, faces=None, colours=None, labels=None, *, ascii=False):
    """Write a mesh by the path's extension (PLY keeps colour and labels),
    atomically: the file is whole or untouched."""
    v = _vertices("vertices", vertices)
    f = _faces(faces, len(v))
    c = _per_vertex("colours", colours, len(v), np.float32)
    lab = None
    if labels is not None:
        lab = _array("labels", labels, (1,))
        if lab.shape != (len(v),):
            _fail("usage", f"labels: shape {lab.shape}, expected ({len(v)},)")
        if lab.dtype != np.bool_ and not np.issubdtype(lab.dtype, np.number):
            _fail("usage", f"labels: dtype {lab.dtype}, expected integers")
        if lab.dtype != np.bool_:  # what uint8 cannot hold would wrap or truncate
            bad = np.flatnonzero(~((lab >= 0) & (lab <= 255) & (lab == np.round(lab))))
            if bad.size:
                _fail("range", f"labels[{bad[0]}] = {lab[bad[0]]}: expected an integer in "
                      "0..255 (0 captured, 1 added)")
        lab = np.ascontiguousarray(lab, dtype=np.uint8)
    _check(_relief.write_mesh(os.fspath(path), v, f, c, lab, bool(ascii)))


def read_image(path):
    """Read a PNG or JPEG: (H, W) for grey, else (H, W, C); uint8 or uint16."""
    (img,) = _check(_relief.read_image(os.fspath(path)))
    return img[:, :, 0] if img.shape[2] == 1 else img


def write_image(path, image):
    """Write (H, W) or (H, W, C) uint8 or uint16 samples as PNG or JPEG by
    the path's extension (JPEG: 8 bits, no alpha), atomically."""
    img = _array("image", image, (2, 3))
    img = img[:, :, None] if img.ndim == 2 else img
    if img.dtype not in (np.uint8, np.uint16) or not 1 <= img.shape[2] <= 4:
        _fail("usage", f"image: dtype {img.dtype} with {img.shape[2]} channels, expected "
              "uint8 or uint16 with 1 to 4")
    _check(_relief.write_image(os.fspath(path), np.ascontiguousarray(img)))


def write_depth(path, depth, *, format="pfm", png_scale=0.0):
    """Write an (H, W) depth frame (NaN missing) as a PFM (format "pfm") or a
    16-bit PNG of depth x png_scale ("png16"; 0: 5000 per metre), atomically."""
    z = _array("depth", depth, (2,))
    if format not in ("pfm", "png16"):
        _fail("usage", f"format {format!r}: expected 'pfm' or 'png16'")
    _check(_relief.write_depth(os.fspath(path), _float32("depth", z, zero_missing=True),
                               format, float(png_scale)))


_DEPTH_ENCODINGS = ("auto", "png", "pgm", "nyu", "sun")


def read_depth(path, png_scale=0.0, encoding="auto"):
    """Read a depth frame (organised PCD, PFM, 16-bit PNG or PGM): (H, W)
    float32, metres for a PCD, PNG or PGM (values / png_scale, 0: 5000), NaN
    missing. encoding says how a depth image's samples are depths, as
    ``relief occluders --depth-format`` does: "auto" (by the first bytes),
    "png", "pgm" (big-endian), "nyu" (NYU Depth v2's raw disparity PGM,
    stored little-endian) or "sun" (SUN RGB-D's PNG, bits rotated,
    millimetres unless png_scale)."""
    if encoding not in _DEPTH_ENCODINGS:
        raise ValueError("encoding %r: expected one of %s" % (encoding, ", ".join(_DEPTH_ENCODINGS)))
    z, *_ = _check(_relief.read_depth(os.fspath(path), float(png_scale), encoding))
    return z


Frame = namedtuple("Frame", "depth colour points")
Frame.__doc__ = """What read_pcd returns: the depth (H, W) float32 (metres, NaN
missing), the colour (H, W, 3) uint8 or None (no rgb field) and the points
(H, W, 3) float32 (x, y, z in the camera's coordinates, NaN missing): the
three arguments find_occluders and remove_occluders take."""


def read_pcd(path):
    """Read an organised PCD (ascii, binary or binary_compressed, as
    ``relief occluders`` reads one): a :class:`Frame` of its depth, colour
    and points, so that ``find_occluders(f.colour, f.depth,
    points=f.points)`` runs on it. Another depth file (PNG, PGM, PFM) has no
    points: read it with :func:`read_depth`."""
    z, rgb, xyz, fmt = _check(_relief.read_depth(os.fspath(path), 0.0, "auto"))
    if not fmt.startswith("pcd"):
        _fail("usage", f"{os.fspath(path)} is a {fmt} file, not a PCD: read its depth with "
              "read_depth (and its colour from its own image)")
    shape = z.shape
    colour = None if rgb is None else np.asarray(rgb).reshape(shape + (3,))
    points = np.asarray(xyz).reshape(shape + (3,))
    return Frame(z, colour, points)


def devices():
    """The OpenCL devices, as ``relief devices`` lists them: a list of dicts."""
    (found,) = _check(_relief.devices())
    return list(found)


def parameters(engine):
    """An engine's parameters ("image_fill", "depth_fill", "fill_mesh_holes",
    "complete_mesh", "complete_points", "find_occluders", "remove_occluders"):
    {name: (value form, help)}."""
    table = _relief.param_table(engine)
    if not table:
        _fail("usage", f"unknown engine {engine!r}: expected image_fill, depth_fill, "
              "fill_mesh_holes, complete_mesh, complete_points, find_occluders or "
              "remove_occluders")
    return dict(table)
