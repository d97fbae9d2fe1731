"""Minimal mesh loader for the radial-watermark reference code (phase 1).

Only what the reference/check scripts need: OBJ (``v`` / ``f`` records,
``a/b/c`` face tokens, negative indices, polygons fan-triangulated) and ASCII
OFF.  Pure numpy, no third-party mesh library.

``load_mesh(path, drop_unreferenced=True)`` returns ``(V, F)`` with ``V`` a
float64 (n, 3) array and ``F`` an int64 (m, 3) array.  With
``drop_unreferenced`` the vertices referenced by no face are removed and ``F``
is re-indexed (classic/bunny.obj has 1113 such vertices; without them it has
34834 vertices, the thesis' Table 6.1 lists 34835).
"""
from __future__ import annotations

import numpy as np


def _fan(polys):
    tris = []
    for p in polys:
        for j in range(1, len(p) - 1):
            tris.append((p[0], p[j], p[j + 1]))
    return tris


def _load_obj(path):
    verts, polys = [], []
    with open(path, "r", errors="replace") as fh:
        for line in fh:
            if line.startswith("v "):
                parts = line.split()
                verts.append((float(parts[1]), float(parts[2]), float(parts[3])))
            elif line.startswith("f "):
                idx = []
                for tok in line.split()[1:]:
                    i = int(tok.split("/")[0])
                    idx.append(i - 1 if i > 0 else len(verts) + i)
                polys.append(idx)
    V = np.asarray(verts, dtype=np.float64).reshape(-1, 3)
    F = np.asarray(_fan(polys), dtype=np.int64).reshape(-1, 3)
    return V, F


def _load_off(path):
    with open(path, "r", errors="replace") as fh:
        toks = []
        for line in fh:
            line = line.split("#")[0].strip()
            if line:
                toks.extend(line.split())
    if not toks[0].upper().endswith("OFF"):
        raise ValueError("not an ASCII OFF file: %s" % path)
    pos = 1
    nv, nf = int(toks[pos]), int(toks[pos + 1])
    pos += 3
    V = np.asarray(toks[pos:pos + 3 * nv], dtype=np.float64).reshape(nv, 3)
    pos += 3 * nv
    polys = []
    for _ in range(nf):
        k = int(toks[pos])
        polys.append([int(t) for t in toks[pos + 1:pos + 1 + k]])
        pos += 1 + k
    F = np.asarray(_fan(polys), dtype=np.int64).reshape(-1, 3)
    return V, F


def load_mesh(path, drop_unreferenced=True):
    p = str(path)
    if p.lower().endswith(".obj"):
        V, F = _load_obj(p)
    elif p.lower().endswith(".off"):
        V, F = _load_off(p)
    else:
        raise ValueError("radial_load handles .obj and ASCII .off only: %s" % p)
    if drop_unreferenced and len(F):
        used = np.zeros(len(V), dtype=bool)
        used[F.ravel()] = True
        if not used.all():
            remap = np.cumsum(used) - 1
            V = V[used]
            F = remap[F]
    return V, F
