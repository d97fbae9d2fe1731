"""The attacks by name (the ``--type`` names of ``meshmark attack``, chain steps, study specs)."""
from __future__ import annotations

import inspect

from .._core import MeshError
from ..mesh import FacesLike, Mesh, MeshLike
from . import basic as B
from .bend import bend
from .remesh import remesh
from typing import Any

ATTACKS = {
    "similarity": B.similarity,
    "rotate": B.rotate,
    "translate": B.translate,
    "scale": B.scale,
    "reorder": B.reorder,
    "noise": B.noise,
    "smooth": B.smooth,
    "quantize": B.quantize,
    "dither": B.dither,
    "simplify": B.simplify,
    "subdivide": B.subdivide,
    "remesh": remesh,
    "crop": B.crop,
    "bend": bend,
    "float32": B.float32_cast,
    "roundtrip": B.file_roundtrip,
}

#: keyword arguments that change what an attack returns, not what it does
RETURN_FLAGS = {"return_transform", "return_permutations", "return_kept", "return_target"}


def parameters(name: str) -> dict:
    """The parameters of attack ``name``: keyword -> default (``inspect.Parameter.empty`` if required)."""
    fn = ATTACKS[name]
    return {p.name: p.default for p in inspect.signature(fn).parameters.values()
            if p.kind == p.KEYWORD_ONLY and p.name not in RETURN_FLAGS}


def takes_seed(name: str) -> bool:
    return "seed" in parameters(name)


def attack(V: MeshLike, F: FacesLike = None, *, name: str, **params: Any) -> Mesh:
    """Apply the attack ``name`` (a key of :data:`ATTACKS`) with keyword ``params``.

    MeshError for an unknown name or a parameter the attack does not take.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces.
    """
    fn = ATTACKS.get(name)
    if fn is None:
        raise MeshError(f"unknown attack {name!r} (expected one of {', '.join(sorted(ATTACKS))})")
    accepted = set(parameters(name))
    bad = sorted(set(params) - accepted)
    if bad:
        raise MeshError(f"attack {name!r} does not take {', '.join(bad)} (it takes {', '.join(sorted(accepted)) or 'no parameters'})")
    return fn(V, F, **params)
