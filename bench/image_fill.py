#!/usr/bin/env python3
"""relief's image hole filling against the peers a user would pick instead.

For each image of IMAGES_DIR (the photographs coffee, chelsea, astronaut,
rocket and the textures brick, grass, gravel) holes are cut where the truth
is known:
  disc            radius 1/16 of the shorter side, at the centre
  rect_centre     a rectangle of 12 % of the area, the image's aspect, centred
  rect_off        the same rectangle off-centre, over a structured part
                  (OFF_CENTRE below: the cup's handle and saucer, the cat's
                  eye, the shuttle, the left towers; the textures' top left)
  scratch_lines   two crossing straight lines, 5 pixels wide
  scratch_curve   one and a half periods of a sine across the image, 5 pixels
The masks are drawn by OpenCV from fixed fractions of the image's size: the
same on every run. Every method gets the image with the hole's pixels set to
0 (written as OUT/<image>_<hole>_in.png) and the mask, so none can read the
removed pixels; the peers' outputs get the known pixels pasted back, as
relief writes them back itself.

Methods (each a peer is run in this process, never linked into relief):
  relief default  relief image-fill with its defaults (--method's default);
                  only where the binary has --method
  relief jain     relief image-fill --method jain; without --method in the
                  binary, the binary's only method, run without the flag
  opencv telea    cv2.inpaint, INPAINT_TELEA, radius 3
  opencv ns       cv2.inpaint, INPAINT_NS (Navier-Stokes), radius 3
  opencv fsr_fast cv2.xphoto.inpaint, INPAINT_FSR_FAST (frequency selective
                  reconstruction); colour images in CIELab, as its docs ask
  opencv fsr_best the same, INPAINT_FSR_BEST: only with --fsr-best (about
                  40 s on each large rectangle)
  opencv shiftmap cv2.xphoto.inpaint, INPAINT_SHIFTMAP, CIELab likewise
  patchmatch      pypatchmatch's patch_match.inpaint, patch radius 5
                  (11 x 11 patches), random seed --seed
  resynthesizer   the GIMP Resynthesizer's engine (PyPI resynthesizer's
                  libresynthesizer, imageSynth2) with the settings GIMP's
                  Filters > Enhance > Heal selection passes by default: the
                  corpus is a 50-pixel band around the hole (the selection
                  grown by 50, the selection cut out: here a dilation by a
                  disc of radius 50), random filling order (use_border 1),
                  no tiling, map weight 0, sensitivity to outliers 0.117,
                  16 neighbours, 500 probes

Measures, each over the hole's pixels only:
  rms      root mean square error against the removed pixels, 0..255, over
           pixels and channels
  ssim     the mean of scikit-image's SSIM map over the hole's pixels
           (Wang et al.'s settings: Gaussian window sigma 1.5, population
           covariance, data range 255; colour: the channels' mean). Windows
           near the hole's edge reach known pixels, which every method
           returns unchanged, so a thin scratch scores higher than a large
           hole with the same error
  texture  the mean 5 x 5 local standard deviation over the hole, divided
           by the truth's (1: as rough as the truth; a blur is below 1)
  seconds  relief: the median of REPEAT whole runs with the default backend
           (process start-up and PNG input/output included); peers: one
           call in this process (no file input/output)
relief's default and jain rows also say whether --backend scalar and
--backend host wrote byte-identical files (cmp).

Writes OUT/image_fill.csv (one row per hole and method) and
OUT/image_fill.md (medians per hole class and method); with --figures DIR,
one picture strip per hole, DIR/image_fill_<image>_<hole>.png: the input
with the hole in magenta, each method, the truth, each panel 200 pixels
high and labelled.
  bench/image_fill.py RELIEF IMAGES_DIR OUT [--repeat N] [--only IMAGE,...]
                      [--figures DIR] [--fsr-best] [--seed N]
"""
import argparse
import csv
import ctypes
import os
import statistics
import subprocess
import sys
import time

import cv2
import numpy as np
from skimage.metrics import structural_similarity

