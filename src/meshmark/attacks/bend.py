"""The skinning bend: a two-bone linear blend skinning pose, a stand-in for an animated character."""
from __future__ import annotations

import math

import numpy as np

from .._core import MeshError
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike

AXES = ("x", "y", "z")


def bend(V: MeshLike, F: FacesLike = None, *, degrees: float = 30.0, joint: float = 0.5, width: float = 0.1,
         along: str = "z",
         absolute: bool = False) -> Mesh:
    """Bend the mesh at a joint by two-bone linear blend skinning (deterministic, no seed).

    The bone runs along the axis ``along`` (``"z"`` by default; call it a). Vertices with
    ``a <= joint - width`` stay (bone 1), vertices with ``a >= joint + width`` turn rigidly by
    ``degrees`` (bone 2), and between the two the weight of bone 2 is the smoothstep
    ``s = t^2 (3 - 2t)``, ``t = (a - (joint - width)) / (2 width)``: ``v' = (1 - s) v + s (R (v - c) + c)``.

    The rotation R is about the next axis after ``along`` (z -> x, x -> y, y -> z; right-hand rule,
    positive degrees), through the joint centre c: ``a = joint`` and, on the third axis, the middle of
    the mesh's extent (so the joint line crosses the mesh). Units: ``degrees`` in degrees; ``joint``
    and ``width`` as fractions of the mesh's extent along the bone (defaults 0.5 and 0.1: the joint
    at the middle, a blend zone of 20 % of the length), or, with ``absolute=True``, model units (then
    c is at 0 on the third axis: the arm of the thesis' Table 7.5, bent at z = 1 with width 0.2).
    Unreferenced vertices move like the others. MeshError for a non-finite angle, a width <= 0 or an
    unknown axis. Returns a Mesh with the same faces.
    """
    m = as_mesh(V, F)
    deg = _number(degrees, "bend degrees")
    j, w = _number(joint, "bend joint"), _number(width, "bend width")
    if along not in AXES:
        raise MeshError(f"bend axis (along) must be x, y or z, got {along!r}")
    if not isinstance(absolute, (bool, np.bool_)):
        raise MeshError(f"bend absolute must be true or false, got {absolute!r}")
    a = AXES.index(along)
    r = (a + 1) % 3          # rotation axis
    o = (a + 2) % 3          # the third axis
    X = m.V
    if X.shape[0] == 0:
        raise MeshError("bend: the mesh has no vertices")
    lo, hi = float(X[:, a].min()), float(X[:, a].max())
    if not absolute:
        j, w = lo + j * (hi - lo), w * (hi - lo)
    if not w > 0:
        raise MeshError(f"bend width must be > 0, got {width!r}" + ("" if absolute else " (a fraction of the extent; "
                                                                     "the mesh is flat along the bone?)"))
    t = np.clip((X[:, a] - (j - w)) / (2 * w), 0.0, 1.0)
    s = t * t * (3 - 2 * t)
    c = np.zeros(3)
    c[a] = j
    if not absolute:
        c[o] = 0.5 * (float(X[:, o].min()) + float(X[:, o].max()))
    R = _rotation(r, math.radians(deg))
    V2 = (1 - s)[:, None] * X + s[:, None] * ((X - c) @ R.T + c)
    return Mesh.from_polygons(V2, m.face_indices, m.face_offsets, validate=False)


def _number(x, name: str) -> float:
    try:
        v = float(x)
    except (TypeError, ValueError):
        raise MeshError(f"{name} must be a number, got {x!r}") from None
    if isinstance(x, bool) or not math.isfinite(v):
        raise MeshError(f"{name} must be a finite number, got {x!r}")
    return v


def _rotation(axis: int, a: float) -> np.ndarray:
    """Rotation by ``a`` radians about coordinate axis ``axis`` (0 = x, 1 = y, 2 = z), right-hand rule."""
    c, s = math.cos(a), math.sin(a)
    i, k = (axis + 1) % 3, (axis + 2) % 3
    R = np.eye(3)
    R[i, i], R[i, k], R[k, i], R[k, k] = c, -s, s, c
    return R
