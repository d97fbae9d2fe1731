"""A plain mesh as a minimal valid glTF 2.0 file (built with pygltflib): one scene, one node, one
mesh with one indexed TRIANGLES primitive, float32 POSITION with min/max, uint32 indices. A ``.glb``
holds the data in its BIN chunk, a ``.gltf`` in a ``data:`` URI (one self-contained file).
Polygons are triangulated (``Mesh.triangles``); vertex order is kept.
"""
from __future__ import annotations

import os

import numpy as np
import pygltflib

from .._core import MeshError
from ..mesh import as_mesh, FacesLike, MeshLike
from .._typing import PathLike


def gltf_bytes(path: PathLike, V: MeshLike, F: FacesLike = None) -> bytes:
    """The bytes of a minimal glTF holding the mesh (container from ``path``'s extension).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    mesh = as_mesh(V, F)
    ext = os.path.splitext(os.fspath(path))[1].lower()
    if ext not in (".glb", ".gltf"):
        raise MeshError(f"{path!r}: expected a .glb or .gltf name")
    with np.errstate(over="ignore"):
        P = np.ascontiguousarray(mesh.V, dtype=np.float32)
    if not np.isfinite(P).all():
        raise MeshError("a vertex coordinate overflows float32 (glTF stores positions as 32-bit floats)")
    T = np.ascontiguousarray(mesh.triangles, dtype=np.uint32)
    pos, idx = P.tobytes(), T.tobytes()
    pad = (-len(idx)) % 4
    blob = idx + b"\0" * pad + pos
    g = pygltflib.GLTF2(
        asset=pygltflib.Asset(version="2.0", generator="meshmark"),
        scene=0, scenes=[pygltflib.Scene(nodes=[0])], nodes=[pygltflib.Node(mesh=0)],
        meshes=[pygltflib.Mesh(primitives=[pygltflib.Primitive(attributes=pygltflib.Attributes(POSITION=1), indices=0,
                                                               mode=pygltflib.TRIANGLES)])],
        accessors=[
            pygltflib.Accessor(bufferView=0, componentType=pygltflib.UNSIGNED_INT, count=int(T.size), type=pygltflib.SCALAR),
            pygltflib.Accessor(bufferView=1, componentType=pygltflib.FLOAT, count=len(P), type=pygltflib.VEC3,
                               min=[float(x) for x in P.min(axis=0)], max=[float(x) for x in P.max(axis=0)]),
        ],
        bufferViews=[
            pygltflib.BufferView(buffer=0, byteOffset=0, byteLength=len(idx), target=pygltflib.ELEMENT_ARRAY_BUFFER),
            pygltflib.BufferView(buffer=0, byteOffset=len(idx) + pad, byteLength=len(pos), target=pygltflib.ARRAY_BUFFER),
        ],
        buffers=[pygltflib.Buffer(byteLength=len(blob))],
    )
    g.set_binary_blob(blob)
    if ext == ".glb":
        return b"".join(g.save_to_bytes())
    g.convert_buffers(pygltflib.BufferFormat.DATAURI)
    return g.gltf_to_json().encode("utf-8")


def write_gltf(path: PathLike, V: MeshLike, F: FacesLike = None) -> None:
    """Write the mesh as a minimal glTF to ``path`` (``.glb`` or ``.gltf``).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    data = gltf_bytes(path, V, F)
    try:
        with open(path, "wb") as f:
            f.write(data)
    except OSError as exc:
        raise MeshError(f"cannot write '{os.fsdecode(path)}': {exc.strerror or exc}") from None
