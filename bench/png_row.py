#!/usr/bin/python3
"""Lay 8-bit PNGs (relief render's) side by side into one, for README's
figures: bench/png_row.py OUT.png IN1.png IN2.png ... Heights may differ
(shorter ones are padded white at the bottom); a 6-pixel white gap between.
Only what relief writes is read: 8-bit grey, RGB or RGBA, not interlaced."""
import struct
import sys
import zlib

import numpy as np

CHANNELS = {0: 1, 2: 3, 6: 4}


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit("%s: not a PNG" % path)
    at, idat = 8, b""
    while at < len(data):
        n, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + n]
        if kind == b"IHDR":
            w, h, depth, ctype, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or ctype not in CHANNELS or interlace:
                raise SystemExit("%s: only 8-bit grey/RGB/RGBA, not interlaced" % path)
        elif kind == b"IDAT":
            idat += body
        at += 12 + n
    c = CHANNELS[ctype]
    raw = zlib.decompress(idat)
    stride = w * c
    img = np.zeros((h, stride), np.uint8)
    prev = np.zeros(stride, np.int32)
    for y in range(h):
        f = raw[y * (stride + 1)]
        row = np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        out = np.zeros(stride, np.int32)
        for x in range(stride):  # filters 1, 3, 4 need the left neighbour
            a = out[x - c] if x >= c else 0
            b = prev[x]
            cc = prev[x - c] if x >= c else 0
            if f == 0:
                p = 0
            elif f == 1:
                p = a
            elif f == 2:
                p = b
            elif f == 3:
                p = (a + b) // 2
            else:
                pa, pb, pc = abs(b - cc), abs(a - cc), abs(a + b - 2 * cc)
                p = a if pa <= pb and pa <= pc else (b if pb <= pc else cc)
            out[x] = (row[x] + p) & 255
        img[y] = out
        prev = out
    img = img.reshape(h, w, c)
    if c == 1:
        img = np.repeat(img, 3, axis=2)
    return img[:, :, :3]


def write_png(path, img):
    h, w, _ = img.shape
    raw = b"".join(b"\x00" + img[y].tobytes() for y in range(h))

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(
            ">I", zlib.crc32(kind + body) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    imgs = [read_png(p) for p in sys.argv[2:]]
    h = max(i.shape[0] for i in imgs)
    parts = []
    for k, i in enumerate(imgs):
        pad = np.full((h, i.shape[1], 3), 255, np.uint8)
        pad[:i.shape[0]] = i
        parts.append(pad)
        if k + 1 < len(imgs):
            parts.append(np.full((h, 6, 3), 255, np.uint8))
    write_png(sys.argv[1], np.concatenate(parts, axis=1))


if __name__ == "__main__":
    main()
