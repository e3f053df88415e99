#!/usr/bin/env python3
"""Writes the small crafted captures that tests/cli/test_robust.sh feeds to
relief: geometry the method cannot handle, each with a known answer.
Run from tests/data: python3 crafted.py (the .off files are committed)."""


def grid(nx, ny, x0=0.0, y0=0.0, step=1.0, z=lambda i, j: 0.0, skip=lambda i, j: False):
    """(nx+1) x (ny+1) vertices, two triangles per cell unless skip(i, j)."""
    v, f = [], []
    for j in range(ny + 1):
        for i in range(nx + 1):
            v.append((x0 + i * step, y0 + j * step, z(i, j)))
    idx = lambda i, j: j * (nx + 1) + i
    for j in range(ny):
        for i in range(nx):
            if skip(i, j):
                continue
            a, b, c, d = idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)
            f += [(a, b, c), (a, c, d)]
    return v, f


def write(name, v, f, comment):
    with open(name, "w") as out:
        out.write("OFF\n%d %d 0\n" % (len(v), len(f)))  # OFF has no comments: see below
        for p in v:
            out.write("%.6f %.6f %.6f\n" % p)
        for t in f:
            out.write("3 %d %d %d\n" % t)


# A plane with a hole (something to complete) around cells 4..5.
hole = lambda i, j: 4 <= i <= 5 and 4 <= j <= 5

# fin.off: a third triangle on the interior edge between vertices 12 and 23
# of a 10 x 10 grid: a fin standing up from the plane.
v, f = grid(10, 10, step=0.1, skip=hole)
v.append((0.15, 0.15, 0.08))
f.append((12, 23, len(v) - 1))
write("fin.off", v, f, "plane with a fin: edge 12-23 has three triangles")

# fold.off: a strip that runs along x to 1, then folds back over itself to
# x = 0.4 a little above: two layers over one part of the plane.
v, f = [], []
cols = [(i / 10.0, 0.0) for i in range(11)] + [(1.0 - k / 10.0, 0.01 + 0.004 * k) for k in range(1, 7)]
ny = 10
for (x, z) in cols:
    for j in range(ny + 1):
        v.append((x, j / 10.0, z))
for c in range(len(cols) - 1):
    for j in range(ny):
        a, b = c * (ny + 1) + j, (c + 1) * (ny + 1) + j
        f += [(a, b, b + 1), (a, b + 1, a + 1)]
write("fold.off", v, f, "a strip folded back over itself: two layers over x in [0.4, 1]")

# zigzag.off: a sawtooth as tall as it is wide: no plane, sphere or
# cylinder fits it.
v, f = grid(12, 12, step=0.1, z=lambda i, j: 0.5 * (i % 2) * (1 if j % 4 < 2 else -1))
write("zigzag.off", v, f, "a sawtooth that fits no primitive")

# tiny.off: a 0.2 x 0.2 patch; with --extent -1,-1,1,1 --spacing 0.05 the
# capture is smaller than a window of 3 (and fits one of 1 or 2).
v, f = grid(4, 4, step=0.05)
write("tiny.off", v, f, "a small patch: smaller than the window")

# strip.off: a strip one cell wide: every sample lies next to a target.
v, f = grid(20, 1, step=0.05)
write("strip.off", v, f, "a strip one cell wide: no sample has a complete neighbourhood")

# bent.off: a 1 x 1 patch with a hole, bent on a cylinder of radius 30 along
# y: nearly flat (sag 0.004), so --fit auto takes the cylinder, whose full
# turn of 188 units holds about 170 targets per captured vertex.
import math
R = 30.0
v, f = grid(20, 20, step=0.05, z=lambda i, j: R - math.sqrt(R * R - (i * 0.05 - 0.5) ** 2),
            skip=lambda i, j: 8 <= i <= 11 and 8 <= j <= 11)
write("bent.off", v, f, "a nearly flat patch on a cylinder of radius 30")
