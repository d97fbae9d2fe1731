"""Attack chains: several attacks in one call, from a text such as
``"bend:30,simplify:0.5,noise:0.001,similarity,reorder,roundtrip:obj"`` (grammar in docs/attacks.md).

::

    chain  := step ("," step)*
    step   := name (":" arg)*
    arg    := value              the step's one positional parameter (POSITIONAL), at most once
            | key "=" value      any keyword parameter of the attack
    value  := a number, a word (uniform, obj, ...), true / false, or x;y;z for a vector

Step j (counted from 0) of a chain run with ``seed`` gets ``seed + j`` when it takes a seed and does
not give one (``noise:0.001:seed=7``), as the attacks of a study task do.
"""
from __future__ import annotations

import math

import numpy as np

from .._core import MeshError
from ..mesh import as_mesh, Mesh, MeshPair
from .registry import ATTACKS, parameters, takes_seed
from typing import Any, Sequence

#: the parameter a bare value sets in each step (None: the step takes no positional value)
POSITIONAL = {
    "similarity": None, "rotate": "angle", "translate": "offset", "scale": "factor", "reorder": None,
    "noise": "strength", "smooth": "iterations", "quantize": "bits", "dither": "bits", "simplify": "fraction",
    "subdivide": "levels", "remesh": "edge_length", "crop": "fraction", "bend": "degrees", "float32": None,
    "roundtrip": "format",
}

_VECTORS = {"axis", "center", "normal", "offset", "scale_range"}
_INTS = {"seed", "iterations", "bits", "levels", "decimals"}
_BOOLS = {"fix_boundary", "vertices", "faces", "absolute"}
_WORDS = {"kind", "weights", "word", "scheme", "format", "along"}


def _value(key: str, text: str):
    t = text.strip()
    if key in _WORDS:
        if not t:
            raise MeshError(f"{key} needs a value")
        return t
    if key in _BOOLS:
        if t.lower() not in ("true", "false"):
            raise MeshError(f"{key} must be true or false, got {t!r}")
        return t.lower() == "true"
    if key in _VECTORS:
        parts = [p for p in t.replace(";", " ").split() if p]
        try:
            vals = [float(p) for p in parts]
        except ValueError:
            raise MeshError(f"{key} must be numbers separated by ';' (like 1;0;0), got {t!r}") from None
        return vals
    try:
        v = float(t)
    except ValueError:
        raise MeshError(f"{key} must be a number, got {t!r}") from None
    if key in _INTS:
        if not math.isfinite(v) or v != int(v):
            raise MeshError(f"{key} must be an integer, got {t!r}")
        return int(v)
    return v


def parse_chain(text: str) -> list:
    """The steps of a chain text: a list of ``(name, params)``. MeshError naming the step (its
    position, counted from 1, and its text) for an empty step, an unknown attack or parameter, two
    positional values or a value of the wrong kind."""
    if not isinstance(text, str) or not text.strip():
        raise MeshError("an attack chain must be a non-empty text like 'bend:30,simplify:0.5,noise:0.001'")
    steps = []
    for j, raw in enumerate(text.split(",")):
        where = f"chain step {j + 1} {raw.strip()!r}"
        parts = [p.strip() for p in raw.split(":")]
        name = parts[0]
        if not name:
            raise MeshError(f"{where}: empty step (two commas, or a comma at the end?)")
        if name not in ATTACKS:
            raise MeshError(f"{where}: unknown attack {name!r} (expected one of {', '.join(sorted(ATTACKS))})")
        known = parameters(name)
        params: dict = {}
        positional_seen = False
        for arg in parts[1:]:
            if not arg:
                raise MeshError(f"{where}: empty parameter (two colons?)")
            if "=" in arg:
                key, _, val = arg.partition("=")
                key = key.strip()
                if key not in known:
                    raise MeshError(f"{where}: the {name} attack does not take {key!r} "
                                    f"(it takes {', '.join(sorted(known)) or 'no parameters'})")
            else:
                key, val = POSITIONAL[name], arg
                if key is None:
                    raise MeshError(f"{where}: {name} takes no positional value (give key=value: "
                                    f"{', '.join(sorted(known)) or 'no parameters'})")
                if positional_seen:
                    raise MeshError(f"{where}: more than one positional value (the one is {key})")
                positional_seen = True
            if key in params:
                raise MeshError(f"{where}: {key} is given twice")
            try:
                params[key] = _value(key, val)
            except MeshError as e:
                raise MeshError(f"{where}: {e}") from None
        steps.append((name, params))
    return steps


def format_chain(steps: Sequence[tuple[str, dict[str, Any]]]) -> str:
    """The chain text of ``steps`` (a list of ``(name, params)``); ``parse_chain`` reads it back."""
    out = []
    for name, params in steps:
        bits = [name]
        pos = POSITIONAL.get(name)
        for k, v in params.items():
            txt = ";".join(f"{x:g}" for x in v) if isinstance(v, (list, tuple)) else (
                str(v).lower() if isinstance(v, bool) else f"{v:g}" if isinstance(v, float) else str(v))
            bits.append(txt if k == pos else f"{k}={txt}")
        if pos in params:  # the positional value first
            bits.insert(1, bits.pop(1 + list(params).index(pos)))
        out.append(":".join(bits))
    return ",".join(out)


def steps_of(spec) -> list:
    """``spec`` as a list of ``(name, params)``: a chain text, or such a list (checked)."""
    if isinstance(spec, str):
        return parse_chain(spec)
    steps = []
    for j, st in enumerate(spec):
        try:
            name, params = st
        except (TypeError, ValueError):
            raise MeshError(f"chain step {j + 1}: expected (name, params), got {st!r}") from None
        if name not in ATTACKS:
            raise MeshError(f"chain step {j + 1}: unknown attack {name!r} (expected one of {', '.join(sorted(ATTACKS))})")
        bad = sorted(set(params) - set(parameters(name)))
        if bad:
            raise MeshError(f"chain step {j + 1} ({name}): unknown parameter {bad[0]!r}")
        steps.append((name, dict(params)))
    if not steps:
        raise MeshError("an attack chain needs at least one step")
    return steps


def step_seed(name: str, params: dict, seed: int, j: int) -> dict:
    """The keyword arguments step ``j`` runs with: ``params`` plus ``seed + j`` for a random attack."""
    if "seed" not in params and takes_seed(name):
        return {**params, "seed": int(seed) + j}
    return dict(params)


def chain(mesh: MeshPair, spec: str | Sequence[tuple[str, dict[str, Any]]], *, seed: int = 0) -> Mesh:
    """Apply the attack chain ``spec`` (a chain text or a list of ``(name, params)``) to ``mesh`` (a
    Mesh, or ``(V, F)``) in order.

    ``chain(mesh, "bend:30,simplify:0.5,noise:0.001,similarity,reorder,roundtrip:obj", seed=0)``.
    Step j of a random attack gets ``seed + j`` unless it gives its own seed: the result equals
    applying the steps one by one (``attack(m, name=..., seed=seed + j, ...)``). MeshError naming the
    step for a bad text or a value the attack refuses.
    """
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or not 0 <= int(seed) < 2 ** 63:
        raise MeshError(f"chain seed must be an integer in 0 .. 2^63 - 1, got {seed!r}")
    steps = steps_of(spec)
    m = as_mesh(*mesh) if isinstance(mesh, tuple) else as_mesh(mesh)
    for j, (name, params) in enumerate(steps):
        try:
            m = ATTACKS[name](m, **step_seed(name, params, int(seed), j))
        except MeshError as e:
            raise MeshError(f"chain step {j + 1} ({name}): {e}") from None
    return m
