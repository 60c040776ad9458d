#!/usr/bin/env python3
"""Checks a triangle mesh, independently of the mesher that wrote it (needs numpy).

    mesh_check.py MESH.{obj,ply,stl} [--vm MODEL.vm [--clip XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX]]
                  [--cell H]

Prints one JSON object:
- triangles, vertices (those used by a triangle), degenerate (repeated index or zero
  area), components (connected by shared vertices), euler (V - E + F);
- boundary_edges (used once), non_manifold_edges (three times or more),
  misoriented_edges (twice in the same direction); watertight: none of the three, i.e.
  every edge shared by exactly two triangles in opposite directions;
- non_manifold_vertices: vertices whose triangles form more than one fan (joined
  through the edges at the vertex); manifold: watertight and no such vertex;
- self_intersections: triangle pairs that cross, over a uniform grid of their boxes.
  Pairs sharing no vertex: an edge of one crosses the other's interior; pairs sharing
  one vertex: the edge opposite it crosses the other. Strict sign tests of f64
  orientation determinants (not exact predicates; an edge end within 1e-12 of the
  cube of the pair's extent of the other's plane counts as in it): touching and
  coplanar overlaps are not counted, nor are pairs sharing an edge;
- with --vm: the largest distance of a used vertex to the surface, estimated to first
  order as |f| / |grad f| (gradient by central differences), f the .vm tape evaluated in
  f64; with --clip, f is the shape clipped to the box (min of -f and the box's
  distances, our `tracer mesh`'s clip), so vertices on the caps count as on the surface.
  max_distance is in model units; with --cell H also in cells (max_distance_cells).

STL is binary; its vertices are merged where their coordinates are equal.
Bad input gives one line on stderr and exit code 2.
"""
import argparse
import json
import math
import struct
import sys

import numpy as np


class Bad(Exception):
    pass


# ---------------------------------------------------------------- reading meshes


def read_obj(path):
    verts, tris = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for n, line in enumerate(f, 1):
            w = line.split()
            if not w:
                continue
            try:
                if w[0] == "v":
                    verts.append([float(x) for x in w[1:4]])
                elif w[0] == "f":
                    idx = [int(x.split("/")[0]) for x in w[1:]]
                    idx = [i - 1 if i > 0 else len(verts) + i for i in idx]
                    for k in range(1, len(idx) - 1):  # fan a polygon
                        tris.append([idx[0], idx[k], idx[k + 1]])
            except ValueError:
                raise Bad(f"{path}:{n}: cannot read '{line.strip()}'")
    return np.array(verts, dtype=np.float64).reshape(-1, 3), np.array(tris, dtype=np.int64).reshape(-1, 3)


PLY_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4",
             "uint": "u4", "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1",
             "int16": "i2", "uint16": "u2", "int32": "i4", "uint32": "u4",
             "float32": "f4", "float64": "f8"}


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.find(b"end_header\n")
    if not data.startswith(b"ply\n") or end < 0:
        raise Bad(f"{path}: not a PLY file")
    header = data[:end].decode("ascii", errors="replace").splitlines()
    if "format binary_little_endian 1.0" not in header:
        raise Bad(f"{path}: only binary little-endian PLY is read")
    elements = []  # (name, count, [(prop, type or (count type, item type))])
    for line in header:
        w = line.split()
        if w[:1] == ["element"]:
            elements.append((w[1], int(w[2]), []))
        elif w[:1] == ["property"]:
            if w[1] == "list":
                elements[-1][2].append((w[4], (PLY_TYPES[w[2]], PLY_TYPES[w[3]])))
            else:
                elements[-1][2].append((w[2], PLY_TYPES[w[1]]))
    pos = end + len(b"end_header\n")
    verts = tris = None
    for name, count, props in elements:
        if name == "vertex":
            if any(isinstance(t, tuple) for _, t in props):
                raise Bad(f"{path}: list property in the vertices")
            dt = np.dtype([(p, "<" + t) for p, t in props])
            arr = np.frombuffer(data, dtype=dt, count=count, offset=pos)
            pos += dt.itemsize * count
            verts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
        elif name == "face":
            if len(props) != 1 or not isinstance(props[0][1], tuple):
                raise Bad(f"{path}: faces must have one list property")
            ct, it = props[0][1]
            # Triangles only: a fixed record of the count and three indices.
            dt = np.dtype([("n", "<" + ct), ("i", "<" + it, (3,))])
            arr = np.frombuffer(data, dtype=dt, count=count, offset=pos)
            if count and not np.all(arr["n"] == 3):
                raise Bad(f"{path}: faces other than triangles")
            pos += dt.itemsize * count
            tris = arr["i"].astype(np.int64)
        else:
            raise Bad(f"{path}: element '{name}' is not read")
    if verts is None or tris is None:
        raise Bad(f"{path}: no vertex or face element")
    return verts, tris


