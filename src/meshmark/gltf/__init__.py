"""glTF 2.0 (``.glb`` and ``.gltf``) in and out: an asset's triangle meshes as one carrier, and
marked positions written back into a copy of the asset with everything else unchanged.

    mesh, info = meshmark.gltf.read("hero.glb")         # all triangle primitives, joined
    res = laplacian.embed(mesh, payload="ACME", key="k")
    meshmark.gltf.write_positions(info, res.V, "marked.glb")   # only POSITION bytes and min/max change

``meshmark.read_mesh`` / ``write_mesh`` dispatch here on the extension (``write_mesh("x.glb", mesh,
source=info)`` writes back; without ``source`` a minimal glTF of the mesh). See ``docs/gltf.md``.
"""
from __future__ import annotations

from typing import Any
import importlib

EXTENSIONS = (".glb", ".gltf")


def is_gltf(path: Any) -> bool:
    """Whether ``path`` names a glTF file (by its extension)."""
    import os
    try:
        name = os.fsdecode(os.fspath(path))
    except TypeError:
        return False
    return os.path.splitext(name)[1].lower() in EXTENSIONS


# The readers and writers need pygltflib: imported on first use, so that OBJ/OFF/PLY/STL work without it.
_LAZY = {"GltfInfo": "reader", "Part": "reader", "read": "reader", "plan_write": "writer",
         "write_positions": "writer", "gltf_bytes": "minimal", "write_gltf": "minimal"}


def __getattr__(name):
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = ["GltfInfo", "Part", "read", "plan_write", "write_positions", "gltf_bytes", "write_gltf", "is_gltf",
           "EXTENSIONS"]
