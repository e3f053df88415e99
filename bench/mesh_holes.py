#!/usr/bin/env python3
"""relief's mesh hole engines against CGAL, PyMeshLab, pymeshfix and trimesh
on cuts whose truth is known (issue 61). Run by bench/mesh_holes.sh, in the
bench's own venv (numpy, scipy, cgal, pymeshlab, pymeshfix, trimesh):

  mesh_holes.py RELIEF DATA OUT [--quick] [--only CASE,...] [--timeout S] [--figures DIR]

Each cut is made by `relief cut --truth` (the truth: the whole mesh, label 1
on the vertices the cut lacks) from a mesh of DATA/real or from `relief
synth`'s whole truths. Each method fills the cut; the peers run in a child
process of this script (`mesh_holes.py --peer NAME ...`), so that a crash or a
refusal is a row, never the end of the bench. Every output is measured
against the truth (the definitions are in measure() and in
docs/benchmarks.md), a row printed and written to OUT/mesh_holes.csv, and
each output rendered about the cut by `relief render`, with the same view per
cut, into OUT/CASE/*.png and one row OUT/CASE/row.png.

All lengths are in h, the mean edge length of the cut capture.
"""
import csv
import math
import os
import shutil
import subprocess
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))

# ---------------------------------------------------------------- mesh files

PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
             "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
             "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(path):
    """(V, F, vertex properties by name) of a PLY of triangles (binary either
    endianness, or ascii); polygons are fanned into triangles."""
    data = open(path, "rb").read()
    end = data.index(b"end_header") + len(b"end_header")
    end = data.index(b"\n", end) + 1
    lines = data[:end].decode("ascii", "replace").splitlines()
    fmt = "ascii"
    elements = []  # (name, count, [(prop, type) or (prop, 'list', ctype, itype)])
    for ln in lines:
        w = ln.split()
        if not w:
            continue
        if w[0] == "format":
            fmt = w[1]
        elif w[0] == "element":
            elements.append((w[1], int(w[2]), []))
        elif w[0] == "property" and elements:
            if w[1] == "list":
                elements[-1][2].append((w[4], "list", w[2], w[3]))
            else:
                elements[-1][2].append((w[2], w[1]))
    body = data[end:]
    V = F = None
    props = {}
    if fmt == "ascii":
        tokens = body.split()
        at = 0
        for name, count, plist in elements:
            if name == "vertex":
                k = len(plist)
                arr = np.array(tokens[at:at + k * count], dtype=np.float64).reshape(count, k)
                at += k * count
                for j, p in enumerate(plist):
                    props[p[0]] = arr[:, j]
            elif name == "face":
                faces = []
                for _ in range(count):
                    for q in plist:
                        if q[1] == "list":
                            n = int(tokens[at])
                            faces.append([int(t) for t in tokens[at + 1:at + 1 + n]])
                            at += 1 + n
                        else:
                            at += 1
                F = fan(faces)
            elif any(q[1] == "list" for q in plist):
                raise ValueError("%s: element %s not read" % (path, name))
            else:  # skipped (a range map's camera)
                at += len(plist) * count
    else:
        e = "<" if fmt == "binary_little_endian" else ">"
        at = 0
        for name, count, plist in elements:
            if name == "vertex":
                dt = np.dtype([(p[0], e + PLY_TYPES[p[1]]) for p in plist])
                arr = np.frombuffer(body, dt, count, at)
                at += dt.itemsize * count
                for p in plist:
                    props[p[0]] = arr[p[0]].astype(np.float64)
            elif name == "face":
                # the index list (triangles read at once), other scalar
                # properties (a range map's flags, quality) skipped
                if [q[1] for q in plist].count("list") != 1:
                    raise ValueError("%s: faces with other lists than their indices" % path)
                fields = []
                for q in plist:
                    if q[1] == "list":
                        ct, it = np.dtype(e + PLY_TYPES[q[2]]), np.dtype(e + PLY_TYPES[q[3]])
                        fields += [("n", ct), ("i", it, 3)]
                    else:
                        fields.append((q[0], e + PLY_TYPES[q[1]]))
                tri = np.dtype(fields)
                fast = np.frombuffer(body, tri, count, at) if len(body) - at >= tri.itemsize * count else None
                if fast is not None and np.all(fast["n"] == 3):
                    F = fast["i"].astype(np.int64)
                    at += tri.itemsize * count
                else:
                    faces = []
                    for _ in range(count):
                        for q in plist:
                            if q[1] == "list":
                                n = int(np.frombuffer(body, ct, 1, at)[0])
                                at += ct.itemsize
                                faces.append(np.frombuffer(body, it, n, at).tolist())
                                at += it.itemsize * n
                            else:
                                at += np.dtype(PLY_TYPES[q[1]]).itemsize
                    F = fan(faces)
            elif any(q[1] == "list" for q in plist):
                raise ValueError("%s: element %s not read" % (path, name))
            else:  # skipped (a range map's camera)
                at += np.dtype([(q[0], e + PLY_TYPES[q[1]]) for q in plist]).itemsize * count
    V = np.stack([props.pop("x"), props.pop("y"), props.pop("z")], axis=1)
    if F is None:
        F = np.zeros((0, 3), np.int64)
    return V, F, props


