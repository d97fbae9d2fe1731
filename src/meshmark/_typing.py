"""Type aliases of the public API (annotations only; numpy.typing underneath). The mesh aliases
(``MeshLike``, ``FacesLike``, ``MeshPair``) live in :mod:`meshmark.mesh`, beside :class:`~meshmark.Mesh`.

* :data:`FloatArray` — a float64 array, e.g. ``(n, 3)`` vertex positions in mesh units;
* :data:`IntArray` — an integer array, e.g. ``(m, 3)`` int32 faces (0-based vertex indices);
* :data:`BoolArray` / :data:`UInt8Array` — masks and bit vectors;
* :data:`PathLike` — a file path (``str`` or :class:`os.PathLike`);
* :data:`Progress` — ``progress(fraction in [0, 1], text)`` or None.
"""
from __future__ import annotations

import os
from typing import Any, Callable, Optional, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.integer[Any]]
BoolArray = NDArray[np.bool_]
UInt8Array = NDArray[np.uint8]
PathLike = Union[str, os.PathLike]
Progress = Optional[Callable[[float, str], None]]

__all__ = ["ArrayLike", "NDArray", "FloatArray", "IntArray", "BoolArray", "UInt8Array", "PathLike", "Progress"]