IMAGES = ["coffee.png", "chelsea.png", "astronaut.png", "rocket.jpg",
          "brick.png", "grass.png", "gravel.png"]
# The off-centre rectangle's centre, as fractions of width and height.
OFF_CENTRE = {"coffee": (0.32, 0.66), "chelsea": (0.32, 0.38),
              "astronaut": (0.80, 0.26), "rocket": (0.20, 0.50),
              "brick": (0.27, 0.27), "grass": (0.27, 0.27), "gravel": (0.27, 0.27)}
CLASSES = {"disc": "disc", "rect_centre": "large rectangle", "rect_off": "large rectangle",
           "scratch_lines": "scratch", "scratch_curve": "scratch"}
SCRATCH = 5


def holes(stem, w, h):
    """[(name, mask)], mask uint8 255 = hole."""
    out = []
    m = np.zeros((h, w), np.uint8)
    cv2.circle(m, (w // 2, h // 2), min(w, h) // 16, 255, -1)
    out.append(("disc", m))
    rw, rh = round(w * 0.12 ** 0.5), round(h * 0.12 ** 0.5)
    for name, (fx, fy) in (("rect_centre", (0.5, 0.5)), ("rect_off", OFF_CENTRE[stem])):
        x0 = min(max(round(fx * w - rw / 2), 0), w - rw)
        y0 = min(max(round(fy * h - rh / 2), 0), h - rh)
        m = np.zeros((h, w), np.uint8)
        m[y0:y0 + rh, x0:x0 + rw] = 255
        out.append((name, m))
    m = np.zeros((h, w), np.uint8)
    cv2.line(m, (round(0.10 * w), round(0.20 * h)), (round(0.90 * w), round(0.75 * h)), 255, SCRATCH)
    cv2.line(m, (round(0.15 * w), round(0.85 * h)), (round(0.80 * w), round(0.10 * h)), 255, SCRATCH)
    out.append(("scratch_lines", m))
    m = np.zeros((h, w), np.uint8)
    x = np.linspace(0.05 * w, 0.95 * w, 400)
    y = h * (0.5 + 0.28 * np.sin(3 * np.pi * (x - 0.05 * w) / (0.9 * w)))
    cv2.polylines(m, [np.round(np.stack([x, y], 1)).astype(np.int32)], False, 255, SCRATCH)
    out.append(("scratch_curve", m))
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
    colour = truth.ndim == 3
    _, smap = structural_similarity(truth, result, data_range=255, gaussian_weights=True,
                                    sigma=1.5, use_sample_covariance=False, full=True,
                                    channel_axis=2 if colour else None)
    if colour:
        smap = smap.mean(axis=2)
    ssim = float(smap[sel].mean())
    tex = float(local_sd(result)[sel].mean() / max(local_sd(truth)[sel].mean(), 1e-9))
    return rms, ssim, tex


# -- relief ---------------------------------------------------------------

def relief_has_method(relief):
    r = subprocess.run([relief, "image-fill", "--help"], capture_output=True, text=True)
    return "--method" in r.stdout + r.stderr


def run_relief(relief, src, mask_path, out, extra):
    t0 = time.perf_counter()
    r = subprocess.run([relief, "image-fill", src, "--mask", mask_path, "-o", out, "--quiet"]
                       + extra, capture_output=True, text=True)
    t = time.perf_counter() - t0
    if r.returncode != 0:
        raise RuntimeError("relief %s failed: %s" % (" ".join(extra), r.stderr.strip()))
    return t


def relief_method(relief, src, mask_path, stem_out, extra, repeat):
    """(median seconds, result, scalar and host byte-identical)."""
    out = stem_out + ".png"
    times = [run_relief(relief, src, mask_path, out, extra) for _ in range(repeat)]
    result = cv2.imread(out, cv2.IMREAD_UNCHANGED)
    outs = []
    for backend in ("scalar", "host"):
        o = "%s_%s.png" % (stem_out, backend)
        run_relief(relief, src, mask_path, o, extra + ["--backend", backend])
        outs.append(o)
    with open(outs[0], "rb") as a, open(outs[1], "rb") as b:
        same = a.read() == b.read()
    for o in outs:
        os.remove(o)
    return statistics.median(times), result, same


# -- peers ----------------------------------------------------------------

def opencv_inpaint(flag):
    return lambda img, mask: cv2.inpaint(img, mask, 3, flag)


def xphoto(flag):
    def run(img, mask):
        src = cv2.cvtColor(img, cv2.COLOR_BGR2Lab) if img.ndim == 3 else img
        dst = np.zeros_like(src)
        cv2.xphoto.inpaint(src, 255 - mask, dst, flag)  # its mask: non-zero = known
        return cv2.cvtColor(dst, cv2.COLOR_Lab2BGR) if img.ndim == 3 else dst
    return run


def patchmatch(seed):
    from patchmatch import patch_match

    if not patch_match.patchmatch_available:
        raise RuntimeError("pypatchmatch's native library did not load")

    def run(img, mask):
        patch_match.set_random_seed(seed)
        src = img if img.ndim == 3 else np.dstack([img] * 3)
        out = patch_match.inpaint(np.ascontiguousarray(src), mask, patch_size=5)
        return out if img.ndim == 3 else out[:, :, 0].copy()
    return run


class _ImageBuffer(ctypes.Structure):
    _fields_ = [("data", ctypes.POINTER(ctypes.c_ubyte)), ("width", ctypes.c_uint),
                ("height", ctypes.c_uint), ("rowBytes", ctypes.c_size_t)]


class _Params(ctypes.Structure):
    _fields_ = [("isMakeSeamlesslyTileableHorizontally", ctypes.c_int),
                ("isMakeSeamlesslyTileableVertically", ctypes.c_int),
                ("matchContextType", ctypes.c_int), ("mapWeight", ctypes.c_double),
                ("sensitivityToOutliers", ctypes.c_double), ("patchSize", ctypes.c_uint),
                ("maxProbeCount", ctypes.c_uint)]


def resynthesizer_heal(sampling=50):
    """GIMP's Heal selection through the Resynthesizer engine's C entry
    imageSynth2(image, target mask, corpus mask, format, parameters, ...)."""
    import resynthesizer

    lib = ctypes.CDLL(os.path.join(os.path.dirname(resynthesizer.__file__), "bin",
                                   "libresynthesizer.so"))
    progress = ctypes.CFUNCTYPE(None, ctypes.c_int, ctypes.c_void_p)
    synth = lib.imageSynth2
    synth.argtypes = [ctypes.POINTER(_ImageBuffer)] * 3 + [
        ctypes.c_int, ctypes.POINTER(_Params), progress, ctypes.c_void_p,
        ctypes.POINTER(ctypes.c_int)]
    synth.restype = ctypes.c_int
    # plug_in_resynthesizer(..., 0, 0, use_border 1, corpus, -1, -1, 0.0, 0.117, 16, 500)
    params = _Params(0, 0, 1, 0.0, 0.117, 16, 500)
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * sampling + 1, 2 * sampling + 1))
    callback = progress(lambda percent, context: None)

    def buf(a):
        return _ImageBuffer(a.ctypes.data_as(ctypes.POINTER(ctypes.c_ubyte)),
                            a.shape[1], a.shape[0], a.strides[0])

    def run(img, mask):
        out = np.ascontiguousarray(img.copy())
        target = np.ascontiguousarray(mask)
        corpus = cv2.dilate(mask, disc)
        corpus[mask > 0] = 0
        cancel = ctypes.c_int(0)
        fmt = 0 if img.ndim == 3 else 2  # T_RGB (channel order is immaterial), T_Gray
        err = synth(ctypes.byref(buf(out)), ctypes.byref(buf(target)), ctypes.byref(buf(corpus)),
                    fmt, ctypes.byref(params), callback, None, ctypes.byref(cancel))
        if err:
            raise RuntimeError("imageSynth2 returned %d" % err)
        return out
    return run