def fan(faces):
    out = [(f[0], f[i], f[i + 1]) for f in faces for i in range(1, len(f) - 1)]
    return np.array(out, np.int64).reshape(-1, 3)


def read_off(path):
    tokens = open(path).read().split()
    if tokens[0] != "OFF":
        raise ValueError("%s: not OFF" % path)
    nv, nf = int(tokens[1]), int(tokens[2])
    at = 4
    V = np.array(tokens[at:at + 3 * nv], np.float64).reshape(nv, 3)
    at += 3 * nv
    faces = []
    for _ in range(nf):
        n = int(tokens[at])
        faces.append([int(t) for t in tokens[at + 1:at + 1 + n]])
        at += 1 + n
    return V, fan(faces), {}


def read_mesh(path):
    return read_off(path) if path.endswith(".off") else read_ply(path)


def write_ply(path, V, F, label=None):
    V = np.asarray(V, np.float32)
    F = np.asarray(F, np.int32)
    head = ["ply", "format binary_little_endian 1.0", "element vertex %d" % len(V),
            "property float x", "property float y", "property float z"]
    vd = [("p", "<f4", 3)]
    if label is not None:
        head.append("property int label")
        vd.append(("l", "<i4"))
    head += ["element face %d" % len(F), "property list uchar int vertex_indices", "end_header"]
    va = np.zeros(len(V), vd)
    va["p"] = V
    if label is not None:
        va["l"] = label
    fa = np.zeros(len(F), [("n", "u1"), ("i", "<i4", 3)])
    fa["n"] = 3
    fa["i"] = F
    with open(path, "wb") as f:
        f.write(("\n".join(head) + "\n").encode())
        f.write(va.tobytes())
        f.write(fa.tobytes())


def write_off(path, V, F):
    with open(path, "w") as f:
        f.write("OFF\n%d %d 0\n" % (len(V), len(F)))
        np.savetxt(f, V, "%.9g")
        np.savetxt(f, np.hstack([np.full((len(F), 1), 3), F]), "%d")


# ------------------------------------------------------------------ the peers
# Each runs in a child process: mesh_holes.py --peer NAME IN.ply OUT.ply ARGS.
# It prints "seconds S" (reading, the call and writing; imports not counted).


def peer_main(argv):
    name, src, dst = argv[:3]
    args = dict(a.split("=", 1) for a in argv[3:])
    if name == "cgal":
        from CGAL import CGAL_Polygon_mesh_processing as PMP
        from CGAL.CGAL_Polyhedron_3 import Polyhedron_3
    elif name == "pymeshlab":
        import pymeshlab
    elif name == "pymeshfix":
        import pymeshfix
    elif name == "trimesh":
        import trimesh
    t0 = time.perf_counter()
    V, F, _ = read_mesh(src)
    if name == "cgal":
        # triangulate_refine_and_fair_hole (PMP; default density control
        # 2^0.5 and fairing continuity 1) on each border loop with a vertex
        # in the ball relief is told (ball=cx,cy,cz,r).
        off = dst + ".in.off"
        write_off(off, V, F)
        P = Polyhedron_3(off)
        os.remove(off)
        if P.size_of_facets() != len(F):
            raise SystemExit("CGAL read %d of %d triangles (not a polygon mesh it accepts)"
                             % (P.size_of_facets(), len(F)))
        for i, h in enumerate(P.halfedges()):
            h.set_id(i)
        ball = np.array([float(x) for x in args["ball"].split(",")])
        seen, loops = set(), []
        for h in P.halfedges():
            if not h.is_border() or h.id() in seen:
                continue
            g, pts = h, []
            while True:
                seen.add(g.id())
                p = g.vertex().point()
                pts.append((p.x(), p.y(), p.z()))
                g = g.next()
                if g.id() == h.id():
                    break
            if np.min(np.linalg.norm(np.array(pts) - ball[:3], axis=1)) <= ball[3]:
                loops.append((h, len(pts)))
        if not loops:
            raise SystemExit("no border loop in the ball")
        for h, _ in loops:
            PMP.triangulate_refine_and_fair_hole(P, h, [], [])
        # read back from the polyhedron itself (write_to_file keeps 6 digits)
        V = []
        for i, v in enumerate(P.vertices()):
            v.set_id(i)
            p = v.point()
            V.append((p.x(), p.y(), p.z()))
        F = []
        for f in P.facets():
            g = f.halfedge()
            F.append((g.vertex().id(), g.next().vertex().id(), g.next().next().vertex().id()))
            if f.facet_degree() != 3:
                raise SystemExit("CGAL left a facet of %d sides" % f.facet_degree())
        V, F = np.array(V), np.array(F)
        note = "%d loop(s) of %s edges" % (len(loops), "+".join(str(n) for _, n in loops))
    elif name == "pymeshlab":
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F))
        ms.meshing_close_holes(maxholesize=int(args["maxholesize"]))
        m = ms.current_mesh()
        V, F = m.vertex_matrix(), m.face_matrix()
        note = "maxholesize %s" % args["maxholesize"]
    elif name == "pymeshfix":
        mf = pymeshfix.MeshFix(V, F)
        mf.repair()
        V, F = mf.points, mf.faces
        note = "repair()"
    elif name == "trimesh":
        m = trimesh.Trimesh(V, F, process=False)
        trimesh.repair.fill_holes(m)
        V, F = m.vertices, m.faces
        note = "repair.fill_holes"
    else:
        raise SystemExit("unknown peer " + name)
    write_ply(dst, V, F)
    print("seconds %.3f" % (time.perf_counter() - t0))
    print("note " + note)