def read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 84:
        raise Bad(f"{path}: too short for a binary STL")
    (n,) = struct.unpack_from("<I", data, 80)
    if len(data) != 84 + 50 * n:
        raise Bad(f"{path}: not a binary STL ({len(data)} bytes for {n} triangles)")
    dt = np.dtype([("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    arr = np.frombuffer(data, dtype=dt, count=n, offset=84)
    flat = arr["v"].reshape(-1, 3)
    verts, inv = np.unique(flat, axis=0, return_inverse=True)
    return verts.astype(np.float64), inv.reshape(-1, 3).astype(np.int64)


def read_mesh(path):
    ext = path.rsplit(".", 1)[-1].lower()
    try:
        reader = {"obj": read_obj, "ply": read_ply, "stl": read_stl}[ext]
    except KeyError:
        raise Bad(f"{path}: the extension must be .obj, .ply or .stl")
    try:
        v, t = reader(path)
    except OSError as e:
        raise Bad(f"{path}: {e.strerror}")
    except (ValueError, KeyError, IndexError) as e:
        raise Bad(f"{path}: malformed ({e})")
    if len(t) and (t.min() < 0 or t.max() >= len(v)):
        raise Bad(f"{path}: a triangle refers to a missing vertex")
    return v, t


# ---------------------------------------------------------------- topology


def components(n, a, b):
    """Connected-component labels of n nodes joined by the pairs (a[i], b[i])."""
    lab = np.arange(n)
    while True:
        new = lab.copy()
        np.minimum.at(new, a, lab[b])
        np.minimum.at(new, b, lab[a])
        while True:  # pointer jumping
            j = new[new]
            if np.array_equal(j, new):
                break
            new = j
        if np.array_equal(new, lab):
            return lab
        lab = new


def topology(v, t):
    F = len(t)
    used = np.unique(t)
    # Directed half-edges (from, to) of triangle corner k: t[k] -> t[k+1].
    frm = t.reshape(-1)
    to = t[:, [1, 2, 0]].reshape(-1)
    tri_of = np.repeat(np.arange(F), 3)
    lo, hi = np.minimum(frm, to), np.maximum(frm, to)
    nv = int(t.max()) + 1 if F else 0
    key = lo * nv + hi
    order = np.argsort(key, kind="stable")
    ks = key[order]
    uniq, start, count = np.unique(ks, return_index=True, return_counts=True)
    boundary = int(np.sum(count == 1))
    non_manifold_edges = int(np.sum(count >= 3))
    two = start[count == 2]
    e1, e2 = order[two], order[two + 1]
    misoriented = int(np.sum(frm[e1] == frm[e2]))

    # Fans: corners (triangle, vertex) joined when their triangles share an edge at that
    # vertex. For an edge used k >= 2 times, its uses are chained.
    ja, jb = [], []
    first = np.repeat(start, count)  # for each sorted half-edge, its group's start
    nxt = np.nonzero(np.arange(len(ks)) > first)[0]  # every use after the first
    h1, h2 = order[nxt - 1], order[nxt]
    # the corner of triangle T at vertex V has id 3*T + position of V in T
    def corner(h, vert):
        tri = tri_of[h]
        pos = np.argmax(t[tri] == vert[:, None], axis=1)
        return 3 * tri + pos

    for end in (lo, hi):
        va = end[h1]
        ja.append(corner(h1, va))
        jb.append(corner(h2, va))
    ja = np.concatenate(ja) if ja else np.zeros(0, np.int64)
    jb = np.concatenate(jb) if jb else np.zeros(0, np.int64)
    lab = components(3 * F, ja, jb)
    cv = t.reshape(-1)
    fans = np.unique(np.stack([cv, lab], axis=1), axis=0)
    fans_per_vertex = np.bincount(fans[:, 0], minlength=nv)
    non_manifold_vertices = int(np.sum(fans_per_vertex[used] > 1))

    comp = components(nv, frm, to)
    ncomp = len(np.unique(comp[used]))
    d = v[t[:, 1]] - v[t[:, 0]]
    e = v[t[:, 2]] - v[t[:, 0]]
    area2 = np.linalg.norm(np.cross(d, e), axis=1)
    repeated = (t[:, 0] == t[:, 1]) | (t[:, 1] == t[:, 2]) | (t[:, 0] == t[:, 2])
    watertight = boundary == 0 and non_manifold_edges == 0 and misoriented == 0
    return {
        "triangles": F,
        "vertices": len(used),
        "degenerate": int(np.sum(repeated | (area2 == 0))),
        "components": ncomp,
        "euler": int(len(used) - len(uniq) + F),
        "boundary_edges": boundary,
        "non_manifold_edges": non_manifold_edges,
        "misoriented_edges": misoriented,
        "non_manifold_vertices": non_manifold_vertices,
        "watertight": watertight,
        "manifold": watertight and non_manifold_vertices == 0,
    }


# ---------------------------------------------------------------- self-intersections


def orient(a, b, c, d):
    return np.einsum("ij,ij->i", b - a, np.cross(c - a, d - a))


def segment_crosses(p, q, u, v, w):
    """Whether segment pq crosses the interior of triangle uvw (strict, per row). An end
    within rounding of the plane (|orientation| below 1e-12 of the cube of the pair's
    extent: coplanar or touching) does not cross."""
    s1, s2 = orient(u, v, w, p), orient(u, v, w, q)
    pts = np.stack([p, q, u, v, w], axis=1)
    ext = (pts.max(axis=1) - pts.min(axis=1)).max(axis=1)
    tol = 1e-12 * ext ** 3
    across = ((s1 > tol) & (s2 < -tol)) | ((s1 < -tol) & (s2 > tol))
    t1, t2, t3 = orient(p, q, u, v), orient(p, q, v, w), orient(p, q, w, u)
    inside = ((t1 > 0) & (t2 > 0) & (t3 > 0)) | ((t1 < 0) & (t2 < 0) & (t3 < 0))
    return across & inside


def candidate_pairs(lo, hi):
    """Pairs (i < j) of overlapping boxes, over a uniform grid: each pair is taken once,
    in the grid cell holding the lowest corner of the two boxes' intersection."""
    F = len(lo)
    ext = (hi - lo).max(axis=1)
    size = max(float(np.median(ext)), 1e-300)
    while True:
        a = np.floor(lo / size).astype(np.int64)
        b = np.floor(hi / size).astype(np.int64)
        n = b - a + 1
        per = n.prod(axis=1)
        if per.sum() <= 40 * F + 1000:
            break
        size *= 2.0
    tri = np.repeat(np.arange(F), per)
    r = np.arange(per.sum()) - np.repeat(np.cumsum(per) - per, per)
    nx, ny = n[tri, 0], n[tri, 1]
    cell = np.stack([a[tri, 0] + r % nx, a[tri, 1] + (r // nx) % ny,
                     a[tri, 2] + r // (nx * ny)], axis=1)
    c0 = cell - cell.min(axis=0)
    dims = c0.max(axis=0) + 1
    key = (c0[:, 2] * dims[1] + c0[:, 1]) * dims[0] + c0[:, 0]
    order = np.argsort(key, kind="stable")
    key, tri, cell = key[order], tri[order], cell[order]
    pairs = []
    d = 1
    while d < len(key):
        same = np.nonzero(key[:-d] == key[d:])[0]
        if len(same) == 0:
            break
        i, j = tri[same], tri[same + d]
        ok = np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)
        corner = np.floor(np.maximum(lo[i], lo[j]) / size).astype(np.int64)
        ok &= np.all(corner == cell[same], axis=1)
        i, j = i[ok], j[ok]
        pairs.append(np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1))
        d += 1
    if not pairs:
        return np.zeros((0, 2), np.int64)
    return np.concatenate(pairs)


def self_intersection_flags(v, t, pairs):
    """For each candidate pair (i, j), whether triangles i and j cross (see the module
    doc: no shared vertex, any edge through the other; one shared vertex, the edge
    opposite it through the other; more shared vertices: not counted)."""
    hit = np.zeros(len(pairs), bool)
    for s in range(0, len(pairs), 1 << 20):
        i, j = pairs[s:s + (1 << 20), 0], pairs[s:s + (1 << 20), 1]
        A, B = t[i], t[j]
        eq = A[:, :, None] == B[:, None, :]  # (P, 3, 3)
        shared = eq.sum(axis=(1, 2))
        chunk = np.zeros(len(i), bool)
        m = shared == 0
        if m.any():
            PA, PB = v[A[m]], v[B[m]]
            h = np.zeros(int(m.sum()), bool)
            for X, Y in ((PA, PB), (PB, PA)):
                for k in range(3):
                    h |= segment_crosses(X[:, k], X[:, (k + 1) % 3], Y[:, 0], Y[:, 1], Y[:, 2])
            chunk[m] = h
        m = shared == 1
        if m.any():
            h = np.zeros(int(m.sum()), bool)
            for X, Y, posx in ((A[m], B[m], eq[m].any(axis=2)), (B[m], A[m], eq[m].any(axis=1))):
                k = np.argmax(posx, axis=1)
                rows = np.arange(len(k))
                p = v[X[rows, (k + 1) % 3]]
                q = v[X[rows, (k + 2) % 3]]
                Yv = v[Y]
                h |= segment_crosses(p, q, Yv[:, 0], Yv[:, 1], Yv[:, 2])
            chunk[m] = h
        hit[s:s + len(i)] = chunk
    return hit


def self_intersections(v, t):
    if len(t) < 2:
        return 0
    tv = v[t]  # (F, 3, 3)
    pairs = candidate_pairs(tv.min(axis=1), tv.max(axis=1))
    return int(self_intersection_flags(v, t, pairs).sum())


# ---------------------------------------------------------------- the model


UNARY = {"neg": np.negative, "abs": np.abs, "sqrt": np.sqrt, "square": np.square,
         "sin": np.sin, "cos": np.cos, "tan": np.tan, "asin": np.arcsin, "acos": np.arccos,
         "atan": np.arctan, "exp": np.exp, "ln": np.log, "floor": np.floor, "ceil": np.ceil,
         "round": np.round}
BINARY = {"add": np.add, "sub": np.subtract, "mul": np.multiply, "div": np.divide,
          "min": np.minimum, "max": np.maximum, "atan2": np.arctan2,
          "mod": lambda a, b: np.mod(a, np.abs(b))}


def read_vm(path):
    """The tape of a .vm file: (name, op, args) per line; the last line is the root."""
    try:
        text = open(path, encoding="utf-8").read()
    except (OSError, UnicodeDecodeError) as e:
        raise Bad(f"{path}: {e}")
    tape, seen = [], set()
    for n, line in enumerate(text.splitlines(), 1):
        w = line.split()
        if not w or line.startswith("#"):
            continue
        if len(w) < 2:
            raise Bad(f"{path}:{n}: no opcode")
        name, op, args = w[0], w[1], w[2:]
        if op in ("var-x", "var-y", "var-z"):
            args = []
        elif op == "const":
            try:
                args = [float(args[0])]
            except (IndexError, ValueError):
                raise Bad(f"{path}:{n}: const needs a number")
        elif op in UNARY or op in BINARY:
            k = 1 if op in UNARY else 2
            if len(args) < k or any(a not in seen for a in args[:k]):
                raise Bad(f"{path}:{n}: {op} needs {k} earlier names")
            args = args[:k]
        else:
            raise Bad(f"{path}:{n}: opcode '{op}' is not evaluated by mesh_check.py")
        tape.append((name, op, args))
        seen.add(name)
    if not tape:
        raise Bad(f"{path}: no instruction")
    return tape


def eval_vm(tape, p):
    vals = {}
    with np.errstate(all="ignore"):
        for name, op, args in tape:
            if op == "var-x":
                r = p[:, 0]
            elif op == "var-y":
                r = p[:, 1]
            elif op == "var-z":
                r = p[:, 2]
            elif op == "const":
                r = np.full(len(p), args[0])
            elif op in UNARY:
                r = UNARY[op](vals[args[0]])
            else:
                r = BINARY[op](vals[args[0]], vals[args[1]])
            vals[name] = r
    return vals[tape[-1][0]]


def distances(tape, v, clip, step):
    def g(p):
        f = eval_vm(tape, p)  # fidget's sign: f < 0 inside
        if clip is None:
            return f
        lo, hi = np.array(clip[:3]), np.array(clip[3:])
        box = np.minimum(p - lo, hi - p).min(axis=1)
        return -np.minimum(-f, box)

    out = []
    for s in range(0, len(v), 1 << 16):
        p = v[s:s + (1 << 16)]
        f = g(p)
        grad = np.zeros_like(p)
        for k in range(3):
            e = np.zeros(3)
            e[k] = step
            grad[:, k] = (g(p + e) - g(p - e)) / (2 * step)
        with np.errstate(all="ignore"):
            d = np.abs(f) / np.linalg.norm(grad, axis=1)
        d[f == 0] = 0.0
        out.append(d)
    return np.concatenate(out) if out else np.zeros(0)


# ---------------------------------------------------------------- main


def box(s):
    try:
        b = [float(x) for x in s.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError(f"'{s}' is not six numbers")
    if len(b) != 6 or not all(math.isfinite(x) for x in b) or not all(b[k] < b[k + 3] for k in range(3)):
        raise argparse.ArgumentTypeError(f"'{s}' is not XMIN,YMIN,ZMIN,XMAX,YMAX,ZMAX with min < max")
    return b


def positive(s):
    try:
        x = float(s)
    except ValueError:
        x = float("nan")
    if not (math.isfinite(x) and x > 0):
        raise argparse.ArgumentTypeError(f"'{s}' is not a positive number")
    return x


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("mesh")
    ap.add_argument("--vm", help="the model's .vm tape, for the distance to the surface")
    ap.add_argument("--clip", type=box, help="the box the mesh was clipped to")
    ap.add_argument("--cell", type=positive, help="the cell size, to report distances in cells")
    a = ap.parse_args()
    try:
        v, t = read_mesh(a.mesh)
        tape = read_vm(a.vm) if a.vm else None
        out = topology(v, t) if len(t) else {"triangles": 0}
        out["self_intersections"] = self_intersections(v, t)
        if tape is not None:
            used = v[np.unique(t)] if len(t) else np.zeros((0, 3))
            span = float(np.ptp(used, axis=0).max()) if len(used) else 1.0
            step = (a.cell or span / 64) * 1e-3
            d = distances(tape, used, a.clip, step)
            dmax = float(np.nanmax(d)) if len(d) else 0.0
            out["max_distance"] = dmax
            out["nan_distances"] = int(np.isnan(d).sum())
            if a.cell:
                out["max_distance_cells"] = dmax / a.cell
    except Bad as e:
        print(f"mesh_check.py: error: {e}", file=sys.stderr)
        sys.exit(2)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
