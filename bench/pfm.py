"""PFM (portable float map) reading and writing for the depth benches:
one channel, rows bottom to top on disk, a negative scale for little-endian.
Missing depths are written as +inf, the way relief's readers take them."""
import numpy as np


def read_pfm(path):
    """The map as a float32 array of shape (height, width), top row first."""
    with open(path, "rb") as f:
        assert f.readline().strip() == b"Pf"
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        d = np.fromfile(f, "<f4" if scale < 0 else ">f4").reshape(h, w)
    return d[::-1].astype(np.float32)


def write_pfm(path, d):
    """d, shape (height, width), top row first; NaN written as +inf."""
    with open(path, "wb") as f:
        f.write(b"Pf\n%d %d\n-1.0\n" % (d.shape[1], d.shape[0]))
        np.where(np.isfinite(d), d, np.inf).astype("<f4")[::-1].tofile(f)