# ---------------------------------------------------------------- geometry


def tri_areas(V, F):
    return 0.5 * np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)


def mean_edge(V, F):
    e = np.sort(np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]]), axis=1)
    e = np.unique(e, axis=0)
    return float(np.linalg.norm(V[e[:, 0]] - V[e[:, 1]], axis=1).mean())


def sample(V, F, spacing, seed=1, limit=1_000_000):
    """Points on the triangles, at least one per spacing^2 of area (and one
    per triangle): (points, area weights, triangle of each)."""
    a = tri_areas(V, F)
    s2 = spacing * spacing
    if a.sum() / s2 > limit:
        s2 = a.sum() / limit
    n = np.maximum(1, np.ceil(a / s2)).astype(np.int64)
    fi = np.repeat(np.arange(len(F)), n)
    rng = np.random.default_rng(seed)
    r1 = np.sqrt(rng.random(len(fi)))
    r2 = rng.random(len(fi))
    A, B, C = V[F[fi, 0]], V[F[fi, 1]], V[F[fi, 2]]
    P = (1 - r1)[:, None] * A + (r1 * (1 - r2))[:, None] * B + (r1 * r2)[:, None] * C
    return P, (a / n)[fi], fi


def closest_on_triangles(P, A, B, C):
    """Distances from the points P to the triangles ABC (row by row; Ericson's
    closest point on a triangle)."""
    ab, ac, ap = B - A, C - A, P - A
    d1, d2 = np.einsum("ij,ij->i", ab, ap), np.einsum("ij,ij->i", ac, ap)
    bp = P - B
    d3, d4 = np.einsum("ij,ij->i", ab, bp), np.einsum("ij,ij->i", ac, bp)
    cp = P - C
    d5, d6 = np.einsum("ij,ij->i", ab, cp), np.einsum("ij,ij->i", ac, cp)
    va = d3 * d6 - d5 * d4
    vb = d5 * d2 - d1 * d6
    vc = d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v = np.where(denom != 0, vb / denom, 0)
        w = np.where(denom != 0, vc / denom, 0)
        Q = A + ab * v[:, None] + ac * w[:, None]  # inside
        # edges
        t_ab = np.where(d1 - d3 != 0, d1 / (d1 - d3), 0)
        t_ac = np.where(d2 - d6 != 0, d2 / (d2 - d6), 0)
        t_bc = np.where((d4 - d3) + (d5 - d6) != 0, (d4 - d3) / ((d4 - d3) + (d5 - d6)), 0)
    cases = [
        (d1 <= 0) & (d2 <= 0), A,
        (d3 >= 0) & (d4 <= d3), B,
        (d6 >= 0) & (d5 <= d6), C,
        (vc <= 0) & (d1 >= 0) & (d3 <= 0), A + ab * t_ab[:, None],
        (vb <= 0) & (d2 >= 0) & (d6 <= 0), A + ac * t_ac[:, None],
        (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), B + (C - B) * t_bc[:, None],
    ]
    done = np.zeros(len(P), bool)
    for k in range(0, len(cases), 2):
        m = cases[k] & ~done
        Q[m] = cases[k + 1][m]
        done |= m
    return np.linalg.norm(P - Q, axis=1)


def dist_to_surface(P, V, F, tree, sample_tri, k=16):
    """Distances from P to the triangles F of V: exact, over the triangles of
    the k nearest of their samples (the tree is over those samples; k 16,
    so that a sliver's one sample is not missed for its neighbours')."""
    if len(P) == 0:
        return np.zeros(0)
    _, idx = tree.query(P, k=min(k, tree.n))
    idx = idx.reshape(len(P), -1)
    best = np.full(len(P), np.inf)
    for j in range(idx.shape[1]):
        t = F[sample_tri[idx[:, j]]]
        best = np.minimum(best, closest_on_triangles(P, V[t[:, 0]], V[t[:, 1]], V[t[:, 2]]))
    return best


def roughness(Q, pts, w, tree, radius):
    """RMS residual (per point, weighted by area) of the surface samples within
    radius of each query point about a least-squares quadric height field
    z = au^2 + buv + cv^2 + du + ev + f in the neighbourhood's principal
    frame; the RMS over the queries."""
    res = []
    for nb in tree.query_ball_point(Q, radius):
        if len(nb) < 12:
            continue
        X, ww = pts[nb], w[nb]
        c = np.average(X, axis=0, weights=ww + 1e-30)
        _, _, Vt = np.linalg.svd((X - c) * np.sqrt(ww + 1e-30)[:, None], full_matrices=False)
        L = (X - c) @ Vt.T
        u, v, z = L[:, 0], L[:, 1], L[:, 2]
        A = np.stack([u * u, u * v, v * v, u, v, np.ones_like(u)], axis=1)
        sw = np.sqrt(ww)
        coef, *_ = np.linalg.lstsq(A * sw[:, None], z * sw, rcond=None)
        r = z - A @ coef
        res.append(np.sum(ww * r * r) / np.sum(ww))
    return math.sqrt(np.mean(res)) if res else float("nan")


