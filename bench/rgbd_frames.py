"""The shared RGB-D frames as numpy arrays, for bench/occluders.py: colour
(H, W, 3) uint8 and depth (H, W) float metres (NaN missing), decoded here
without relief (an independent reading of what relief reads): JPEG, PNG and
PPM through OpenCV; NYU's raw disparity PGM, SUN's rotated-bit PNG and an
organised binary_compressed PCD (LZF) by hand."""
import os

import cv2
import numpy as np


def lzf_decompress(src, size):
    """liblzf's decompressor (PCL's binary_compressed)."""
    out = bytearray()
    i = 0
    while i < len(src):
        ctrl = src[i]
        i += 1
        if ctrl < 32:
            out += src[i:i + ctrl + 1]
            i += ctrl + 1
            continue
        length = ctrl >> 5
        ref = len(out) - ((ctrl & 0x1f) << 8) - 1
        if length == 7:
            length += src[i]
            i += 1
        ref -= src[i]
        i += 1
        for k in range(length + 2):
            out.append(out[ref + k])
    assert len(out) == size, (len(out), size)
    return bytes(out)


def read_pcd(path):
    """An organised PCD (x y z rgb, F 4, binary_compressed or binary)."""
    data = open(path, "rb").read()
    header, at = {}, 0
    while True:
        end = data.index(b"\n", at)
        line = data[at:end].decode().strip()
        at = end + 1
        if line.startswith("#") or not line:
            continue
        key, *vals = line.split()
        header[key] = vals
        if key == "DATA":
            break
    w, h = int(header["WIDTH"][0]), int(header["HEIGHT"][0])
    fields = header["FIELDS"]
    n = w * h
    if header["DATA"][0] == "binary_compressed":
        csize, usize = np.frombuffer(data[at:at + 8], "<u4")
        raw = lzf_decompress(data[at + 8:at + 8 + int(csize)], int(usize))
        cols = {f: np.frombuffer(raw[4 * n * k:4 * n * (k + 1)], "<f4") for k, f in enumerate(fields)}
    else:
        arr = np.frombuffer(data[at:at + 4 * n * len(fields)], "<f4").reshape(n, len(fields))
        cols = {f: arr[:, k] for k, f in enumerate(fields)}
    z = cols["z"].reshape(h, w).astype(np.float64)
    packed = cols["rgb"].view("<u4").reshape(h, w)
    rgb = np.stack([(packed >> 16) & 255, (packed >> 8) & 255, packed & 255], -1).astype(np.uint8)
    return rgb, np.where(np.isfinite(z) & (z > 0), z, np.nan)


def read_colour(path):
    bgr = cv2.imread(path, cv2.IMREAD_COLOR)
    assert bgr is not None, path
    return np.ascontiguousarray(bgr[:, :, ::-1])


def read_depth(path, encoding, scale):
    if encoding == "nyu":
        raw = open(path, "rb").read()
        tokens, at = [], 2
        while len(tokens) < 3:
            while raw[at:at + 1].isspace():
                at += 1
            end = at
            while not raw[end:end + 1].isspace():
                end += 1
            tokens.append(int(raw[at:end]))
            at = end
        w, h = tokens[0], tokens[1]
        d = np.frombuffer(raw[at + 1:at + 1 + 2 * w * h], "<u2").reshape(h, w).astype(np.float64)
        z = 351.3 / (1092.5 - d)
        return np.where((d < 2047) & (z > 0), z, np.nan)
    v = cv2.imread(path, cv2.IMREAD_UNCHANGED).astype(np.uint32)
    if encoding == "sun":
        v = ((v >> 3) | (v << 13)) & 0xFFFF
        scale = 1000.0
    return np.where(v > 0, v / scale, np.nan)


def frames(data):
    """[(name, relief arguments, colour, depth)] for every shared frame."""
    rgbd = os.path.join(data, "rgbd")
    out = []
    for i in range(5):
        c = os.path.join(rgbd, "sequence", "color", "%05d.jpg" % i)
        d = os.path.join(rgbd, "sequence", "depth", "%05d.png" % i)
        out.append(("sequence%d" % i, [c, "--depth", d, "--scale", "1000", "--intrinsics",
                                        "525,525,319.5,239.5"], c, (d, "png", 1000.0)))
    c, d = os.path.join(rgbd, "nyu", "NYU_color.ppm"), os.path.join(rgbd, "nyu", "NYU_depth.pgm")
    out.append(("nyu", [c, "--depth", d, "--depth-format", "nyu"], c, (d, "nyu", 0)))
    c, d = os.path.join(rgbd, "sun", "SUN_color.jpg"), os.path.join(rgbd, "sun", "SUN_depth.png")
    out.append(("sun", [c, "--depth", d, "--depth-format", "sun"], c, (d, "sun", 0)))
    p = os.path.join(data, "depth", "office1.pcd")
    out.append(("office1", [p], p, None))
    return out


def load(colour, depth):
    """The frame's colour and depth as read here."""
    if depth is None:
        return read_pcd(colour)
    return read_colour(colour), read_depth(*depth)
