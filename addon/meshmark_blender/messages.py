"""Errors in the user's language (bpy-free).

The core's MeshError texts speak of the algorithm ("Laplacian lengths span an empty range", "K",
"n_thr"); :func:`friendly` turns the ones a panel user meets into what they mean for the mesh
("mesh too small to carry a mark") and names parameters as the panel shows them (Bins, Min. pair
size). A text it does not know is kept, with the parameter names replaced.
"""
from __future__ import annotations

import re

from meshmark.watermark.payload import MAX_DATA_BITS

from . import params as _params

TOO_SMALL = "mesh too small to carry a mark"
TOO_SMALL_HIDE = "mesh too small to hide anything"
MORE_ROOM = "under Advanced > Custom, lower Min. pair size or raise Bins"


def _rename(text: str, method: str | None) -> str:
    """``K=286, n_thr=46`` -> ``Bins 286, Min. pair size 46``; ``n_thr must ...`` -> ``Min. pair size must``."""
    names = _params.labels(method)
    for name in sorted(names, key=len, reverse=True):
        label = names[name]
        text = re.sub(rf"(?<![\w/.-]){re.escape(name)}\s*=\s*(?=[-\d.])", f"{label} ", text)
        text = re.sub(rf"(?<![\w/.-]){re.escape(name)} (?=must|=)", f"{label} ", text)
    return text


def _method_of(text: str, method: str | None) -> str | None:
    m = re.search(r"the (\S+) (?:method|mark)", text)
    return m.group(1) if m and m.group(1) in _params.METHODS else method


def _room(method: str | None) -> str:
    return MORE_ROOM if method in (None, "laplacian") else "under Advanced > Custom, change Bins"


def friendly(text: str, method: str | None = None) -> str:
    """The user-facing form of an error message of the core (see the module docstring)."""
    method = _method_of(text, method)
    label = _params.method_label(method) if method else "this"
    m = re.search(r"span an empty range", text)
    if m:
        return f"{TOO_SMALL}: too few different vertices to sort (add detail, e.g. subdivide)"
    m = re.search(r"K must be at least 4 bins, got (-?\d+) \(the mesh is too small", text)
    if m:
        return f"{TOO_SMALL}: it has too few vertices (a few hundred at least; add detail, e.g. subdivide)"
    m = re.search(r"the mesh has (\d+) referenced vertices but K = (\d+) bins were asked for", text)
    if m:
        return f"{TOO_SMALL}: {m.group(1)} vertices for {m.group(2)} Bins (lower Bins under Advanced > Custom)"
    m = re.search(r"the mesh offers only (\d+) carrier bits to the \S+ method with (.*); at least (\d+) are needed",
                  text)
    if m:
        return (f"{TOO_SMALL}: it offers only {m.group(1)} of the {m.group(3)} bits a mark needs with the "
                f"{label} method ({_rename(m.group(2), method)}); {_room(method)}")
    m = re.search(r"the message needs (\d+) carrier bits .* but the mesh offers (\d+) with the \S+ method "
                  r"\((.*)\); at most (\d+) payload bits fit", text)
    if m:  # framework.embed (docs/coding.md: data + 20 check bits, at least 1.5 carriers per bit)
        cap = int(m.group(2))
        fit = min(int(m.group(4)), MAX_DATA_BITS) // 8
        room = f"at most {fit} bytes of text fit" if fit else "not even one letter fits"
        return (f"message too long for this mesh: it needs {m.group(1)} bits, the mesh can carry {cap} bits "
                f"({_rename(m.group(3), method)}); {room}. Shorten it, or {_room(method)}")
    m = re.search(r"the message is (\d+) bytes \((\d+) bits\); at most (\d+) bytes fit", text)
    if m:
        return f"message too long: {m.group(1)} bytes, at most {m.group(3)} bytes fit in a mark"
    m = re.search(r"mark does not take on this mesh: (\d+) of (\d+) carrier bits still read wrong .*\((.*)\)", text)
    if m:
        return (f"the mark does not hold on this mesh ({m.group(1)} of {m.group(2)} bits would read back wrong "
                f"with {_rename(m.group(3), method)}); nothing was changed. Try other settings under Advanced")
    m = re.search(r"message of (\d+) bytes needs \d+ bits .* \(at most (\d+) message bytes\) at tolerance", text)
    if m:  # meshmark.stego
        if int(m.group(2)) == 0:
            return (f"{TOO_SMALL_HIDE}: not even one byte fits (add detail, e.g. subdivide, or raise Shading "
                    "change under Advanced)")
        return (f"too much to hide: {m.group(1)} bytes, at most {m.group(2)} bytes fit in this mesh. Hide less, "
                "or raise Shading change under Advanced")
    if "mesh has no faces" in text or text.startswith("empty mesh"):
        return f"{TOO_SMALL_HIDE}: it has no faces"
    m = re.search(r"the mesh has (\d+) vertices?.*(?:too small|at least)", text)
    if m:
        return f"mesh too small: {m.group(1)} vertices"
    return _rename(_unscript(text), method)


def _unscript(text: str) -> str:
    """The command line's and the Python API's option syntax out of a core text (the panel has fields)."""
    text = re.sub(r"\s*\((?:give |use )?--[\w-]+[^)]*\)", "", text)
    text = re.sub(r"pass [\w_]+=True(?: \([^)]*\))?", "confirm", text)
    return re.sub(r"give --[\w-]+", "type it in the panel", text)