def topology(V, F):
    """Boundary loops (vertex sets, edge counts) and non-manifold edges of the
    mesh with its coincident vertices merged."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    U, inv = np.unique(V, axis=0, return_inverse=True)
    inv = inv.reshape(-1)
    G = inv[F]
    G = G[(G[:, 0] != G[:, 1]) & (G[:, 1] != G[:, 2]) & (G[:, 2] != G[:, 0])]
    e = np.sort(np.concatenate([G[:, [0, 1]], G[:, [1, 2]], G[:, [2, 0]]]), axis=1)
    ue, cnt = np.unique(e, axis=0, return_counts=True)
    b = ue[cnt == 1]
    nonman = ue[cnt > 2]
    loops = []
    if len(b):
        g = coo_matrix((np.ones(len(b)), (b[:, 0], b[:, 1])), shape=(len(U), len(U)))
        _, lab = connected_components(g, directed=False)
        el = lab[b[:, 0]]
        for c in np.unique(el):
            edges = b[el == c]
            loops.append((np.unique(edges), len(edges)))
    return U, loops, nonman


def self_intersecting_faces(V, F):
    """Per face: does it intersect a face it shares no vertex with
    (PyMeshLab's compute_selection_by_self_intersections_per_face), its
    coincident vertices merged first (a capture's non-manifold vertices,
    split on reading, would make the triangles that touch there count)."""
    import pymeshlab
    V, inv = np.unique(V, axis=0, return_inverse=True)
    F = inv.reshape(-1)[F]
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.asarray(V, np.float64), face_matrix=np.asarray(F, np.int32)))
    ms.compute_selection_by_self_intersections_per_face()
    sel = ms.current_mesh().face_selection_array()
    if len(sel) != len(F):
        raise RuntimeError("pymeshlab changed the face count")
    return sel.astype(bool)


# ------------------------------------------------------------------ measures


class Truth:
    """The truth of a cut, sampled once: the removed part (the truth's
    triangles with a vertex labelled 1: exactly those the cut lacks), the
    whole truth and the capture."""

    def __init__(self, truth_path, cut_path):
        from scipy.spatial import cKDTree
        V, F, p = read_ply(truth_path)
        lab = p["label"].astype(int)
        rem = lab[F].max(axis=1) == 1
        cV, cF, _ = read_ply(cut_path)
        self.h = h = mean_edge(cV, cF)
        self.spacing = h / 4
        self.V, self.F, self.rem = V, F, rem
        self.area = float(tri_areas(V, F[rem]).sum())
        self.removed_vertices = int((lab == 1).sum())
        # removed part
        self.rP, self.rw, rfi = sample(V, F[rem], self.spacing, seed=2)
        self.rF = F[rem]
        self.rfi = rfi
        self.rtree = cKDTree(self.rP)
        # the whole truth, with which samples lie on the removed part
        self.tP, self.tw, tfi = sample(V, F, self.spacing, seed=3)
        self.t_on_rem = rem[tfi]
        self.ttree = cKDTree(self.tP)
        # the capture
        self.cV, self.cF = cV, cF
        self.cP, self.cw, self.cfi = sample(cV, cF, self.spacing, seed=4)
        self.ctree = cKDTree(self.cP)
        self.capture_area = float(self.cw.sum())
        self.rough = roughness(self.queries(self.rP, 400), self.tP, self.tw, self.ttree, 2 * h)
        self.truth_loops = self.loops_at_cut(*topology(V, F)[:2])

    @staticmethod
    def queries(P, n):
        if len(P) <= n:
            return P
        return P[np.random.default_rng(5).choice(len(P), n, replace=False)]

    def near(self, P):
        """Distance from P to the removed part (over its samples)."""
        return self.rtree.query(P)[0] if len(P) else np.zeros(0)

    def loops_at_cut(self, U, loops):
        out = []
        for vs, ne in loops:
            if np.min(self.near(U[vs])) <= 2 * self.h:
                out.append(ne)
        return out


def measure(T, V, F):
    """The row's numbers for the output (V, F) against the truth T."""
    from scipy.spatial import cKDTree
    h = T.h
    r = {}
    oP, ow, _ = sample(V, F, T.spacing, seed=6)
    otree = cKDTree(oP)
    # (the k-d trees' searches are bounded: a search far from a sheet of
    # samples visits most of it)
    # coverage: the removed area within 1 h of the output
    d_rem_out = otree.query(T.rP, distance_upper_bound=2 * h)[0]
    r["coverage"] = float(T.rw[d_rem_out <= h].sum() / T.rw.sum())
    # capture lost: the capture's area farther than 1 h from the output
    d_cap_out = otree.query(T.cP, distance_upper_bound=2 * h)[0]
    r["capture_lost"] = float(T.cw[d_cap_out > h].sum() / T.cw.sum())
    # each output sample's distance to the truth's removed part and to the
    # capture: over the nearest samples of each (the capture's within 2 h),
    # then exact (to their triangles) where the removed part is the nearer
    # or within 0.5 h of the capture's distance
    d_rem = T.near(oP)
    d_cap = T.ctree.query(oP, distance_upper_bound=2 * h)[0]
    # samples over 2 h from both: on at most 20 000 of them (their area
    # shared out in proportion), the capture's distance by an approximate
    # search (within 25 %)
    far = ~np.isfinite(d_cap) & (d_rem >= 2 * h)
    wt = ow.copy()
    if far.any():
        fi = np.flatnonzero(far)
        pick = fi if len(fi) <= 20000 else np.random.default_rng(7).choice(fi, 20000, replace=False)
        d_cap[pick] = T.ctree.query(oP[pick], eps=0.25)[0]
        wt[fi] = 0
        wt[pick] = ow[fi].sum() / ow[pick].sum() * ow[pick]
        d_cap[np.setdiff1d(fi, pick)] = -1  # not drawn: weight 0 either way
    cand = d_rem < d_cap + 0.5 * h
    d_rem[cand] = dist_to_surface(oP[cand], T.V, T.rF, T.rtree, T.rfi)
    ex = cand & np.isfinite(d_cap) & ~far
    d_cap[ex] = dist_to_surface(oP[ex], T.cV, T.cF, T.ctree, T.cfi)
    # the fill: the output's area nearer the removed part than the capture
    # (by 0.01 h: the capture's own triangles, at 0 from it, never are)
    fill = d_rem < d_cap - 0.01 * h
    # added elsewhere: area nearer the capture and over 1 h from it, over
    # the removed area
    r["elsewhere"] = float(wt[~fill & (d_cap > h)].sum() / T.area)
    r["fill_area"] = float(wt[fill].sum() / T.area)
    if fill.any():
        d = d_rem[fill] / h
        wf = wt[fill]
        r["dist_mean"] = float(np.sum(d * wf) / wf.sum())
        o = np.argsort(d)
        cw = np.cumsum(wf[o])
        r["dist_p95"] = float(d[o][np.searchsorted(cw, 0.95 * cw[-1])])
        rough = roughness(T.queries(oP[fill], 400), oP, ow, otree, 2 * h)
        r["detail"] = rough / T.rough if T.rough > 0 else float("nan")
    else:
        r["dist_mean"] = r["dist_p95"] = r["detail"] = float("nan")
    # open loops and non-manifold edges at the cut
    U, loops, nonman = topology(V, F)
    at = T.loops_at_cut(U, loops)
    r["loops"] = len(at)
    r["loop_edges"] = int(sum(at))
    r["nonmanifold"] = int(np.sum(T.near(0.5 * (U[nonman[:, 0]] + U[nonman[:, 1]])) <= 2 * h)) if len(nonman) else 0
    # self-intersections at the cut: triangles with a vertex or the centroid
    # within 2 h of the removed part that cross a triangle they share no
    # vertex with
    si = self_intersecting_faces(V, F)
    if si.any():
        Fi = F[si]
        dv = np.minimum.reduce([T.near(V[Fi[:, j]]) for j in range(3)] + [T.near(V[Fi].mean(axis=1))])
        r["selfint"] = int(np.sum(dv <= 2 * h))
    else:
        r["selfint"] = 0
    r["faces"] = len(F)
    return r


# ------------------------------------------------------------------- running


def run(cmd, timeout):
    t0 = time.perf_counter()
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, timeout=timeout)
    except subprocess.TimeoutExpired:
        return None, time.perf_counter() - t0, "", "timed out after %d s" % timeout
    return p.returncode, time.perf_counter() - t0, p.stdout.decode(errors="replace"), p.stderr.decode(errors="replace")