def peers(args):
    """[(method, function or the error that made it unavailable)]."""
    out = [("opencv telea", opencv_inpaint(cv2.INPAINT_TELEA)),
           ("opencv ns", opencv_inpaint(cv2.INPAINT_NS))]
    if hasattr(cv2, "xphoto"):
        out.append(("opencv fsr_fast", xphoto(cv2.xphoto.INPAINT_FSR_FAST)))
        if args.fsr_best:
            out.append(("opencv fsr_best", xphoto(cv2.xphoto.INPAINT_FSR_BEST)))
        out.append(("opencv shiftmap", xphoto(cv2.xphoto.INPAINT_SHIFTMAP)))
    else:
        out.append(("opencv xphoto", "cv2.xphoto missing (opencv-contrib-python-headless)"))
    for name, make in (("patchmatch", lambda: patchmatch(args.seed)),
                       ("resynthesizer", resynthesizer_heal)):
        try:
            out.append((name, make()))
        except Exception as e:  # a peer that cannot load is reported, not fatal
            out.append((name, "%s: %s" % (type(e).__name__, e)))
    return out


# -- outputs --------------------------------------------------------------

def panel(img, label, height=200):
    if img.ndim == 2:
        img = cv2.cvtColor(img, cv2.COLOR_GRAY2BGR)
    w = round(img.shape[1] * height / img.shape[0])
    p = cv2.resize(img, (w, height), interpolation=cv2.INTER_AREA)
    band = np.full((22, w, 3), 255, np.uint8)
    cv2.putText(band, label, (4, 16), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (0, 0, 0), 1, cv2.LINE_AA)
    return np.vstack([band, p])


