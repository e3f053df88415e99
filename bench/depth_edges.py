"""The depth-edge share of a depth fill (issue 63): of the filled pixels in
row gaps whose two captured ends differ by more than STEP (0.3 m), the
share within NEAR (0.1 m) of either end. A fill that ramps across a step
scores low; one that continues each surface to the silhouette scores 1.
Also printed: the share within 0.1 m or the camera's own depth step at the
end (z^2 / 348 m, a Kinect's: 0.28 m at 9.8 m, where 0.1 m is under one
step, so a right fill of a far wall reads as wrong); its 2-D reading (a pixel in a stepped gap along its row or
its column, within NEAR of an end of either) and its interior part (row
gaps with a captured pixel above and below: not a row at the edge of the
frame's invalid margin, where a third surface shows between the row's
ends and the measure counts a right fill as wrong).

  depth_edges.py IN FILLED [--scale S] [--format png|nyu|sun] [--tool T]

IN is the frame with its holes, FILLED relief's (or a peer's) output of the
same kind (a PNG written plainly at S per metre). PNG depths are read with cv2 (S units per metre, default 1000);
--format nyu is NYU Depth v2's raw Kinect disparity PGM (byte-swapped,
z = 351.3 / (1092.5 - d)), sun SUN RGB-D's PNG (bits rotated by 3, mm);
anything else (PCD, PFM) through depth_bench_tool pfm. Prints JSON.
"""
import json, os, subprocess, sys, tempfile
import cv2
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pfm import read_pfm  # noqa: E402


def opt(name, default):
    return sys.argv[sys.argv.index(name) + 1] if name in sys.argv else default


def read(path, scale, fmt, tool):
    """Depths in metres, NaN where missing."""
    if path.lower().endswith((".png", ".pgm")):
        a = cv2.imread(path, cv2.IMREAD_UNCHANGED)
        if fmt == "nyu":
            d = a.astype(np.uint16).byteswap().astype(np.float64)
            z = 351.3 / (1092.5 - d)
            z[(z <= 0) | (d >= 2047)] = np.nan
            return z
        if fmt == "sun":
            u = a.astype(np.uint32)
            a = ((u >> 3) | (u << 13)) & 0xFFFF
        z = a.astype(np.float64) / scale
        z[a == 0] = np.nan
        return z
    with tempfile.TemporaryDirectory() as t:
        out = os.path.join(t, "d.pfm")
        subprocess.run([tool, "pfm", path, out], check=True)
        z = read_pfm(out).astype(np.float64)
    z[~np.isfinite(z) | (z <= 0)] = np.nan
    return z


KINECT_STEP = 1.0 / 348.0  # a structured-light camera's depth step over z^2 (metres)


def gap_marks(before, after, step, near, quantum=0.0):
    """Along rows: in[y, x] where a filled pixel lies in a gap whose ends
    differ by over step, ok[y, x] where it lies within near of an end (or,
    quantum > 0, within quantum x z^2 of it, the camera's own step there,
    when that is more)."""
    inside = np.zeros(before.shape, bool)
    ok = np.zeros(before.shape, bool)
    for y in range(before.shape[0]):
        row = before[y]
        known = np.flatnonzero(np.isfinite(row))
        for a, b in zip(known[:-1], known[1:]):
            if b - a < 2 or abs(row[a] - row[b]) <= step:
                continue
            f = after[y, a + 1:b]
            filled = np.isfinite(f)
            inside[y, a + 1:b] |= filled
            ta = max(near, quantum * row[a] * row[a])
            tb = max(near, quantum * row[b] * row[b])
            ok[y, a + 1:b] |= filled & ((abs(f - row[a]) <= ta) | (abs(f - row[b]) <= tb))
    return inside, ok


def share(before, after, step=0.3, near=0.1):
    """The issue's measure along rows, and its 2-D reading: a pixel in a
    stepped gap along its row or its column, within near of an end of
    either."""
    r_in, r_ok = gap_marks(before, after, step, near)
    c_in, c_ok = gap_marks(before.T, after.T, step, near)
    both_in = r_in | c_in.T
    both_ok = both_in & (r_ok | c_ok.T)
    # interior: a known pixel above and below too (not a row at the edge
    # of the frame's invalid margin, where a third surface shows between
    # the row's ends)
    known = np.isfinite(before)
    above = np.maximum.accumulate(known, axis=0)
    below = np.maximum.accumulate(known[::-1], axis=0)[::-1]
    inner = r_in & above & below
    n, k = int(r_in.sum()), int(r_ok.sum())
    n2, k2 = int(both_in.sum()), int(both_ok.sum())
    n3, k3 = int(inner.sum()), int((inner & r_ok).sum())
    _, q_ok = gap_marks(before, after, step, near, KINECT_STEP)
    k4 = int(q_ok.sum())
    return dict(filled=n, within=k, share=k / n if n else None,
                filled_2d=n2, within_2d=k2, share_2d=k2 / n2 if n2 else None,
                filled_interior=n3, within_interior=k3, share_interior=k3 / n3 if n3 else None,
                within_step=k4, share_step=k4 / n if n else None)


def main():
    inp, filled = sys.argv[1:3]
    scale = float(opt("--scale", "1000"))
    fmt = opt("--format", "png")
    tool = opt("--tool", "build/bench/depth_bench_tool")
    before = read(inp, scale, fmt, tool)
    # relief writes a depth PNG plainly, at the scale it read
    after = read(filled, scale, "png", tool)
    print(json.dumps(share(before, after)))


if __name__ == "__main__":
    main()