def first_line(text, prefer=("error", "warning")):
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    for key in prefer:
        for ln in lines:
            if key in ln:
                return ln
    return lines[0] if lines else ""


def blank_png(path, w=320, h=320):
    """A white picture: the place of a method that wrote nothing."""
    import struct
    import zlib

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    raw = b"".join(b"\0" + b"\xf4" * (3 * w) for _ in range(h))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def fmt(x, spec="%.2f"):
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else spec % x


def markdown_row(r):
    if "coverage" not in r:
        note = r["note"].split(": ", 1)[-1].replace("|", "/")
        note = note if len(note) <= 90 else note[:note.rfind(" ", 0, 90)] + " ..."
        return "| %s | %s | exit %s: %s | | | | | | | %s |\n" % (
            r["case"], r["method"], r["rc"], note, fmt(r["seconds"], "%.1f"))
    return "| %s | %s | %s | %s | %s | %d (%d) | %d | %s / %s | %s | %s |\n" % (
        r["case"], r["method"], fmt(r["coverage"]), fmt(r["elsewhere"]), fmt(r["capture_lost"]),
        r["loops"], r["loop_edges"], r["selfint"], fmt(r["dist_mean"]), fmt(r["dist_p95"]),
        fmt(r["detail"]), fmt(r["seconds"], "%.1f"))


def crop(V, F, label, centre, radius):
    if radius is None:
        return V, F, label
    keep = np.linalg.norm(V - centre, axis=1) <= radius
    idx = np.full(len(V), -1)
    idx[keep] = np.arange(keep.sum())
    Fk = F[np.all(keep[F], axis=1)]
    return V[keep], idx[Fk], None if label is None else label[keep]


