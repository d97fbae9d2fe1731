"""Reading and writing mesh files: OBJ, OFF, PLY (ASCII/binary, float/double) and STL.

OBJ, OFF and PLY are parsed natively by meshmark's own bounded readers (every count is checked
against the bytes left in the file before anything is allocated), STL by CGAL's stream support. Vertex order is preserved; float64 values round
trip exactly through OBJ, OFF and double PLY (17 significant digits), and float32-exactly through
float PLY and STL.
"""
from __future__ import annotations

import os

import numpy as np

from . import _core
from ._core import MeshError
from .mesh import Mesh, as_mesh


def _native_path(path) -> bytes:
    """The path as bytes for the native code: a name that is not valid UTF-8 (a byte from argv kept
    as a surrogate escape) is passed through unchanged instead of failing to convert."""
    if isinstance(path, bool) or not isinstance(path, (str, bytes, os.PathLike)):
        raise MeshError(f"a mesh path must be a string or path, got {type(path).__name__}")
    return os.fsencode(path)


def read_mesh(path: str | os.PathLike, *, drop_collapsed: bool = True, return_info: bool = False):
    """Read a mesh file (format from the extension: .obj .off .ply .stl).

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
    d = _core.read_mesh(_native_path(path), drop_collapsed)
    mesh = Mesh.from_polygons(d["V"], d["indices"], d["offsets"], validate=False)  # validated natively
    if return_info:
        keys = ("format", "binary", "float32", "n_file_faces", "n_dropped_faces")
        return mesh, {k: d[k] for k in keys}
    return mesh


def write_mesh(path: str | os.PathLike, V, F=None, *, binary: bool = True, float32: bool = False,
               precision: int = 17, decimals: int | None = None) -> None:
    """Write a mesh (a :class:`Mesh`, or ``V`` and ``F``) to .obj, .off, .ply or .stl.

    Parameters
    ----------
    binary : PLY and STL only: binary (default) or ASCII.
    float32 : PLY only: store coordinates as 32-bit floats (STL always does).
    precision : ASCII formats: significant digits (default 17: exact float64 round trip).
    decimals : ASCII formats: if given, fixed notation with this many decimals (as OBJ exporters do, 6).
    """
    mesh = as_mesh(V, F)
    if precision < 1 or precision > 17:
        raise MeshError(f"precision must be 1..17 significant digits, got {precision}")
    if decimals is not None and not 0 <= decimals <= 17:
        raise MeshError(f"decimals must be 0..17, got {decimals}")
    _core.write_mesh(_native_path(path), mesh.V, mesh.face_indices, mesh.face_offsets, binary=binary,
                     float32=float32, precision=precision, decimals=-1 if decimals is None else decimals)
