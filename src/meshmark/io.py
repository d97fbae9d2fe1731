"""Reading and writing mesh files: OBJ, OFF, PLY (ASCII/binary, float/double), STL and glTF 2.0
(.glb/.gltf, through :mod:`meshmark.gltf`).

OBJ, OFF and PLY are parsed natively by meshmark's own bounded readers (every count is checked
against the bytes left in the file before anything is allocated), STL by CGAL's stream support. Vertex order is preserved; float64 values round
trip exactly through OBJ, OFF and double PLY (17 significant digits), and float32-exactly through
float PLY and STL.
"""
from __future__ import annotations

import os
from typing import TYPE_CHECKING, Any

import numpy as np

from . import _core
from ._core import MeshError
from ._typing import ArrayLike, PathLike
from .mesh import as_mesh, FacesLike, Mesh, MeshLike

if TYPE_CHECKING:  # pygltflib is imported on first use of a glTF file
    from .gltf.reader import GltfInfo


def _native_path(path) -> bytes:
    """The path as bytes for the native code: a name that is not valid UTF-8 (a byte from argv kept
    as a surrogate escape) is passed through unchanged instead of failing to convert."""
    if isinstance(path, bool) or not isinstance(path, (str, bytes, os.PathLike)):
        raise MeshError(f"a mesh path must be a string or path, got {type(path).__name__}")
    return os.fsencode(path)


def read_mesh(path: str | os.PathLike, *, drop_collapsed: bool = True,
              return_info: bool = False) -> Mesh | tuple[Mesh, dict[str, Any]]:
    """Read a mesh file (format from the extension: .obj .off .ply .stl .glb .gltf).

    A glTF asset reads as one mesh: every triangle primitive of every mesh, positions in each
    primitive's own space, joined in file order (:func:`meshmark.gltf.read`, docs/gltf.md); its info
    also has ``gltf``, the :class:`meshmark.gltf.GltfInfo` that ``write_mesh(..., source=info)`` needs
    to write marked positions back into the asset.

    Returns a :class:`Mesh` whose ``V`` holds every vertex record in file order (unreferenced
    vertices included) and whose faces are the polygons as stored. STL triangle corners are welded
    on exactly equal coordinates, numbered in order of first appearance.
    Faces that repeat a vertex are repaired or dropped (``drop_collapsed=True``, the default):
    consecutive repeats merge, ``(a, b, b, c) -> (a, b, c)``; a face left with fewer than 3 corners
    (an STL triangle whose corners weld together) is dropped. With ``drop_collapsed=False`` they are
    a MeshError.

    With ``return_info=True`` returns ``(mesh, info)`` where info has ``format``, ``binary``,
    ``float32`` (the file stores 32-bit coordinates), ``n_file_faces`` (face records in the file)
    and ``n_dropped_faces``.

    Raises MeshError with the path and what is wrong (missing, empty, truncated, malformed, ...).
    """
    native = _native_path(path)
    from . import gltf
    if gltf.is_gltf(path):
        mesh, g = gltf.read(path, drop_collapsed=drop_collapsed)
        if return_info:
            return mesh, {"format": g.container, "binary": g.container == "glb",
                          "float32": all(p.encoding == "float32" for p in g.parts), "n_file_faces": g.n_file_faces,
                          "n_dropped_faces": g.n_dropped_faces, "gltf": g}
        return mesh
    d = _core.read_mesh(native, drop_collapsed)
    mesh = Mesh.from_polygons(d["V"], d["indices"], d["offsets"], validate=False)  # validated natively
    if return_info:
        keys = ("format", "binary", "float32", "n_file_faces", "n_dropped_faces")
        return mesh, {k: d[k] for k in keys}
    return mesh


def write_mesh(path: str | os.PathLike, V: MeshLike, F: FacesLike = None, *, binary: bool = True, float32: bool = False,
               precision: int = 17, decimals: int | None = None, source: GltfInfo | None = None) -> None:
    """Write a mesh (a :class:`Mesh`, or ``V`` and ``F``) to .obj, .off, .ply, .stl, .glb or .gltf.

    Parameters
    ----------
    binary : PLY and STL only: binary (default) or ASCII.
    float32 : PLY only: store coordinates as 32-bit floats (STL always does).
    precision : ASCII formats: significant digits (default 17: exact float64 round trip).
    decimals : ASCII formats: if given, fixed notation with this many decimals (as OBJ exporters do, 6).
    source : .glb/.gltf only: the :class:`meshmark.gltf.GltfInfo` of the asset ``V`` was read from
        (``read_mesh(..., return_info=True)[1]["gltf"]``): writes a copy of that asset in which only
        the changed positions (and their accessors' min/max) differ, plus an external ``.bin`` beside
        ``path`` if the asset keeps its buffer in one. Without it, a minimal glTF of the mesh (float32).
    """
    from . import gltf
    _native_path(path)
    if source is not None:
        if not gltf.is_gltf(path):
            raise MeshError("source= writes back into a glTF asset: the output must be .glb or .gltf")
        if not isinstance(source, gltf.GltfInfo):
            raise MeshError(f"source must be the GltfInfo of the asset read, got {type(source).__name__}")
        gltf.write_positions(source, V.V if isinstance(V, Mesh) else V, path)
        return
    mesh = as_mesh(V, F)
    if gltf.is_gltf(path):
        gltf.write_gltf(path, mesh)
        return
    if precision < 1 or precision > 17:
        raise MeshError(f"precision must be 1..17 significant digits, got {precision}")
    if decimals is not None and not 0 <= decimals <= 17:
        raise MeshError(f"decimals must be 0..17, got {decimals}")
    _core.write_mesh(_native_path(path), mesh.V, mesh.face_indices, mesh.face_offsets, binary=binary,
                     float32=float32, precision=precision, decimals=-1 if decimals is None else decimals)


def mesh_outputs(path: PathLike, V: ArrayLike, mesh: Mesh, info: dict | None = None) -> list:
    """``[(path, writer)]`` pairs for :func:`meshmark.atomic.write_all` that write the mesh ``mesh``
    with positions ``V`` to ``path``, as read with ``read_mesh(..., return_info=True)`` (``info``):

    * a glTF read and a glTF written with the same faces: the asset itself with only the changed
      positions rewritten (:func:`meshmark.gltf.plan_write`; an external ``.bin`` beside it too);
    * otherwise the mesh in the format of ``path`` (float PLY if the input stored float32).
    Each ``writer(tmp)`` writes its file's bytes to the temporary name it is given."""
    from . import gltf
    g = (info or {}).get("gltf")
    V = np.asarray(V.V if isinstance(V, Mesh) else V)
    if g is not None and gltf.is_gltf(path) and V.shape == mesh.V.shape:
        return [(p, _bytes_writer(data)) for p, data in gltf.plan_write(g, V, path)]
    float32 = bool((info or {}).get("float32")) and os.fspath(path).lower().endswith(".ply")
    return [(path, lambda p: write_mesh(p, V, mesh, float32=float32))]


def _bytes_writer(data: bytes):
    def write(p):
        with open(p, "wb") as f:
            f.write(data)
    return write