def new_faces_apart(V, F, cV, cF):
    """For the picture of a peer's output: its triangles that are not the
    capture's, on copies of their vertices labelled 1 (orange), the rest 0.
    The copies are moved by 0.001 h, or relief render's reading would weld
    them back (and the labels with them)."""
    h = mean_edge(cV, cF)
    q = 1e-3 * h

    def keys(VV, FF):
        P = np.round(VV[FF] / q).astype(np.int64)  # (m, 3, 3)
        return [tuple(sorted(map(tuple, p))) for p in P.tolist()]
    old = set(keys(cV, cF))
    new = np.array([k not in old for k in keys(V, F)], bool)
    Fo, Fn = F[~new], F[new]
    used, inv = np.unique(Fn.reshape(-1), return_inverse=True)
    nV = np.concatenate([V, V[used] + 1e-3 * h])
    nF = np.concatenate([Fo, len(V) + inv.reshape(-1, 3)])
    lab = np.concatenate([np.zeros(len(V), np.int32), np.ones(len(used), np.int32)])
    return nV, nF, lab


def view_of(T, centre):
    """The render's view: from the truth's centroid towards the cut, its
    elevation kept within 50 degrees so that a fill's profile shows."""
    d = centre - T.V.mean(axis=0)
    n = np.linalg.norm(d)
    if n < 1e-9 * np.ptp(T.V, axis=0).max():
        return "0,25"
    d /= n
    az = math.degrees(math.atan2(d[1], d[0]))
    el = max(-50.0, min(50.0, math.degrees(math.asin(max(-1, min(1, d[2]))))))
    return "%.1f,%.1f" % (az, el)


# --------------------------------------------------------------------- cases


def border_vertex(V, F, which):
    """A vertex of the mesh's longest boundary loop: the one with the largest
    coordinate `which` (0, 1, 2)."""
    U, loops, _ = topology(V, F)
    vs, _ = max(loops, key=lambda x: x[1])
    p = U[vs[np.argmax(U[vs, which])]]
    return int(np.argmin(np.linalg.norm(V - p, axis=1)))


def make_cases(relief, data, out, names):
    """The cuts named, made: a dict each (name, desc, truth and cut paths, the
    cut's region, the hole's ball when not the cut's, the pictures' crop
    radius and view rule), the cut's mesh and ball chosen from the data."""
    real = os.path.join(data, "real")
    cases = []

    def cut(name, src, region, desc, crop_r, mask=None, view=None):
        d = os.path.join(out, name)
        os.makedirs(d, exist_ok=True)
        cp, tp = os.path.join(d, "cut.ply"), os.path.join(d, "truth.ply")
        rc, _, _, err = run([relief, "cut", src, "-o", cp, "--truth", tp] + region, 300)
        if rc != 0:
            print("bench: %s: relief cut failed (%s): %s" % (name, rc, first_line(err)), file=sys.stderr)
            return
        cases.append(dict(name=name, desc=desc, truth=tp, cut=cp, region=" ".join(region),
                          mask=mask, crop=crop_r, view=view))

    def synth(kind, n):
        d = os.path.join(out, "synth")
        os.makedirs(d, exist_ok=True)
        t = os.path.join(d, "%s_%d_truth.ply" % (kind, n))
        if not os.path.exists(t):
            run([relief, "synth", kind, "-o", os.path.join(d, "%s_%d.ply" % (kind, n)),
                 "--truth", t, "--vertices", str(n)], 300)
        return t

    def ball(c, r):
        return ["--ball", ",".join("%.6g" % x for x in c) + ",%.6g" % r]

    for name in names:
        if name == "vase-wall":
            # blackVase (axis along z): the wall at mid-height, the vertex
            # farthest along +x within 1 % of the height of the middle
            src = os.path.join(real, "ggg_sfm", "blackVase.ply")
            V, _, _ = read_ply(src)
            zm = 0.5 * (V[:, 2].min() + V[:, 2].max())
            band = np.flatnonzero(np.abs(V[:, 2] - zm) < 0.01 * np.ptp(V[:, 2]))
            c = V[band[np.argmax(V[band, 0])]]
            cut(name, src, ball(c, 30), "blackVase: a ball of r 30 (about 6 h) on the wall at mid-height", 75)
        elif name in ("angel-knee", "angel-leg"):
            # the statue's knee: issue 61's ball, and a larger one that takes
            # the leg's front whole
            src = os.path.join(real, "ggg_sfm", "Angel.ply")
            c, r = (13.11, -64.51, 16.35), (15 if name == "angel-knee" else 25)
            cut(name, src, ball(c, r), "Angel: the knee, a ball of r %d (issue 61's)" % r
                if r == 15 else "Angel: the knee and shin, a ball of r %d" % r, 2.5 * r)
        elif name == "sphere-cap":
            # relief synth sphere-dimples' whole truth (radius 1): the cap
            # about its top vertex, 70 degrees across
            src = synth("sphere-dimples", 6000)
            V, _, _ = read_ply(src)
            c = V[np.argmax(V[:, 2])]
            cut(name, src, ball(c, 2 * math.sin(math.radians(35) / 2)),
                "sphere-dimples (r 1, 5762 vertices): the cap about the top vertex, a ball of r 0.60", 1.6)
        elif name == "head-border":
            # a partial range scan's border: the top vertex of lato000's outer
            # border, a ball of r 6 (about 11 h)
            src = os.path.join(real, "meshlab_rangemap_lato", "lato000.ply")
            V, F, _ = read_ply(src)
            c = V[border_vertex(V, F, 1)]
            cut(name, src, ball(c, 6), "lato000 (range scan of a head): a notch at the outer border's top vertex, r 6", 15,
                view="render")
        elif name == "cylinder-band":
            # relief synth cylinder-bands' whole truth (radius 1, axis z,
            # z 0..2, open ends): a slab 0.3 high through the middle vertex
            src = synth("cylinder-bands", 6000)
            V, _, _ = read_ply(src)
            zc = V[np.argmin(np.abs(V[:, 2] - np.median(V[:, 2]))), 2]
            mask = (0.0, 0.0, zc, math.hypot(1.05, 0.15))
            cut(name, src, ["--slab", "0,0,%.6g,0,0,1,0.15" % zc],
                "cylinder-bands (r 1, 6165 vertices): a band 0.3 high all round at mid-height", None, mask)
    return cases


