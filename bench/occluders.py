"""bench/occluders.sh's work: `relief occluders` on every shared RGB-D frame
(the sequence's five, NYU, SUN, office1), then `relief remove-occluders`
with the mask found. Prints per frame the mask's share of the frame, each
background plane's marked share (the report's planes[].marked: the share of
its region, the captured pixels within 3 sigma of it in its connected
support, that the mask covers), the seconds of `occluders` (the median of
--repeat runs, the report's own clock) and the removed pixels whose colour
after is the frame's missing-colour placeholder (the single colour of most
missing-depth pixels, when rare among the captured; '-' when the frame has
none). Writes bench/figures/occluders_<frame>_{before,mask,after}.png at
320 pixels a panel: colour and depth (near bright, missing black) before;
the overlay; colour and depth after.
  occluders.py RELIEF DATA_DIR FIGURES_DIR TMP_DIR REPEAT [EXTRA ARGS...]"""
import json
import os
import statistics
import subprocess
import sys

import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rgbd_frames  # noqa: E402

PANEL = 320


def placeholder(rgb, z):
    """The colour of most missing-depth pixels when under 1 % of the
    captured have it; None."""
    miss = np.isnan(z)
    if not miss.any():
        return None
    packed = (rgb[..., 0].astype(np.uint32) << 16) | (rgb[..., 1].astype(np.uint32) << 8) | rgb[..., 2]
    values, counts = np.unique(packed[miss], return_counts=True)
    top = values[np.argmax(counts)]
    if counts.max() * 2 < miss.sum() or (packed[~miss] == top).mean() > 0.01:
        return None
    return top


def depth_picture(z, lo, hi):
    """Inverse depth as a colour map, near bright; missing black."""
    t = np.clip((1.0 / np.where(np.isnan(z), hi, z) - 1.0 / hi) / (1.0 / lo - 1.0 / hi), 0, 1)
    pic = cv2.applyColorMap((255 * t).astype(np.uint8), cv2.COLORMAP_TURBO)[:, :, ::-1]
    pic[np.isnan(z)] = 0
    return pic


def panel(rgb):
    h, w = rgb.shape[:2]
    return cv2.resize(rgb, (PANEL, round(h * PANEL / w)), interpolation=cv2.INTER_AREA)


def save(path, *pictures):
    row = np.concatenate([panel(p) for p in pictures], axis=1)
    cv2.imwrite(path, np.ascontiguousarray(row[:, :, ::-1]), [cv2.IMWRITE_PNG_COMPRESSION, 9])


def run(cmd):
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)


def one_frame(relief, name, args, colour, depth, figures, tmp, repeat, extra):
    t = os.path.join(tmp, name)
    mask, overlay, report = t + "_mask.png", t + "_overlay.png", t + "_r.json"
    seconds = []
    for _ in range(repeat):
        run([relief, "occluders", *args, "-o", mask, "--overlay", overlay, "--report", report,
             "--quiet", *extra])
        with open(report) as f:
            r = json.load(f)
        seconds.append(r["seconds"]["total"])
    rgb, z = rgbd_frames.load(colour, depth)
    if depth is None:
        after, after_c = t + "_after.pcd", t + "_after.png"
        run([relief, "remove-occluders", *args, "--mask", mask, "-o", after, "--colour-out",
             after_c, "--quiet", *extra])
        rgb_after, z_after = rgbd_frames.read_pcd(after)
    else:
        after_c, after_z = t + "_after.png", t + "_after_depth.png"
        run([relief, "remove-occluders", *args, "--mask", mask, "-o", after_c, "--depth-out",
             after_z, "--scale", "1000", "--quiet", *extra])
        rgb_after = rgbd_frames.read_colour(after_c)
        z_after = rgbd_frames.read_depth(after_z, "png", 1000.0)
    m = cv2.imread(mask, cv2.IMREAD_GRAYSCALE) > 0
    ph = placeholder(rgb, z)
    if ph is None:
        bad = "-"
    else:
        packed = (rgb_after[..., 0].astype(np.uint32) << 16) | (rgb_after[..., 1].astype(np.uint32) << 8) | rgb_after[..., 2]
        bad = str(int((packed[m] == ph).sum()))
    lo, hi = np.nanpercentile(z, 1), np.nanpercentile(z, 99)
    prefix = os.path.join(figures, "occluders_" + name)
    save(prefix + "_before.png", rgb, depth_picture(z, lo, hi))
    save(prefix + "_mask.png", rgbd_frames.read_colour(overlay))
    save(prefix + "_after.png", rgb_after, depth_picture(z_after, lo, hi))
    planes = [p["marked"] for p in r["background"]["planes"]]
    return {"frame": name, "share": r["mask"]["share"], "planes": planes,
            "worst": max(planes) if planes else float("nan"),
            "seconds": statistics.median(seconds), "placeholder": bad,
            "noise": r["background"]["noise"]}


def main():
    relief, data, figures, tmp, repeat = sys.argv[1:6]
    extra = sys.argv[6:]
    os.makedirs(figures, exist_ok=True)
    rows = [one_frame(relief, *f, figures, tmp, int(repeat), extra)
            for f in rgbd_frames.frames(data)]
    print("| frame | mask share | planes' marked shares | worst plane | seconds (median of %s) "
          "| placeholder pixels removed |" % repeat)
    print("| --- | --- | --- | --- | --- | --- |")
    for r in rows:
        print("| %s | %.1f %% | %s | %.1f %% | %.2f | %s |" % (
            r["frame"], 100 * r["share"], ", ".join("%.1f" % (100 * p) for p in r["planes"]),
            100 * r["worst"], r["seconds"], r["placeholder"]))


if __name__ == "__main__":
    main()
