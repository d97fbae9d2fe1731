"""Where a mesh comes from, and which meshes are the same geometry (docs/steganalysis.md §6, "Sources").

* :func:`source_of` — the collection a file was taken from: for ``../shared/meshes/corpus-large/<folder>/...``
  the folder; for ``classic/`` and ``corpus/`` the repository of its row in ``SOURCES.md`` under the same
  name (``kmammou/v-hacd`` -> ``v-hacd``, ``odedstein/meshes`` -> ``odedstein-meshes``, the Thingi10K files
  of ``DragonAceNL/MeshPrep`` -> ``thingi10k``); anything else: its parent folder's name.
* :func:`geometry_key` / :func:`geometry_hash` — a canonical form of the geometry that does not depend on
  the file format, the vertex or face order or duplicated vertex records: the referenced vertices welded
  on equal coordinates, centred on the bounding-box centre and divided by its diagonal, each coordinate
  column sorted; with the number of vertices and triangles.
* :func:`deduplicate` — groups of files that are byte-identical or have the same canonical geometry
  (columns equal to ``tol`` = 1e-5 of the diagonal: float32 against text storage of one mesh); the first
  file of each group (sorted by path) represents it.
"""
from __future__ import annotations

import hashlib
import pathlib
import re

import numpy as np

_REPO_SOURCE = {"odedstein/meshes": "odedstein-meshes", "DragonAceNL/MeshPrep": "thingi10k"}
_TABLE: dict = {}


def _shared_root(p: pathlib.Path):
    parts = p.resolve().parts
    for i in range(len(parts) - 1, 0, -1):
        if parts[i - 1] == "shared" and parts[i] == "meshes":
            return pathlib.Path(*parts[: i + 1]), parts[i + 1:]
    return None, parts


def _sources_table(root: pathlib.Path) -> dict:
    """relative path -> source repository of root/SOURCES.md (classic/, corpus/ rows)."""
    key = str(root)
    if key not in _TABLE:
        rows = {}
        f = root / "SOURCES.md"
        if f.is_file():
            for line in f.read_text(errors="replace").splitlines():
                m = re.match(r"\| `([^`]+)` \|.*?\| `([\w.-]+/[\w.-]+):", line)
                if m:
                    rows[m.group(1)] = m.group(2)
        _TABLE[key] = rows
    return _TABLE[key]


def source_of(path) -> str:
    """The collection of one mesh file (see the module docstring)."""
    p = pathlib.Path(str(path).split("#")[0])
    root, rel = _shared_root(p)
    if root is not None and len(rel) >= 2:
        if rel[0] == "corpus-large" and len(rel) >= 3:
            return rel[1]
        repo = _sources_table(root).get("/".join(rel))
        if repo:
            return _REPO_SOURCE.get(repo, repo.split("/")[1])
    return p.parent.name or "."


def geometry_key(mesh):
    """(n_vertices, n_triangles, (n, 3) sorted normalised coordinate columns) of a Mesh."""
    T = np.asarray(mesh.triangles)
    V = np.asarray(mesh.V, float)[np.unique(T)] if len(T) else np.zeros((0, 3))
    V = np.unique(V, axis=0)  # weld on equal coordinates (STL corners, duplicated records)
    lo, hi = V.min(0), V.max(0)
    diag = float(np.linalg.norm(hi - lo)) or 1.0
    C = np.sort((V - (lo + hi) / 2) / diag, axis=0)
    return len(V), len(T), C


def geometry_hash(mesh) -> str:
    """sha256 of geometry_key with the columns rounded to 1e-6 of the diagonal: equal for the same coordinates
    in another format, vertex or face order. Storage rounding (float32 against text) can move a coordinate
    across a 1e-6 step, so deduplicate compares the keys with a tolerance instead of the hashes."""
    n, t, C = geometry_key(mesh)
    h = hashlib.sha256(f"{n} {t}\n".encode())
    h.update(np.round(C * 1e6).astype(np.int64).tobytes())
    return h.hexdigest()


def deduplicate(paths, tol: float = 1e-5, read=None):
    """Groups (lists of paths, sorted) of the same mesh: byte-identical files, then the same geometry_key
    to ``tol``. Unreadable files are their own group. Returns the groups, singletons included, ordered by
    their first path."""
    from .._core import MeshError
    from ..io import read_mesh
    read = read or read_mesh
    paths = sorted(pathlib.Path(p) for p in paths)
    by_bytes: dict = {}
    for p in paths:
        by_bytes.setdefault(hashlib.sha256(p.read_bytes()).hexdigest(), []).append(p)
    reps = [g[0] for g in by_bytes.values()]
    group = {g[0]: list(g) for g in by_bytes.values()}
    keys = {}
    for p in reps:
        try:
            keys[p] = geometry_key(read(p))
        except MeshError:
            keys[p] = None
    buckets: dict = {}
    for p in reps:
        if keys[p] is not None:
            buckets.setdefault(keys[p][:2], []).append(p)
    merged = {p: p for p in reps}
    for ps in buckets.values():
        for i, a in enumerate(ps):
            if merged[a] is not a:
                continue
            for b in ps[i + 1:]:
                if merged[b] is b and np.abs(keys[a][2] - keys[b][2]).max() <= tol:
                    merged[b] = a
    out: dict = {}
    for p in reps:
        out.setdefault(merged[p], []).extend(group[p])
    return sorted((sorted(g) for g in out.values()), key=lambda g: g[0])