SIZE = "320x320"  # the pictures'
# the pictures bench/mesh_holes.sh --figures copies into bench/figures (docs/benchmarks.md's)
FIGURES = {"angel-knee": ["truth", "relief-complete-told", "relief-points-told", "cgal", "pymeshlab"],
           "head-border": ["truth", "relief-complete-told", "cgal", "pymeshfix"],
           "cylinder-band": ["truth", "relief-complete-told", "cgal", "pymeshlab"]}
ALL = ["vase-wall", "angel-knee", "angel-leg", "sphere-cap", "head-border", "cylinder-band"]
QUICK = ["angel-knee", "sphere-cap", "cylinder-band"]

METHODS = [
    ("cut (no fill)", None),
    ("relief complete, told the hole", "relief-complete-told"),
    ("relief complete, defaults", "relief-complete"),
    ("relief depth-fill, told the hole", "relief-depth-told"),
    ("relief complete-points --mesh, told", "relief-points-told"),
    ("CGAL triangulate_refine_and_fair_hole", "cgal"),
    ("PyMeshLab meshing_close_holes", "pymeshlab"),
    ("pymeshfix MeshFix.repair", "pymeshfix"),
    ("trimesh repair.fill_holes", "trimesh"),
]


def main(argv):
    if argv and argv[0] == "--peer":
        return peer_main(argv[1:])
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 1
    relief, data, out = argv[:3]
    quick, only, timeout, figures = False, None, 300, None
    rest = argv[3:]
    while rest:
        a = rest.pop(0)
        if a == "--quick":
            quick = True
        elif a == "--only":
            only = rest.pop(0).split(",")
        elif a == "--figures":
            figures = rest.pop(0)
        elif a == "--timeout":
            timeout = int(rest.pop(0))
        else:
            print("mesh_holes.py: unknown option " + a, file=sys.stderr)
            return 1
    os.makedirs(out, exist_ok=True)
    row_py = os.path.join(HERE, "png_row.py")
    cases = make_cases(relief, data, out, only or (QUICK if quick else ALL))
    fields = ["case", "method", "rc", "coverage", "elsewhere", "capture_lost", "loops", "loop_edges",
              "selfint", "nonmanifold", "dist_mean", "dist_p95", "detail", "seconds", "fill_area",
              "faces", "h", "removed_vertices", "removed_area_h2", "truth_loops", "note"]
    csv_path = os.path.join(out, "mesh_holes.csv")
    md = []  # the same rows as a markdown table, OUT/mesh_holes.md
    fcsv = open(csv_path, "w", newline="")
    wcsv = csv.DictWriter(fcsv, fields)
    wcsv.writeheader()
    head = "%-38s %6s %6s %6s %10s %5s %11s %6s %7s" % (
        "method", "cover", "else", "lost", "loops(edg)", "s-int", "dist m/p95", "detail", "s")
    for case in cases:
        name, d = case["name"], os.path.join(out, case["name"])
        T = Truth(case["truth"], case["cut"])
        reg = case["region"].split()
        if case["mask"] is not None:
            mc, mr = np.array(case["mask"][:3]), case["mask"][3]
        else:
            b = [float(x) for x in reg[1].split(",")]
            mc, mr = np.array(b[:3]), b[3]
        mr += 2 * T.h
        mask = "ball:%s,%.6g" % (",".join("%.6g" % x for x in mc), mr)
        view = view_of(T, mc)
        if case.get("view") == "render":  # relief render's own, facing the capture
            _, _, _, err = run([relief, "render", case["truth"], "-o", os.path.join(d, "whole.png"),
                                "--size", SIZE], 120)
            view = err.split(", view ")[1].split(",", 2)[:2] if ", view " in err else None
            view = ",".join(view) if view else view_of(T, mc)
        cut_loops = T.loops_at_cut(*topology(T.cV, T.cF)[:2])
        print("\n== %s: %s\n   relief cut %s: %d vertices removed, removed area %.0f h^2, h %.4g; "
              "the cut's loops there: %s edges; the truth's: %s" % (
                  name, case["desc"], case["region"], T.removed_vertices, T.area / T.h ** 2, T.h,
                  "+".join(map(str, cut_loops)) or "none", "+".join(map(str, T.truth_loops)) or "none"))
        print("   " + head)
        pics = []
        for label, key in METHODS:
            outp = os.path.join(d, (key or "cut") + ".ply")
            rc, secs, note = 0, float("nan"), ""
            if key is None:
                outp = case["cut"]
            elif key.startswith("relief"):
                args = {"relief-complete-told": ["complete", case["cut"], "-o", outp, "--hole-mask", mask],
                        "relief-complete": ["complete", case["cut"], "-o", outp],
                        "relief-depth-told": ["depth-fill", case["cut"], "-o", outp, "--hole-mask", mask],
                        "relief-points-told": ["complete-points", case["cut"], "-o", os.path.join(d, "points.ply"),
                                               "--mesh", outp, "--hole-mask", mask]}[key]
                if os.path.exists(outp):
                    os.remove(outp)
                rc, secs, _, err = run([relief] + args + ["--quiet"], timeout)
                note = first_line(err)
            else:
                extra = {"cgal": ["ball=%s,%.6g" % (",".join("%.6g" % x for x in mc), mr)],
                         "pymeshlab": ["maxholesize=%d" % (max(cut_loops) + 1 if cut_loops else 30)]}.get(key, [])
                if os.path.exists(outp):
                    os.remove(outp)
                rc, secs, so, err = run([sys.executable, os.path.abspath(__file__), "--peer", key, case["cut"], outp]
                                        + extra, timeout)
                for ln in so.splitlines():
                    if ln.startswith("seconds "):
                        secs = float(ln.split()[1])
                    elif ln.startswith("note "):
                        note = ln[5:]
                if rc != 0:
                    note = first_line(err, ("Error", "error", "Exception")) or note
            row = dict(case=name, method=label, rc="timeout" if rc is None else rc, seconds=secs,
                       h=T.h, removed_vertices=T.removed_vertices, removed_area_h2=T.area / T.h ** 2,
                       truth_loops="+".join(map(str, T.truth_loops)), note=note)
            if rc == 0 and os.path.exists(outp):
                try:
                    V, F, props = read_mesh(outp)
                    row.update(measure(T, V, F))
                except Exception as e:  # a measure that fails is a row too
                    row["note"] = "measure failed: %s" % e
                    rc = "measure"
                else:
                    lab = props.get("label")
                    if key is None or (key and not key.startswith("relief")):
                        V, F, lab = new_faces_apart(V, F, T.cV, T.cF) if key else (V, F, None)
                    Vc, Fc, lc = crop(V, F, None if lab is None else lab.astype(np.int32), mc, case["crop"])
                    rp, png = os.path.join(d, (key or "cut") + "_view.ply"), os.path.join(d, (key or "cut") + ".png")
                    if os.path.exists(png):
                        os.remove(png)
                    write_ply(rp, Vc, Fc, lc)
                    run([relief, "render", rp, "-o", png, "--view", view, "--size", SIZE,
                         "--colour-by", "label" if lc is not None else "none"], 120)
                    os.remove(rp)
            png = os.path.join(d, (key or "cut") + ".png")
            if not (rc == 0 and os.path.exists(png)):
                blank_png(png)
            if key != "trimesh":  # it fills 3- and 4-edge holes only: the cut again
                pics.append(png)
            if rc == 0 and "coverage" in row:
                line = "%-38s %6s %6s %6s %10s %5s %11s %6s %7s" % (
                    label, fmt(row["coverage"]), fmt(row["elsewhere"]), fmt(row["capture_lost"]),
                    "%d (%d)" % (row["loops"], row["loop_edges"]), row["selfint"],
                    "%s/%s" % (fmt(row["dist_mean"]), fmt(row["dist_p95"])), fmt(row["detail"]),
                    fmt(secs, "%.1f"))
            else:
                line = "%-38s %s" % (label, "FAILED (exit %s): %s" % (row["rc"], row["note"][:110]))
            print("   " + line, flush=True)
            wcsv.writerow({k: (("%.4g" % v) if isinstance(v, float) else v) for k, v in row.items() if k in fields})
            md.append(markdown_row(row))
            fcsv.flush()
        # the truth, the removed part orange, first in the row
        Vc, Fc, lc = crop(T.V, T.F, read_ply(case["truth"])[2]["label"].astype(np.int32), mc, case["crop"])
        rp = os.path.join(d, "truth_view.ply")
        write_ply(rp, Vc, Fc, lc)
        run([relief, "render", rp, "-o", os.path.join(d, "truth.png"), "--view", view, "--size", SIZE,
             "--colour-by", "label"], 120)
        os.remove(rp)
        if pics and os.path.exists(os.path.join(d, "truth.png")):
            run([sys.executable, row_py, os.path.join(d, "row.png"), os.path.join(d, "truth.png")] + pics, 300)
    fcsv.close()
    with open(os.path.join(out, "mesh_holes.md"), "w") as f:
        f.write("| cut | method | coverage | added elsewhere | capture lost | open loops at the cut (edges) "
                "| self-intersecting at the cut | distance to truth, mean / p95 (h) | detail | s |\n"
                "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n" + "".join(md))
    if figures:
        for case in cases:
            for what in FIGURES.get(case["name"], []):
                src = os.path.join(out, case["name"], what + ".png")
                if os.path.exists(src):
                    shutil.copyfile(src, os.path.join(figures, "mesh_holes_%s_%s.png" % (case["name"], what)))
        print("bench: pictures for docs/benchmarks.md in %s/mesh_holes_*.png" % figures)
    print("\nbench: %s (and .md); pictures %s/CASE/*.png and row.png (truth, cut, then the methods in the table's order, trimesh left out; white: no output)" % (csv_path, out))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