def strip(path, holed, mask, results, truth):
    shown = cv2.cvtColor(holed, cv2.COLOR_GRAY2BGR) if holed.ndim == 2 else holed.copy()
    shown[mask > 0] = (255, 0, 255)
    panels = [panel(shown, "input")] + [panel(r, m) for m, r in results] + [panel(truth, "truth")]
    gap = np.full((panels[0].shape[0], 4, 3), 255, np.uint8)
    row = [panels[0]]
    for p in panels[1:]:
        row += [gap, p]
    cv2.imwrite(path, np.hstack(row))


def median_table(rows, methods):
    lines = ["| hole class | method | holes | RMS | SSIM | texture | seconds |",
             "| --- | --- | --- | --- | --- | --- | --- |"]
    for cls in ("disc", "large rectangle", "scratch"):
        for m in methods:
            sel = [r for r in rows if r["class"] == cls and r["method"] == m]
            if not sel:
                continue
            med = {k: statistics.median(float(r[k]) for r in sel)
                   for k in ("rms", "ssim", "texture", "seconds")}
            lines.append("| %s | %s | %d | %.1f | %.3f | %.2f | %.2f |" % (
                cls, m, len(sel), med["rms"], med["ssim"], med["texture"], med["seconds"]))
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("relief")
    ap.add_argument("images")
    ap.add_argument("out")
    ap.add_argument("--repeat", type=int, default=3, help="relief's runs per hole (median)")
    ap.add_argument("--only", default="", help="images by stem, comma-separated")
    ap.add_argument("--figures", default="", help="write the picture strips here")
    ap.add_argument("--fsr-best", action="store_true", help="also INPAINT_FSR_BEST (slow)")
    ap.add_argument("--seed", type=int, default=1, help="PatchMatch's random seed")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    if args.figures:
        os.makedirs(args.figures, exist_ok=True)
    names = IMAGES
    if args.only:
        want = set(args.only.split(","))
        names = [n for n in IMAGES if os.path.splitext(n)[0] in want or n in want]
        if not names:
            raise SystemExit("bench: --only %s matches none of %s" % (args.only, ", ".join(IMAGES)))

    has_method = relief_has_method(args.relief)
    if has_method:
        relief_runs = [("relief default", []), ("relief jain", ["--method", "jain"])]
    else:
        print("bench: %s image-fill has no --method: its one method is run as relief jain"
              % args.relief, flush=True)
        relief_runs = [("relief jain", [])]
    others = peers(args)
    for m, f in others:
        if isinstance(f, str):
            print("bench: %s unavailable: %s" % (m, f), flush=True)
    others = [(m, f) for m, f in others if not isinstance(f, str)]
    methods = [m for m, _ in relief_runs] + [m for m, _ in others]

    rows = []
    for name in names:
        path = os.path.join(args.images, name)
        truth = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if truth is None:
            raise SystemExit("bench: cannot read %s" % path)
        h, w = truth.shape[:2]
        stem = os.path.splitext(name)[0]
        for hole, mask in holes(stem, w, h):
            base = os.path.join(args.out, "%s_%s" % (stem, hole))
            holed = truth.copy()
            holed[mask > 0] = 0
            cv2.imwrite(base + "_in.png", holed)
            cv2.imwrite(base + "_mask.png", mask)
            results = []
            for method, extra in relief_runs:
                t, r, same = relief_method(args.relief, base + "_in.png", base + "_mask.png",
                                           "%s_%s" % (base, method.replace(" ", "_")), extra,
                                           args.repeat)
                results.append((method, t, r, "yes" if same else "NO", args.repeat))
            for method, f in others:
                t0 = time.perf_counter()
                try:
                    r = f(holed, mask)
                except Exception as e:
                    print("bench: %s failed on %s %s: %s" % (method, stem, hole, e), flush=True)
                    continue
                t = time.perf_counter() - t0
                # As relief does, and as a user would: the known pixels back
                # (xphoto's CIELab round trip and shiftmap change a few).
                r[mask == 0] = truth[mask == 0]
                cv2.imwrite("%s_%s.png" % (base, method.replace(" ", "_")), r)
                results.append((method, t, r, "", 1))
            for method, t, r, same, runs in results:
                rms, ssim, tex = measure(r, truth, mask)
                rows.append({"image": name, "hole": hole, "class": CLASSES[hole],
                             "pixels": int((mask > 0).sum()), "method": method,
                             "seconds": "%.3f" % t, "runs": runs, "rms": "%.2f" % rms,
                             "ssim": "%.4f" % ssim, "texture": "%.3f" % tex,
                             "scalar_host_identical": same})
                print("%-14s %-13s %-16s %8.3f s  rms %6.2f  ssim %.3f  texture %.3f%s" %
                      (name, hole, method, t, rms, ssim, tex,
                       "  scalar=host: " + same if same else ""), flush=True)
            if args.figures:
                strip(os.path.join(args.figures, "image_fill_%s_%s.png" % (stem, hole)),
                      holed, mask, [(m, r) for m, _, r, _, _ in results], truth)

    with open(os.path.join(args.out, "image_fill.csv"), "w", newline="") as f:
        wr = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        wr.writeheader()
        wr.writerows(rows)
    checked = [r for r in rows if r["scalar_host_identical"]]
    md = ["# Image hole filling: medians per hole class and method", "",
          "%d images (%s), %d holes; relief %s; relief's seconds: median of %d runs, "
          "peers: one call. RMS over the hole (0..255, lower is better), SSIM: mean of the "
          "SSIM map over the hole (higher is better), texture: local roughness over the "
          "truth's (1 is the truth's)." % (
              len(names), ", ".join(os.path.splitext(n)[0] for n in names),
              len({(r["image"], r["hole"]) for r in rows}),
              "with --method (default and jain)" if has_method else
              "without --method (its one method, as relief jain)", args.repeat), ""]
    md += median_table(rows, methods)
    md += ["", "relief --backend scalar and --backend host byte-identical: %d of %d runs." % (
        sum(r["scalar_host_identical"] == "yes" for r in checked), len(checked))]
    with open(os.path.join(args.out, "image_fill.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print("\n".join(md[4:]))


if __name__ == "__main__":
    main()
