#!/usr/bin/env python3
"""Compare two STL solids by volume and bounding box.

    stlcmp.py A.stl B.stl [--volume REL] [--box ABS_REL] [--closed]

Reads binary or ASCII STL (OpenSCAD writes ASCII, sumi export binary),
prints each solid's volume (the signed sum of its triangles' tetrahedra
against the origin), bounding box and triangle count, and exits 1 when the
volumes differ by more than REL of the larger (default 1e-4) or a box
coordinate by more than ABS_REL of the larger box's longest side (default
1e-4). With --closed, B must also be closed and consistently oriented:
every directed edge (between points equal to the bit) once, and its
reverse once (a triangle that float32 collapses to a line left out).
Uses numpy when it is installed, plain Python otherwise.
"""
import struct
import sys

try:
    import numpy as np
except ImportError:  # plain Python below
    np = None


def read_stl(path):
    """The triangles of an STL file: a list of 9-tuples (or an n x 3 x 3 array)."""
    data = open(path, "rb").read()
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * n == len(data):  # binary: the size says so
            if np is not None:
                rec = np.frombuffer(data, dtype=np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")]),
                                    count=n, offset=84)
                return rec["v"].astype(np.float64)
            return [struct.unpack_from("<9f", data, 84 + 50 * i + 12) for i in range(n)]
    tris, cur = [], []
    for line in data.decode("ascii", "replace").splitlines():
        w = line.split()
        if w and w[0] == "vertex":
            cur.extend(float(x) for x in w[1:4])
            if len(cur) == 9:
                tris.append(tuple(cur))
                cur = []
    if np is not None:
        return np.array(tris, dtype=np.float64).reshape(-1, 3, 3)
    return tris


def measure(tris):
    """(volume, [min x, y, z], [max x, y, z], triangles)."""
    if np is not None:
        if len(tris) == 0:
            return 0.0, [0, 0, 0], [0, 0, 0], 0
        a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
        vol = float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6)
        pts = tris.reshape(-1, 3)
        return vol, list(pts.min(axis=0)), list(pts.max(axis=0)), len(tris)
    vol, lo, hi = 0.0, [float("inf")] * 3, [float("-inf")] * 3
    for t in tris:
        ax, ay, az, bx, by, bz, cx, cy, cz = t
        vol += ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
        for k in range(3):
            lo[k] = min(lo[k], t[k], t[3 + k], t[6 + k])
            hi[k] = max(hi[k], t[k], t[3 + k], t[6 + k])
    if not tris:
        lo, hi = [0, 0, 0], [0, 0, 0]
    return vol / 6, lo, hi, len(tris)


def open_edges(tris):
    """Directed edges of tris without exactly one reverse partner."""
    count = {}
    for t in (tris.reshape(-1, 9).tolist() if np is not None else tris):
        p = [tuple(t[0:3]), tuple(t[3:6]), tuple(t[6:9])]
        if p[0] == p[1] or p[1] == p[2] or p[2] == p[0]:
            continue  # two points one in float: its neighbours meet across it
        for k in range(3):
            e = (p[k], p[(k + 1) % 3])
            count[e] = count.get(e, 0) + 1
    return sum(1 for (a, b), n in count.items() if n != 1 or count.get((b, a), 0) != 1)


def main(argv):
    args, vol_tol, box_tol, closed = [], 1e-4, 1e-4, False
    i = 1
    while i < len(argv):
        if argv[i] == "--volume":
            vol_tol = float(argv[i + 1]); i += 2
        elif argv[i] == "--closed":
            closed = True; i += 1
        elif argv[i] == "--box":
            box_tol = float(argv[i + 1]); i += 2
        else:
            args.append(argv[i]); i += 1
    if len(args) != 2:
        sys.stderr.write(__doc__)
        return 2
    tris = [read_stl(p) for p in args]
    m = [measure(t) for t in tris]
    for p, (v, lo, hi, n) in zip(args, m):
        print("%s: volume %.6g, box [%s] [%s], %d triangles" %
              (p, v, ", ".join("%.6g" % x for x in lo), ", ".join("%.6g" % x for x in hi), n))
    (va, loa, hia, _), (vb, lob, hib, _) = m
    side = max([h - l for h, l in zip(hia, loa)] + [h - l for h, l in zip(hib, lob)] + [1e-300])
    dv = abs(va - vb) / max(abs(va), abs(vb), 1e-300)
    db = max(abs(x - y) for x, y in zip(loa + hia, lob + hib)) / side
    ok = dv <= vol_tol and db <= box_tol
    if closed:
        n_open = open_edges(tris[1])
        print("%s: %d edges without a reverse partner" % (args[1], n_open))
        ok = ok and n_open == 0
    print("volume differs by %.3g%% (allowed %.3g%%), box by %.3g%% of its side (allowed %.3g%%): %s" %
          (100 * dv, 100 * vol_tol, 100 * db, 100 * box_tol, "same" if ok else "DIFFERENT"))
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))
