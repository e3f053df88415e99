"""The vertices of a binary little-endian PLY as dicts of their properties
(x, y, z, label, ...), for the shell tests' checks (test_ggg_holes.sh)."""
import struct

CODE = {"float": "f", "double": "d", "uchar": "B", "int": "i"}


def vertices(path):
    f = open(path, "rb")
    head = []
    while not head or head[-1] != b"end_header":
        head.append(f.readline().strip())
    n, props, in_vertex = 0, [], False
    for line in head:
        w = line.split()
        if w[:1] == [b"element"]:
            in_vertex = w[1] == b"vertex"
            n = int(w[2]) if in_vertex else n
        elif w[:1] == [b"property"] and in_vertex:
            props.append((w[1].decode(), w[2].decode()))
    fmt = "<" + "".join(CODE[t] for t, _ in props)
    rec, names = struct.calcsize(fmt), [p for _, p in props]
    return [dict(zip(names, struct.unpack(fmt, f.read(rec)))) for _ in range(n)]
