"""Chao, Lin, Yu and Lee, "A high capacity 3D steganography algorithm", IEEE TVCG 15(2), 2009, as
thesis §8.2 uses it (n_layers = 10, n_intervals = 10000): the baseline of §4.3.2.

PCA frame (``meshmark.pca`` and its sign rule); per axis the extreme vertices V_a, V_b (kept fixed)
bound the segment that is split into ``n_intervals`` intervals of alternating state; each layer
carries one bit per axis per vertex (3 n_layers bits per carrier vertex), a vertex in an interval of
the wrong state is mirrored into the neighbouring interval (see ``native/include/meshmark/chao_stego.h``
and the interpretation notes in ``docs/stego.md``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import as_mesh, Mesh
from .._typing import ArrayLike


@dataclass
class ChaoResult:
    V: np.ndarray
    frame: dict          # centroid, axes, pa, pb, ia, ib: the extraction key of the non-blind mode
    n_bits: int
    capacity_bits: int
    bits_per_vertex: float
    n_layers: int
    n_intervals: int


def _vertices(mesh):
    if isinstance(mesh, np.ndarray):
        V = np.ascontiguousarray(mesh, dtype=np.float64)
        if V.ndim != 2 or V.shape[1] != 3:
            raise MeshError(f"V must be (n, 3), got {V.shape}")
        return V
    return as_mesh(mesh).V


def _bits_of(message) -> np.ndarray:
    if isinstance(message, str):
        message = message.encode("utf-8")
    return np.unpackbits(np.frombuffer(bytes(message), dtype=np.uint8))


def capacity(mesh: Mesh, n_layers: int = 10, n_intervals: int = 10000) -> int:
    """Bits the Chao et al. method can hide in ``mesh`` (a Mesh, ``V`` (n, 3) float64): 3 bits (one per coordinate) per
    carrier vertex (all but the frame vertices) and layer."""
    V = _vertices(mesh)
    f = _core.chao_frame(V)
    return int(len(_core.chao_carriers(V.shape[0], f)) * 3 * n_layers)


def embed(mesh: Mesh, bits: ArrayLike | None = None, *, message: bytes | None = None, n_layers: int = 10,
          n_intervals: int = 10000,
          fill: bool = False, seed: int | None = None) -> ChaoResult:
    """Embed ``bits`` (0/1 array) or ``message`` (bytes/str, 8 bits per byte, MSB first).

    ``fill=True`` pads with random bits (``seed``) to the full capacity (steganalysis at full load).
    """
    V = _vertices(mesh)
    if not 1 <= int(n_layers) <= 30:
        raise MeshError(f"n_layers must be 1..30, got {n_layers}")
    if int(n_intervals) < 2:
        raise MeshError(f"n_intervals must be >= 2, got {n_intervals}")
    if (bits is None) == (message is None):
        raise MeshError("give exactly one of bits or message")
    b = _bits_of(message) if message is not None else np.asarray(bits)
    if b.ndim != 1 or (b.size and not np.isin(b, (0, 1)).all()):
        raise MeshError("bits must be a 1-D array of 0 and 1")
    f = _core.chao_frame(V)
    cap = int(len(_core.chao_carriers(V.shape[0], f)) * 3 * n_layers)
    if b.size > cap:
        raise MeshError(f"message of {b.size} bits exceeds the Chao capacity of {cap} bits "
                        f"({n_layers} layers x 3 axes x {cap // (3 * n_layers)} carrier vertices)")
    if fill and b.size < cap:
        rng = np.random.default_rng(seed)
        b = np.concatenate([b, rng.integers(0, 2, cap - b.size)])
    Vm = _core.chao_embed(V, f, b.astype(np.uint8), int(n_layers), int(n_intervals))
    return ChaoResult(V=Vm, frame=f, n_bits=int(b.size), capacity_bits=cap, bits_per_vertex=cap / V.shape[0],
                      n_layers=int(n_layers), n_intervals=int(n_intervals))


def extract(mesh: Mesh, n_bits: int, *, frame: dict | None = None, n_layers: int = 10,
            n_intervals: int = 10000) -> np.ndarray:
    """The first ``n_bits`` bits (uint8 0/1). ``frame=None`` is the blind mode of the paper (PCA and
    V_a, V_b recomputed from the marked mesh); with the embedder's ``frame`` the bits are exact.

    ``mesh``: a Mesh with ``V`` (n, 3) float64; returns (n_bits,) uint8."""
    V = _vertices(mesh)
    f = _core.chao_frame(V) if frame is None else frame
    return _core.chao_extract(V, f, int(n_bits), int(n_layers), int(n_intervals))
