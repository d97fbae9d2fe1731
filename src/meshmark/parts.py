"""Several meshes as one carrier: the parts of a character (Blender objects, glTF primitives).

A character usually comes in parts (body, head, clothes, each its own object or glTF primitive, each
skinned to the same armature). Marking each part alone spreads a short message over carriers that
are too few, and reading one part alone reads a fraction of the evidence. :func:`join` puts the parts
side by side in one :class:`~meshmark.Mesh` (vertices concatenated in part order, faces renumbered,
no vertex merged), so every method embeds and extracts over all of them as one carrier, and
:meth:`Joined.split` cuts a marked or posed vertex array back into the parts.

    joined = meshmark.parts.join([body, head, cloth])      # Mesh or (V, F) per part
    res = laplacian.embed(joined.mesh, payload="ACME", key="k")
    body_V, head_V, cloth_V = joined.split(res.V)
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ._core import MeshError
from .mesh import as_mesh, Mesh, MeshPair
from ._typing import ArrayLike
from typing import Sequence


@dataclass(frozen=True)
class Joined:
    """The parts as one mesh.

    mesh : the joined :class:`Mesh`; part ``i`` owns vertices ``offsets[i]:offsets[i+1]`` and faces
        ``face_offsets[i]:face_offsets[i+1]``.
    offsets : ``(k + 1,) int64`` vertex offsets of the k parts.
    face_offsets : ``(k + 1,) int64`` face offsets of the parts.
    """
    mesh: Mesh
    offsets: np.ndarray
    face_offsets: np.ndarray

    @property
    def n_parts(self) -> int:
        """The number of parts joined (the (k + 1,) vertex offsets minus one)."""
        return int(self.offsets.size - 1)

    def split(self, V: ArrayLike) -> list[np.ndarray]:
        """Cut an ``(n, 3)`` array over the joined vertices (marked, posed) into the parts' arrays."""
        V = np.asarray(V)
        if V.ndim < 1 or V.shape[0] != int(self.offsets[-1]):
            raise MeshError(f"the array has {V.shape[0] if V.ndim else 0} rows but the joined parts have "
                            f"{int(self.offsets[-1])} vertices")
        return [V[a:b] for a, b in zip(self.offsets[:-1], self.offsets[1:])]

    def part_of_vertex(self) -> np.ndarray:
        """``(n,) int64``: the part index of every joined vertex."""
        return np.repeat(np.arange(self.n_parts, dtype=np.int64), np.diff(self.offsets))


def join(parts: Sequence[MeshPair]) -> Joined:
    """Join meshes (each a :class:`Mesh` or a ``(V, F)`` pair) into one, in the order given.

    Vertices are concatenated without merging (seams between parts stay as they are), faces keep
    their sizes and winding and are renumbered by each part's vertex offset. Raises MeshError if there
    is no part or a part is not a valid mesh (the part's index is named).
    """
    meshes = []
    for i, p in enumerate(parts):
        try:
            meshes.append(p if isinstance(p, Mesh) else as_mesh(*p))
        except (MeshError, TypeError, ValueError) as exc:
            raise MeshError(f"part {i}: {exc}") from None
    if not meshes:
        raise MeshError("join needs at least one part")
    nv = np.array([m.n_vertices for m in meshes], dtype=np.int64)
    nf = np.array([m.n_faces for m in meshes], dtype=np.int64)
    nc = np.array([m.face_indices.size for m in meshes], dtype=np.int64)
    offsets = np.concatenate([[0], np.cumsum(nv)])
    face_offsets = np.concatenate([[0], np.cumsum(nf)])
    if offsets[-1] > np.iinfo(np.int32).max:
        raise MeshError(f"the parts hold {int(offsets[-1])} vertices together, more than 2^31 - 1")
    V = np.concatenate([m.V for m in meshes], axis=0)
    idx = np.concatenate([m.face_indices.astype(np.int64) for m in meshes]) + np.repeat(offsets[:-1], nc)
    corner_start = np.concatenate([[0], np.cumsum(nc)])
    fo = np.concatenate([m.face_offsets[:-1] + s for m, s in zip(meshes, corner_start[:-1])] + [[corner_start[-1]]])
    mesh = Mesh.from_polygons(V, idx.astype(np.int32), fo.astype(np.int64), validate=False)
    return Joined(mesh=mesh, offsets=offsets, face_offsets=face_offsets)
