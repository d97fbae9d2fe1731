"""The mesh model: vertices plus polygon faces, validated natively.

A :class:`Mesh` stores

* ``V`` — ``(n, 3) float64`` vertex positions, in file order (unreferenced vertices kept);
* ``face_indices`` — ``(c,) int32`` the corners of all faces, face after face, in winding order;
* ``face_offsets`` — ``(m + 1,) int64``: face ``f`` is ``face_indices[face_offsets[f]:face_offsets[f+1]]``.

This is the layout of Blender's loops/polygons and of PLY/OBJ face lists, so quads and n-gons stay
as they are. Algorithms on the edge graph use the polygons as stored; algorithms that need triangles
call :func:`meshmark.triangulate` (deterministic, see ``docs/mesh_model.md``).
"""
from __future__ import annotations

from typing import Any, Callable, Sequence, Union

import numpy as np

from . import _core
from ._typing import ArrayLike, FloatArray, IntArray, UInt8Array
from ._core import MeshError

_INT32_MAX = np.iinfo(np.int32).max


def _as_vertices(V, name: str = "V") -> np.ndarray:
    """Return V as a C-contiguous (n, 3) float64 array, or raise MeshError naming what is wrong."""
    if isinstance(V, Mesh):
        return V.V
    try:
        A = np.asarray(V)
    except Exception as exc:  # ragged lists and the like
        raise MeshError(f"{name} must be an (n, 3) array of coordinates: {exc}") from None
    if A.dtype == object or A.dtype.kind not in "fiu":
        raise MeshError(f"{name} must hold real numbers, got dtype {A.dtype}")
    if A.ndim != 2 or A.shape[1] != 3:
        raise MeshError(f"{name} must have shape (n, 3), got {A.shape}")
    return np.ascontiguousarray(A, dtype=np.float64)


def _as_polygons(F, name: str = "F") -> tuple[np.ndarray, np.ndarray]:
    """Convert faces to (indices int32, offsets int64).

    F may be an (m, k) integer array (k >= 3) or a sequence of index sequences of mixed lengths.
    """
    if isinstance(F, (list, tuple)):
        if len(F) == 0:
            return np.zeros(0, np.int32), np.zeros(1, np.int64)
        try:
            A = np.asarray(F)
        except ValueError:  # ragged: polygons of mixed sizes
            A = None
        if A is None or A.dtype == object:
            try:
                parts = [np.asarray(f).reshape(-1) for f in F]
                flat = np.concatenate(parts)
            except Exception as exc:
                raise MeshError(f"{name} must hold integer vertex indices: {exc}") from None
            if flat.dtype.kind not in "iu":
                raise MeshError(f"{name} must hold integer vertex indices, got dtype {flat.dtype}")
            offsets = np.zeros(len(parts) + 1, dtype=np.int64)
            np.cumsum([p.size for p in parts], out=offsets[1:])
            return _checked_indices(flat, name), offsets
        F = A
    if not isinstance(F, np.ndarray):
        raise MeshError(f"{name} must be an (m, k) integer array or a list of index lists, got {type(F).__name__}")
    if F.dtype.kind not in "iu":
        raise MeshError(f"{name} must hold integer vertex indices, got dtype {F.dtype}")
    if F.ndim != 2:
        raise MeshError(f"{name} must have shape (m, k) with k >= 3, got {F.shape}")
    m, k = F.shape
    if m == 0:
        return np.zeros(0, np.int32), np.zeros(1, np.int64)
    if k < 3:
        raise MeshError(f"{name} must have shape (m, k) with k >= 3, got {F.shape}: a face needs at least 3 vertices")
    offsets = np.arange(0, (m + 1) * k, k, dtype=np.int64)
    return _checked_indices(F.reshape(-1), name, k), offsets


def _checked_indices(flat: np.ndarray, name: str, k: int | None = None) -> np.ndarray:
    if flat.size and flat.dtype.itemsize >= 4 and flat.dtype != np.int32:
        bad = (flat > _INT32_MAX) | (flat < -_INT32_MAX - 1) if flat.dtype.kind == "i" else flat > _INT32_MAX
        if bad.any():
            c = int(np.argmax(bad))
            where = f"face {c // k}" if k else f"corner {c}"
            raise MeshError(f"{name}: {where} refers to vertex {int(flat[c])}, outside the 32-bit index range")
    return np.ascontiguousarray(flat, dtype=np.int32)


