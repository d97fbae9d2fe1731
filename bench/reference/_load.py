"""Tiny numpy OBJ / OFF loader for the meshmark reference scripts.

load_mesh(path, drop_unreferenced=True) -> (V, F, info)
  V : (n,3) float64 vertex positions (file values parsed as double)
  F : (m,3) int64 triangles (polygons are fan-triangulated; see info['polys'])
  info : dict(n_records, n_unreferenced, dropped, polys=list-of-arrays or None,
              old_index = map new->file vertex index)

Unreferenced vertices (vertex records used by no face) are DROPPED by default:
for classic/bunny.obj this gives 35947 - 1113 = 34834 vertices, i.e. the
thesis' Bunny (N = 34835, Table 7.1, thesis line 1820) up to one vertex.
With drop_unreferenced=False they are kept (degree-0 rows in the Kirchhoff matrix).

Only `v` and `f` records are read (OBJ); `f a/b/c` and negative indices are handled.
OFF: ASCII OFF only (counts line, then vertices, then "k i0 i1 ..." faces).
"""
import numpy as np


def _finish(V, polys, drop_unreferenced):
    n_rec = len(V)
    sizes = np.array([len(p) for p in polys])
    if sizes.size and np.all(sizes == 3):
        F = np.asarray(polys, dtype=np.int64).reshape(-1, 3)
        poly_list = None
    else:
        tris = []
        for p in polys:                       # fan triangulation (loader only)
            p = np.asarray(p, dtype=np.int64)
            tris.append(np.stack([np.full(len(p) - 2, p[0]), p[1:-1], p[2:]], 1))
        F = np.concatenate(tris).astype(np.int64)
        poly_list = [np.asarray(p, dtype=np.int64) for p in polys]
    used = np.zeros(n_rec, bool)
    used[F.ravel()] = True
    n_unref = int(n_rec - used.sum())
    old_index = np.arange(n_rec)
    if drop_unreferenced and n_unref:
        remap = -np.ones(n_rec, np.int64)
        remap[used] = np.arange(used.sum())
        F = remap[F]
        if poly_list is not None:
            poly_list = [remap[p] for p in poly_list]
        V = V[used]
        old_index = old_index[used]
    info = dict(n_records=n_rec, n_unreferenced=n_unref,
                dropped=bool(drop_unreferenced and n_unref),
                polys=poly_list, old_index=old_index)
    return np.ascontiguousarray(V, dtype=np.float64), F, info


def load_obj(path, drop_unreferenced=True):
    verts, polys = [], []
    with open(path, "r", errors="replace") as fh:
        for line in fh:
            if line.startswith("v "):
                verts.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                polys.append(idx)
    return _finish(np.array(verts, dtype=np.float64), polys, drop_unreferenced)


def load_off(path, drop_unreferenced=True):
    with open(path, "r", errors="replace") as fh:
        toks = []
        for line in fh:
            line = line.split("#")[0].strip()
            if line:
                toks.append(line)
    head = toks[0]
    if head.startswith("OFF") and len(head.split()) > 1:
        counts, body = head.split()[1:], toks[1:]
    else:
        counts, body = toks[1].split(), toks[2:]
    nv, nf = int(counts[0]), int(counts[1])
    V = np.array([[float(t) for t in body[i].split()[:3]] for i in range(nv)])
    polys = []
    for i in range(nv, nv + nf):
        t = body[i].split()
        k = int(t[0])
        polys.append([int(x) for x in t[1:1 + k]])
    return _finish(V, polys, drop_unreferenced)


def load_mesh(path, drop_unreferenced=True):
    p = str(path).lower()
    if p.endswith(".obj"):
        return load_obj(path, drop_unreferenced)
    if p.endswith(".off"):
        return load_off(path, drop_unreferenced)
    raise ValueError("only .obj / .off supported: %s" % path)


def save_obj(path, V, F, fmt="%.6f"):
    """Write V/F as OBJ with the given float format (default = 6 decimals like many exporters)."""
    with open(path, "w") as fh:
        np.savetxt(fh, V, fmt="v " + " ".join([fmt] * 3))
        np.savetxt(fh, np.asarray(F) + 1, fmt="f %d %d %d")
