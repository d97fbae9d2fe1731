"""The watermark methods by name: :data:`METHODS`, filled by each method module with :func:`register`.

Below :mod:`.keyfile` and :mod:`.framework` (both look a method up here), it imports nothing of the
package. A method is an object with ``name``, ``resolve``, ``describe``, ``carriers``, ``embed`` and
``extract`` (see :mod:`.framework`).
"""
from __future__ import annotations

from .._core import MeshError

METHODS: dict = {}


def register(method) -> None:
    """Make ``method`` available as ``method=method.name`` (replacing one of the same name)."""
    METHODS[method.name] = method


def method_named(name: str):
    """The registered method called ``name``; MeshError listing the known ones otherwise."""
    if name not in METHODS:
        raise MeshError(f"unknown watermark method {name!r} (known: {', '.join(METHODS)})")
    return METHODS[name]