class Mesh:
    """A polygon mesh: ``V`` (n, 3) float64 plus faces of any sizes. Validated on construction.

    Parameters
    ----------
    V : array_like, shape (n, 3)
        Vertex positions (any real dtype; stored as float64).
    F : array_like, shape (m, k), or sequence of sequences
        Faces as vertex indices (0-based), k >= 3; mixed sizes allowed as a list of lists.
    validate : bool
        Check for NaN/Inf, out-of-range indices, faces that repeat a vertex, empty meshes
        (default True). Raises :class:`MeshError` naming the first bad vertex or face.
    """

    __slots__ = ("V", "face_indices", "face_offsets", "_topology")

    def __init__(self, V: ArrayLike, F: ArrayLike, *, validate: bool = True) -> None:
        """Validated mesh from ``V`` (n, 3) float64 positions (mesh units) and ``F`` (m, k) integer faces or a list of
        polygons."""
        self.V = _as_vertices(V)
        self.face_indices, self.face_offsets = _as_polygons(F)
        self._topology = {}
        if validate:
            _core.validate(self.V, self.face_indices, self.face_offsets)

    @classmethod
    def from_polygons(cls, V: ArrayLike, indices: ArrayLike, offsets: ArrayLike, *, validate: bool = True) -> "Mesh":
        """Build from the flat corner layout, e.g. Blender's loops: ``V`` (n, 3) float64 positions in mesh
        units, ``indices`` (c,) integer corners face after face, ``offsets`` (m + 1,) integer starts."""
        m = cls.__new__(cls)
        m.V = _as_vertices(V)
        idx = np.asarray(indices)
        off = np.asarray(offsets)
        if idx.dtype.kind not in "iu" or off.dtype.kind not in "iu":
            raise MeshError("indices and offsets must be integer arrays")
        if idx.ndim != 1 or off.ndim != 1:
            raise MeshError(f"indices and offsets must be 1-D, got shapes {idx.shape} and {off.shape}")
        m.face_indices = _checked_indices(idx, "indices")
        m.face_offsets = np.ascontiguousarray(off, dtype=np.int64)
        m._topology = {}
        if validate:
            _core.validate(m.V, m.face_indices, m.face_offsets)
        return m

    # --- sizes -------------------------------------------------------------------------------
    @property
    def n_vertices(self) -> int:
        """n, the number of rows of the (n, 3) ``V`` (unreferenced vertices included)."""
        return int(self.V.shape[0])

    @property
    def n_faces(self) -> int:
        """m, the number of faces (polygons; the (m + 1,) ``face_offsets`` minus one)."""
        return int(self.face_offsets.shape[0] - 1)

    @property
    def face_sizes(self) -> IntArray:
        """(m,) number of corners of each face."""
        return np.diff(self.face_offsets)

    @property
    def is_triangle_mesh(self) -> bool:
        """Whether every face has 3 corners (then ``F`` is (m, 3) int32)."""
        return bool(self.n_faces and (self.face_sizes == 3).all())

    @property
    def F(self) -> IntArray:
        """(m, k) int32 faces when every face has k corners; MeshError for mixed polygon sizes."""
        sizes = self.face_sizes
        if sizes.size == 0:
            return np.zeros((0, 3), np.int32)
        k = int(sizes[0])
        if (sizes != k).any():
            raise MeshError(f"mesh mixes polygons of {int(sizes.min())} to {int(sizes.max())} corners; "
                            "use mesh.triangles or face_indices/face_offsets")
        return self.face_indices.reshape(-1, k)

    @property
    def triangles(self) -> IntArray:
        """(t, 3) int32 triangles (polygons triangulated deterministically, triangles as they are)."""
        if self.is_triangle_mesh:
            return self.face_indices.reshape(-1, 3)
        return _core.triangulate(self.V, self.face_indices, self.face_offsets)[0]

    # --- topology (cached: faces are treated as immutable once in a Mesh) ---------------------
    def edges(self) -> IntArray:
        """(e, 2) int32 unique edges (i < j) of the polygon edge graph, computed once per face set
        and shared by the meshes made with :meth:`with_vertices`."""
        if "edges" not in self._topology:
            self._topology["edges"] = _core.unique_edges(self.n_vertices, self.face_indices, self.face_offsets)[0]
        return self._topology["edges"]

    def referenced(self) -> UInt8Array:
        """(n,) uint8: 1 for the vertices used by a face (cached like :meth:`edges`)."""
        if "referenced" not in self._topology:
            self._topology["referenced"] = _core.referenced_mask(self.n_vertices, self.face_indices)
        return self._topology["referenced"]

    def cached(self, key: Any, compute: Callable[[], Any]) -> Any:
        """``compute()`` for these positions and faces, remembered for the two most recent vertex
        arrays on this face set (matched by identity and checksum, so an array edited in place is
        recomputed): lets embed, its verification and extract share per-vertex work."""
        cache = self._topology.setdefault("derived", [])
        check = float(self.V.sum())
        for V, k, c, value in cache:
            if V is self.V and k == key and (c == check or (c != c and check != check)):
                return value
        value = compute()
        cache.append((self.V, key, check, value))
        del cache[:-2]
        return value

    def copy(self) -> "Mesh":
        """A deep copy: (n, 3) float64 ``V`` and the (c,) / (m + 1,) face arrays copied."""
        return Mesh.from_polygons(self.V.copy(), self.face_indices.copy(), self.face_offsets.copy(), validate=False)

    def with_vertices(self, V: ArrayLike) -> "Mesh":
        """Same faces, new (n, 3) positions (validated)."""
        V = _as_vertices(V)
        if V.shape[0] != self.n_vertices:
            raise MeshError(f"expected {self.n_vertices} vertices, got {V.shape[0]}")
        m = Mesh.from_polygons(V, self.face_indices, self.face_offsets)
        m._topology = self._topology
        return m

    def __repr__(self) -> str:
        sizes = np.unique(self.face_sizes)
        kinds = "triangles" if sizes.tolist() == [3] else f"polygons of {sizes.min()}..{sizes.max()} corners"
        return f"Mesh({self.n_vertices} vertices, {self.n_faces} faces: {kinds})"


