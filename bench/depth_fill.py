"""relief depth-fill against OpenCV's inpainting on real depth frames.

Holes are cut where the frame is valid, so the removed depths are the
truth: a disc, a 5-pixel scratch and a rectangle in office1.pcd (a Kinect-
class frame: flat walls, a door, furniture) and in motorcycle_disp.pfm (a
Middlebury disparity: a textured machine). relief runs the three variants
on both scorers (scalar, OpenCL: time, and whether the bytes agree);
OpenCV's Telea and Navier-Stokes run on the same float image, handed over
in thousandths (OpenCV's float inpainting returns noise on values of a few
units: a plane at 2..3 m came back with +-2 m spikes), every missing pixel
masked. Every output is measured by relief's own code (depth_bench_tool
measure): RMS over the cut pixels, the slope jump at their rim over the
capture's own second difference, and the roughness ratio (mean |second
difference| inside the holes, filled over truth: 1 keeps the texture,
near 0 is a smooth membrane).

  depth_fill.py RELIEF TOOL DEPTH_DIR OUT [--repeat N]
"""
import csv, json, os, statistics, subprocess, sys, time
import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfm import read_pfm, write_pfm  # noqa: E402

relief, tool, depth, out = sys.argv[1:5]
repeat = int(sys.argv[sys.argv.index("--repeat") + 1]) if "--repeat" in sys.argv else 1


def holes(shape, cx, cy, rect):
    """A disc of radius 24, a 5-pixel scratch, a rectangle (x, y, w, h)."""
    h, w = shape
    disc = np.zeros(shape, np.uint8)
    cv2.circle(disc, (cx, cy), 24, 255, -1)
    scratch = np.zeros(shape, np.uint8)
    cv2.line(scratch, (w // 6, h // 3), (w * 5 // 6, h * 2 // 3), 255, 5)
    box = np.zeros(shape, np.uint8)
    x, y, rw, rh = rect
    box[y:y + rh, x:x + rw] = 255
    return {"disc": disc, "scratch": scratch, "rect": box}


def run(args):
    """Run a command `repeat` times; the median wall time."""
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(args, check=True, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def measure(filled, truth, mask):
    r = subprocess.run([tool, "measure", filled, truth, mask], check=True,
                       capture_output=True, text=True)
    return json.loads(r.stdout)


frames = {
    "office1": (os.path.join(depth, "office1.pcd"), 320, 150, (430, 300, 48, 36)),
    "motorcycle": (os.path.join(depth, "motorcycle_disp.pfm"), 420, 260, (260, 320, 70, 50)),
}
os.makedirs(out, exist_ok=True)
rows = []
for name, (src, cx, cy, rect) in frames.items():
    base = os.path.join(out, name)
    subprocess.run([tool, "pfm", src, base + ".pfm"], check=True)
    truth = read_pfm(base + ".pfm")
    for hole, m in holes(truth.shape, cx, cy, rect).items():
        case = "%s_%s" % (base, hole)
        cut = (m > 0) & np.isfinite(truth)
        cv2.imwrite(case + "_mask.png", m)
        write_pfm(case + "_maskf.pfm", np.where(cut, 1.0, 0.0).astype(np.float32))
        inp = np.where(m > 0, np.nan, truth).astype(np.float32)
        write_pfm(case + "_in.pfm", inp)
        for variant in ("plain", "haar", "decompose"):
            outs = {}
            for backend in ("scalar", "opencl"):
                o = "%s_%s_%s.pfm" % (case, variant, backend)
                secs = run([relief, "depth-fill", case + "_in.pfm", "-o", o, "--variant",
                            variant, "--backend", backend, "--quiet"])
                outs[backend] = (o, secs)
            same = open(outs["scalar"][0], "rb").read() == open(outs["opencl"][0], "rb").read()
            r = measure(outs["scalar"][0], base + ".pfm", case + "_maskf.pfm")
            rows.append(dict(frame=name, hole=hole, method="relief " + variant,
                             seconds=round(outs["scalar"][1], 3),
                             opencl_seconds=round(outs["opencl"][1], 3),
                             identical=int(same), pixels=r["compared"],
                             rms=r["rms"], slope_jump=r["slope_jump"],
                             truth_slope_jump=r["truth_slope_jump"],
                             roughness=r["roughness_ratio"]))
        # OpenCV on the same float image, in thousandths, every missing
        # pixel masked (it needs a value for each); outside the capture
        # stays missing as relief leaves it.
        miss = ~np.isfinite(inp)
        src_mm = np.where(miss, 0, inp * 1000.0).astype(np.float32)
        for method, flag in (("telea", cv2.INPAINT_TELEA), ("ns", cv2.INPAINT_NS)):
            t = time.perf_counter()
            f = cv2.inpaint(src_mm, miss.astype(np.uint8), 5, flag) / 1000.0
            secs = time.perf_counter() - t
            f = np.where(miss & ~(m > 0) & ~np.isfinite(truth), np.nan, f)
            o = "%s_%s.pfm" % (case, method)
            write_pfm(o, f.astype(np.float32))
            r = measure(o, base + ".pfm", case + "_maskf.pfm")
            rows.append(dict(frame=name, hole=hole, method="opencv " + method,
                             seconds=round(secs, 3), opencl_seconds="", identical="",
                             pixels=r["compared"], rms=r["rms"],
                             slope_jump=r["slope_jump"],
                             truth_slope_jump=r["truth_slope_jump"],
                             roughness=r["roughness_ratio"]))
        for row in rows[-5:]:
            print("%-10s %-7s %-16s %6.2f s  RMS %.4g  slope jump %.2f (truth %.2f)  "
                  "roughness %.2f" % (row["frame"], row["hole"], row["method"], row["seconds"],
                                      row["rms"], row["slope_jump"], row["truth_slope_jump"],
                                      row["roughness"]), flush=True)

with open(os.path.join(out, "depth_fill.csv"), "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

# Pictures for the README: the office disc and the motorcycle rectangle,
# cropped around the hole at 2x, one colour map per crop (the truth's 1st
# to 99th percentile), missing pixels black.
def picture(name, hole, cx, cy, half):
    case = os.path.join(out, "%s_%s" % (name, hole))
    truth = read_pfm(os.path.join(out, name + ".pfm"))
    crops = {"hole": read_pfm(case + "_in.pfm"), "relief": read_pfm(case + "_decompose_scalar.pfm"),
             "telea": read_pfm(case + "_telea.pfm"), "truth": truth}
    sl = np.s_[cy - half:cy + half, cx - half:cx + half]
    ok = np.isfinite(truth[sl])
    lo, hi = np.percentile(truth[sl][ok], [1, 99])
    for what, d in crops.items():
        v = np.clip((d[sl] - lo) / (hi - lo), 0, 1)
        im = cv2.applyColorMap((np.nan_to_num(v) * 255).astype(np.uint8), cv2.COLORMAP_TURBO)
        im[~np.isfinite(d[sl])] = 0
        im = cv2.resize(im, None, fx=2, fy=2, interpolation=cv2.INTER_NEAREST)
        cv2.imwrite(os.path.join(out, "depthfill_%s_%s.png" % (name, what)), im)


picture("office1", "disc", 320, 150, 48)
picture("motorcycle", "rect", 295, 345, 64)
