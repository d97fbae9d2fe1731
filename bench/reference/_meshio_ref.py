"""Minimal, dependency-light mesh reader for the reference (oracle) scripts.

Used only by attacks_ref.py / metrics_ref.py / check_attacks_metrics_ref.py.
Returns float64 vertices (N,3) and int64 triangles (M,3); polygons are
fan-triangulated (v0,vi,vi+1) in file order.  Vertex order is the file order
and unreferenced vertices are KEPT (drop them with attacks_ref.remove_unreferenced).

Supported: OBJ (``v``/``f`` records, ``a/b/c`` index syntax, negative indices),
ASCII OFF, PLY (ASCII or binary, through ``plyfile``).
"""
from __future__ import annotations

import os

import numpy as np

__all__ = ["load_mesh", "triangulate_polygons"]


def triangulate_polygons(polys):
    """Fan-triangulate a list of index sequences (grouped by length, no per-face loop)."""
    polys = [np.asarray(p, dtype=np.int64) for p in polys]
    if not polys:
        return np.zeros((0, 3), np.int64)
    lens = np.fromiter((len(p) for p in polys), dtype=np.int64, count=len(polys))
    out = []
    order = []
    for n in np.unique(lens):
        if n < 3:
            continue
        sel = np.nonzero(lens == n)[0]
        P = np.stack([polys[i] for i in sel])           # (k, n)
        k = np.arange(1, n - 1)
        tris = np.stack([np.repeat(P[:, :1], n - 2, 1), P[:, k], P[:, k + 1]], axis=-1)
        out.append(tris.reshape(-1, 3))
        order.append(np.repeat(sel, n - 2) * 1_000_000 + np.tile(k, len(sel)))
    if not out:
        return np.zeros((0, 3), np.int64)
    T = np.concatenate(out)
    return T[np.argsort(np.concatenate(order), kind="stable")]


def _load_obj(path):
    with open(path, "r", errors="replace") as fh:
        lines = fh.read().splitlines()
    vlines = [l for l in lines if l.startswith("v ") or l.startswith("v\t")]
    flines = [l for l in lines if l.startswith("f ") or l.startswith("f\t")]
    V = np.array(" ".join(l[2:] for l in vlines).split(), dtype=np.float64)
    # 'v x y z [w|r g b]' -> keep the first three values of each record
    counts = np.array([len(l.split()) - 1 for l in vlines])
    if np.all(counts == 3):
        V = V.reshape(-1, 3)
    else:
        starts = np.concatenate([[0], np.cumsum(counts)[:-1]])
        V = V[starts[:, None] + np.arange(3)[None, :]]
    nv = len(V)
    text = " ".join(l[2:] for l in flines)
    toks = text.split()
    if "/" in text:  # 'v/vt/vn' -> 'v'
        toks = [t.split("/", 1)[0] for t in toks]
    idx = np.array(toks, dtype=np.int64)
    idx = np.where(idx > 0, idx - 1, nv + idx)           # OBJ is 1-based; negatives are relative
    if len(idx) == 3 * len(flines):                      # every face has >= 3 corners
        return V, idx.reshape(-1, 3)
    fcounts = np.array([len(l.split()) - 1 for l in flines], dtype=np.int64)
    polys = np.split(idx, np.cumsum(fcounts)[:-1])
    return V, triangulate_polygons(polys)


def _load_off(path):
    with open(path, "r", errors="replace") as fh:
        toks = []
        for line in fh:
            line = line.split("#", 1)[0].strip()
            if line:
                toks.append(line)
    head = toks[0].split()
    if head[0].upper().endswith("OFF") and len(head) == 1:
        counts = toks[1].split()
        body = toks[2:]
    else:  # 'OFF nv nf ne' on one line
        counts = head[1:]
        body = toks[1:]
    nv, nf = int(counts[0]), int(counts[1])
    V = np.array(" ".join(body[:nv]).split(), dtype=np.float64).reshape(nv, -1)[:, :3]
    flines = body[nv:nv + nf]
    arr = np.array(" ".join(flines).split(), dtype=np.int64)
    if arr.size == 4 * nf and np.all(arr[0::4] == 3):   # all triangles (no per-face colours)
        return V, arr.reshape(-1, 4)[:, 1:]
    polys = []
    for l in flines:  # general polygons / trailing colour values
        a = l.split()
        n = int(a[0])
        polys.append([int(x) for x in a[1:1 + n]])
    return V, triangulate_polygons(polys)


def _load_ply(path):
    from plyfile import PlyData

    ply = PlyData.read(path)
    v = ply["vertex"]
    V = np.stack([np.asarray(v["x"], np.float64), np.asarray(v["y"], np.float64),
                  np.asarray(v["z"], np.float64)], axis=1)
    F = np.zeros((0, 3), np.int64)
    if "face" in ply:
        fe = ply["face"]
        name = "vertex_indices" if "vertex_indices" in fe.data.dtype.names else "vertex_index"
        raw = fe[name]
        try:
            F = np.asarray(np.stack(raw), np.int64)
            if F.shape[1] != 3:
                F = triangulate_polygons(list(F))
        except ValueError:
            F = triangulate_polygons(list(raw))
    return V, F


def load_mesh(path):
    """Return (V float64 (N,3), F int64 (M,3))."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".obj":
        return _load_obj(path)
    if ext == ".off":
        return _load_off(path)
    if ext == ".ply":
        return _load_ply(path)
    raise ValueError(f"unsupported mesh format: {ext}")
