"""The frames, the fills and the table of bench/depth_edges.sh.

  depth_edges_bench.py RELIEF TOOL DATA OUT [--repeat N] [--only F,...] [--figures DIR]
"""
import csv, os, statistics, subprocess, sys, time
import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import depth_edges as de  # noqa: E402

relief, tool, data, out = sys.argv[1:5]
opt = de.opt
repeat = int(opt("--repeat", "1"))
only = opt("--only", "")
figures = opt("--figures", "")
rgbd = os.path.join(data, "rgbd")


def frames():
    """name: (depth file, its format, colour file or None, scale per metre)."""
    f = {}
    for i in range(5):
        f["seq%d" % i] = (os.path.join(rgbd, "sequence/depth/%05d.png" % i), "png",
                          os.path.join(rgbd, "sequence/color/%05d.jpg" % i), 1000.0)
    f["nyu"] = (os.path.join(rgbd, "nyu/NYU_depth.pgm"), "nyu",
                os.path.join(rgbd, "nyu/NYU_color.ppm"), 1000.0)
    f["sun"] = (os.path.join(rgbd, "sun/SUN_depth.png"), "sun",
                os.path.join(rgbd, "sun/SUN_color.jpg"), 1000.0)
    f["office1"] = (os.path.join(data, "depth/office1.pcd"), "pcd", None, 1000.0)
    return {k: v for k, v in f.items() if not only or k in only.split(",")}


def timed(args):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        subprocess.run(args, check=True, stderr=subprocess.DEVNULL)
        times.append(time.perf_counter() - t)
    return statistics.median(times)


def depth_args(src, fmt, scale):
    """relief's options reading the frame (NYU's and SUN's own encodings by
    --depth-format; the bench decodes them independently, depth_edges.py)."""
    if fmt == "pcd":
        return []
    return ["--scale", str(scale)] + (["--depth-format", fmt] if fmt in ("nyu", "sun") else [])


def telea(name, z, scale):
    miss = ~np.isfinite(z)
    inside = np.zeros_like(miss)  # relief's inside: known on both sides along a row or column
    for a, t in ((miss, False), (miss.T, True)):
        k = ~a
        first = np.argmax(k, axis=1)
        last = a.shape[1] - 1 - np.argmax(k[:, ::-1], axis=1)
        cols = np.arange(a.shape[1])[None, :]
        m = a & k.any(axis=1)[:, None] & (cols > first[:, None]) & (cols < last[:, None])
        inside |= m.T if t else m
    t0 = time.perf_counter()
    f = cv2.inpaint(np.where(miss, 0, z * 1000).astype(np.float32), miss.astype(np.uint8), 5,
                    cv2.INPAINT_TELEA) / 1000.0
    secs = time.perf_counter() - t0
    return np.where(miss & ~inside, np.nan, f), secs


def colour_map(z, lo, hi):
    g = np.clip((hi - z) / (hi - lo), 0, 1)
    img = cv2.applyColorMap((np.nan_to_num(g) * 255).astype(np.uint8), cv2.COLORMAP_TURBO)
    img[~np.isfinite(z)] = 0
    return img


def from_above(before, after, size=240):
    """A view from above of the points (x right, depth up): grey captured,
    red filled; the frame's 1st-99th percentile depth range."""
    H, W = before.shape
    f = 525.0 * W / 640.0
    u = np.arange(W)[None, :] - (W - 1) / 2.0
    hi = np.nanpercentile(before, 99) * 1.05
    xr = np.nanpercentile(np.abs(u * before / f), 99) * 1.05
    img = np.zeros((size, size, 3), np.uint8)
    for z, sel, col in ((before, np.isfinite(before), (150, 150, 150)),
                        (after, ~np.isfinite(before) & np.isfinite(after), (40, 40, 255))):
        x = (u * np.where(sel, z, np.nan) / f)[sel]
        zz = z[sel]
        X = ((x / xr * 0.5 + 0.5) * (size - 1)).astype(int)
        Y = ((1 - zz / hi) * (size - 1)).astype(int)
        ok = (X >= 0) & (X < size) & (Y >= 0) & (Y < size)
        img[Y[ok], X[ok]] = col
    return img


def main():
    os.makedirs(out, exist_ok=True)
    rows = []
    for name, (src, fmt, colour, scale) in frames().items():
        before = de.read(src, scale, fmt, tool)
        ext = ".pcd" if fmt == "pcd" else ".png"
        outs = {}
        for mode in ("layers", "across"):
            o = os.path.join(out, "%s_%s%s" % (name, mode, ext))
            args = [relief, "depth-fill", src, "-o", o, "--edges", mode, "--quiet"]
            args += depth_args(src, fmt, scale)
            if colour and mode == "layers":
                args += ["--colour", colour]
            secs = timed(args)
            outs["relief " + mode] = (de.read(o, scale, "png", tool), secs)
        outs["opencv telea"] = telea(name, before, scale)
        for method, (after, secs) in outs.items():
            s = de.share(before, after)
            rows.append(dict(frame=name, method=method, seconds=round(secs, 3), **s))
            print("%-8s %-14s %6.2f s  filled across steps %5d: within 0.1 m %s  or a step %s  "
                  "2-D %s  interior %s" % (name, method, secs, s["filled"], fmt_share(s["share"]),
                                           fmt_share(s["share_step"]), fmt_share(s["share_2d"]),
                                           fmt_share(s["share_interior"])), flush=True)
        if figures:
            pictures(name, before, outs)
    totals(rows)
    with open(os.path.join(out, "depth_edges.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def fmt_share(s):
    return "  -  " if s is None else "%.3f" % s


def totals(rows):
    """Every frame together, per method: the shares of all their pixels."""
    for method in dict.fromkeys(r["method"] for r in rows):
        rs = [r for r in rows if r["method"] == method]
        n, k = sum(r["filled"] for r in rs), sum(r["within"] for r in rs)
        ni, ki = sum(r["filled_interior"] for r in rs), sum(r["within_interior"] for r in rs)
        ks = sum(r["within_step"] for r in rs)
        print("all      %-14s filled across steps %5d: within 0.1 m %.3f  or a step %.3f  "
              "interior %.3f" % (method, n, k / n if n else float("nan"),
                                 ks / n if n else float("nan"), ki / ni if ni else float("nan")))


def pictures(name, before, outs):
    os.makedirs(figures, exist_ok=True)
    lo, hi = np.nanpercentile(before, 1), np.nanpercentile(before, 99)
    small = lambda img: cv2.resize(img, (320, 240), interpolation=cv2.INTER_NEAREST)
    row1 = [small(colour_map(before, lo, hi))]
    pad = lambda img: cv2.copyMakeBorder(img, 0, 0, 40, 40, cv2.BORDER_CONSTANT)
    row2 = [pad(from_above(before, before))]
    for method in ("relief layers", "relief across", "opencv telea"):
        row1.append(small(colour_map(outs[method][0], lo, hi)))
        row2.append(pad(from_above(before, outs[method][0])))
    cv2.imwrite(os.path.join(figures, "depth_edges_%s.png" % name),
                np.vstack([np.hstack(row1), np.hstack(row2)]))


if __name__ == "__main__":
    main()