#: ``V`` of the functions taking ``(V, F=None)``: a :class:`Mesh` (then ``F`` is None) or (n, 3) positions.
MeshLike = Union[Mesh, ArrayLike]
#: ``F``: (m, k) integer faces, a list of polygons, a :class:`Mesh` whose faces to use, or None (``V`` a Mesh).
FacesLike = Union[Mesh, ArrayLike, Sequence[Sequence[int]], None]
#: a :class:`Mesh` or a ``(V (n, 3), F (m, k))`` tuple (metrics, analysis, chains).
MeshPair = Union[Mesh, tuple[ArrayLike, ArrayLike]]


def as_mesh(V: MeshLike, F: FacesLike = None) -> Mesh:
    """Return a :class:`Mesh` from a Mesh (``F`` must be None), from ``(V, F)`` arrays (``V`` (n, 3)
    float64 positions in mesh units, ``F`` (m, k) integer faces or a list of polygons), or from
    new (n, 3) positions ``V`` on the faces of a Mesh ``F``."""
    if isinstance(V, Mesh):
        if F is not None:
            raise MeshError("pass either a Mesh or (V, F), not both")
        return V
    if F is None:
        raise MeshError("faces F are required when V is an array")
    if isinstance(F, Mesh):  # new positions on an existing mesh's faces
        return F.with_vertices(V)
    return Mesh(V, F)


def vertices_and_mask(V: MeshLike, F: FacesLike = None) -> tuple[FloatArray, UInt8Array]:
    """``(V (n, 3) float64, mask (n,) uint8)``: the vertices that take part in a vertex statistic,
    the referenced ones of a mesh (a :class:`Mesh`, or ``(V, F)``), all of a point set (``F`` None)."""
    if isinstance(V, Mesh) or F is not None:
        mesh = as_mesh(V, F)
        return mesh.V, mesh.referenced()
    V = _as_vertices(V)
    return V, np.ones(len(V), np.uint8)
