"""The meshes of a study: the built-in ones (``builtin:NAME``), loading a mesh file (or its bytes
shipped to a Dask worker), compaction, the welded vertex count a spec's ``min_vertices`` compares and
the content digest that keys a mesh's tasks."""
from __future__ import annotations

import hashlib
import os
import tempfile

import numpy as np

from .._core import MeshError
from ..mesh import Mesh

MESH_SUFFIXES = (".obj", ".off", ".ply", ".stl")

BUILTINS = ("torus", "cylinder", "default", "arm")


def builtin_mesh(name: str) -> Mesh:
    from .. import shapes
    if name == "torus":
        return shapes.torus()
    if name == "cylinder":
        return shapes.cylinder()
    if name == "default":
        return shapes.default_mesh()
    if name == "arm":  # the jittered arm of tests/test_laplacian_watermark.py (20k vertices)
        m = shapes.cylinder(segments=64, rings=320)
        h = 2 * np.pi * 0.15 / 64
        return m.with_vertices(m.V + np.random.default_rng(0).uniform(-0.25, 0.25, m.V.shape) * h)
    raise MeshError(f"unknown built-in mesh {name!r} (known: {', '.join(BUILTINS)})")


def compact(m: Mesh) -> Mesh:
    """Unreferenced vertices dropped, triangulated (as examples/attack_table.py measured)."""
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return Mesh(m.V[used], (np.cumsum(used) - 1)[m.triangles])


def load_mesh(path: str, data: bytes | None = None, do_compact: bool = False) -> Mesh:
    from ..io import read_mesh
    if path.startswith("builtin:"):
        m = builtin_mesh(path.split(":", 1)[1])
    elif data is not None:  # bytes shipped by Dask: read them from a private temporary file
        with tempfile.TemporaryDirectory(prefix="meshmark-study-") as d:
            p = os.path.join(d, "mesh" + os.path.splitext(path)[1].lower())
            with open(p, "wb") as f:
                f.write(data)
            m = read_mesh(p)
    else:
        m = read_mesh(path)
    return compact(m) if do_compact else m


def welded_vertices(path: str) -> int:
    """Vertices the faces use once vertices at equal positions are merged (what the methods see with
    ``weld = true``): the size a spec's ``meshes.min_vertices`` compares. Unreadable files count 0."""
    from ..topology import weld_vertices
    try:
        m = weld_vertices(load_mesh(path)).mesh
    except MeshError:
        return 0
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return int(used.sum())



def mesh_digest(path: str) -> str:
    """blake2b-128 of a file's bytes (hex); of the vertex and face arrays for ``builtin:NAME``."""
    h = hashlib.blake2b(digest_size=16)
    if path.startswith("builtin:"):
        m = builtin_mesh(path.split(":", 1)[1])
        for a in (m.V, m.face_indices, m.face_offsets):
            h.update(np.ascontiguousarray(a).tobytes())
        return h.hexdigest()
    with open(path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()

