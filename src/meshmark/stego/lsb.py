"""Adaptive high-capacity LSB steganography (thesis §4.3.2), the orchestration around the native
bit layout (``native/include/meshmark/stego_lsb.h``) and orderings (``stego_order.h``).

Embedding (eq. numbers of the thesis):

1. carrier words C = V in the chosen precision (fixed32 grid, float32 or float64 bit patterns);
2. levels i of C from the tolerance (§4.3.1, eqs. 4.3.19-4.3.25, ``meshmark.analysis``), turned into
   cell exponents t = floor(log2 L) - i (L = the largest bounding-box extent);
3. pi_1 = projection order of the unmarked quantized vertices on their first principal axis;
4. the message frame (``crypto``) plus random padding replaces bits 1 .. k-1 of every word in pi_1;
5. i' = levels of the marked mesh with its LSBs cleared, t' likewise; pi_2 = projection order of that
   mesh quantized at t'; e = t - t' (eq. 4.3.26) in pi_2 order, deflate-compressed, length-prefixed,
   goes into the LSBs (c = 1) in pi_2 order;
6. the result is extracted again in memory and compared (a new nonce is tried in the rare case that
   it does not round-trip, e.g. two marked vertices collide with different e).

Extraction follows the thesis: clear the LSBs, levels i', pi_2, read e, t = t' + e (eq. 4.3.27),
quantize at t, pi_1, read the frame, decrypt. Nothing depends on the vertex or face order.
"""
from __future__ import annotations

import hmac
import math
import os
import struct
import zlib
from dataclasses import dataclass, field

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import Mesh, as_mesh
from . import crypto
from .._typing import IntArray
from typing import Callable

PRECISIONS = ("fixed32", "float32", "float64")
_MAX_ATTEMPTS = 4


def _check_precision(precision: str) -> str:
    if precision not in PRECISIONS:
        raise MeshError(f"precision must be one of {', '.join(PRECISIONS)}, got {precision!r}")
    return precision


def _check_tolerance(tolerance) -> float:
    try:
        tol = float(tolerance)
    except (TypeError, ValueError):
        raise MeshError(f"tolerance must be a number of degrees, got {tolerance!r}") from None
    if not math.isfinite(tol) or tol <= 0:
        raise MeshError(f"tolerance must be a positive number of degrees, got {tolerance!r}")
    return tol


def _check_mesh(mesh) -> Mesh:
    m = as_mesh(mesh)
    if m.n_vertices == 0:
        raise MeshError("empty mesh: no vertices to carry a message")
    if m.n_faces == 0:
        raise MeshError("mesh has no faces: the quantization levels need triangles")
    return m


ADAPTIVE = ("triangle", "curvature", "global")


def _adaptive_mode(adaptive) -> str:
    if adaptive is True:
        return "triangle"
    if adaptive is False:
        return "global"
    if adaptive not in ADAPTIVE:
        raise MeshError(f"adaptive must be True, False or one of {', '.join(ADAPTIVE)}, got {adaptive!r}")
    return adaptive


def level_function(tolerance: float = 1.0, adaptive: bool | str = True, levels: int | Callable[[Mesh], int | IntArray] | None = None,
                   bound: str = "appr") -> Callable[[Mesh], int | IntArray]:
    """mesh -> levels i (int, or (n,) ints) of §4.3.1, from ``meshmark.analysis``:

    * ``adaptive=True`` / ``"triangle"``: eq. 4.3.25 with eps_j = tolerance for every triangle, a vertex
      taking the largest level of its triangles (how Table 4.4 and Fig. 4.8 were made);
    * ``"curvature"``: eq. 4.3.24's curvature-dependent eps_j (Fig. 4.7's alpha, mu, sigma; tolerance
      is eps_0, so curved regions get up to alpha = 45.7 deg more);
    * ``False`` / ``"global"``: one level for the mesh (eq. 4.3.21, ``bound``).

    ``levels`` overrides: an int used for every vertex, or a callable ``mesh -> int | (n,) array``.
    """
    if levels is not None:
        if callable(levels):
            return levels
        if np.ndim(levels) == 0 and float(levels) == int(levels):
            lv = int(levels)
            if not 0 <= lv <= 32:
                raise MeshError(f"levels must lie in 0..32, got {lv}")
            return lambda mesh: lv
        raise MeshError("levels must be an int or a callable mesh -> int | (n,) array "
                        "(a fixed (n,) array cannot be recomputed on the marked mesh)")
    tol = _check_tolerance(tolerance)
    mode = _adaptive_mode(adaptive)
    from .. import analysis
    if mode == "triangle":
        return lambda mesh: analysis.adaptive_levels(mesh, tolerance=tol, alpha=0.0)
    if mode == "curvature":
        return lambda mesh: analysis.adaptive_levels(mesh, tolerance=tol)
    return lambda mesh: analysis.quantization_level(mesh, tolerance=tol, bound=bound)


def _levels_array(mesh: Mesh, i) -> np.ndarray:
    """(n,) int64 levels; vertices no face uses keep every bit (level 32): they carry only the LSB
    (moving them within a coarse cell would change the bounding box, and so everybody's levels)."""
    n = mesh.n_vertices
    i = np.asarray(i)
    if i.ndim == 0:
        i = np.full(n, int(i), dtype=np.int64)
    if i.shape != (n,):
        raise MeshError(f"levels must be an int or one per vertex ({n}), got shape {i.shape}")
    i = i.astype(np.int64)
    used = _referenced(mesh)
    if not used.all():
        i = np.where(used, i, 32)
    return i


def _referenced(mesh: Mesh) -> np.ndarray:
    """Vertices some face uses (cached with the face set, which with_vertices shares)."""
    return mesh.referenced().view(bool)


def _on_faces(mesh: Mesh, V: np.ndarray) -> Mesh:
    """``mesh.with_vertices(V)`` for carrier words made here (finite, (n, 3) float64: the native
    functions return nothing else), without validating the unchanged faces again."""
    m = Mesh.from_polygons(V, mesh.face_indices, mesh.face_offsets, validate=False)
    m._topology = mesh._topology
    return m


def _thesis_bpv(mesh: Mesh, i) -> float:
    """3 mean(32 - i - c), c = 1, over the vertices faces use: the thesis' count in its 32-bit
    bounding-cube words (Table 4.4), for comparison with the capacity of the chosen precision."""
    used = _referenced(mesh)
    return float(3 * np.mean(np.maximum(0, 31 - np.asarray(i)[used])))


def _cell_exponents(mesh: Mesh, i, precision: str, fr) -> np.ndarray:
    """t = floor(log2 L) - i, clamped to the precision's range (stego_lsb.h)."""
    V = mesh.V
    L = float(_core.stego_extent(V))
    if not L > 0:
        raise MeshError("degenerate mesh: all vertices coincide")
    fl = math.frexp(L)[1] - 1  # floor(log2 L)
    i = _levels_array(mesh, i)
    lo, hi = _core.stego_t_range(precision, fr[0])
    return np.clip(fl - i.astype(np.int64), lo, hi).astype(np.int32)


@dataclass
class _Layout:
    C: np.ndarray
    fr: tuple
    t: np.ndarray
    order: np.ndarray
    first: np.ndarray
    capacity: int


def _layout(C: np.ndarray, t: np.ndarray, precision: str, fr, mesh: Mesh) -> _Layout:
    Q = _core.stego_quantize(C, t, precision, *fr)
    order, first, _, _ = _core.stego_order(Q, t, *fr, mesh.face_indices, mesh.face_offsets)
    cap = int(_core.stego_capacity(C, t, precision, *fr, order, first))
    return _Layout(C, fr, t, order, first, cap)


def _frame(V: np.ndarray, precision: str):
    """The frame (E, o) of stego_lsb.h and the carrier words of V in it."""
    E, o = _core.stego_frame(V, precision)
    fr = (int(E), o)
    return fr, _core.stego_snap(V, precision, *fr)


def _carrier(m: Mesh, precision: str, level_fn):
    """Steps 1-3 on the unmarked mesh: (frame, mesh of the carrier words C, levels i, cell exponents t,
    layout in pi_1 order)."""
    fr, C = _frame(m.V, precision)
    cm = _on_faces(m, C)
    i = _levels_array(cm, level_fn(cm))
    t = _cell_exponents(cm, i, precision, fr)
    return fr, cm, i, t, _layout(C, t, precision, fr, m)


def _marked_order(Vm: np.ndarray, mesh: Mesh, level_fn, precision: str, fr):
    """(t', pi_2 order, first) of a marked carrier (its LSBs are ignored)."""
    Z = _core.stego_clear_lsb(Vm, precision, *fr)
    zmesh = _on_faces(mesh, Z)
    i2 = _levels_array(zmesh, level_fn(zmesh))
    t2 = _cell_exponents(zmesh, i2, precision, fr)
    Q2 = _core.stego_quantize(Z, t2, precision, *fr)
    order2, first2, _, _ = _core.stego_order(Q2, t2, *fr, mesh.face_indices, mesh.face_offsets)
    return t2, order2, first2, i2


def _compress_e(raw: bytes) -> bytes:
    """Raw deflate (read by zlib.decompress(wbits=-15), whatever the compressor's settings) with the
    run-length strategy: e is runs of zeros, and Z_RLE codes them within ~10 % of level 9's size at
    30-70x its speed (level 9's long match chains on runs took 0.15 s of a 1M-vertex embed)."""
    c = zlib.compressobj(9, zlib.DEFLATED, -15, 9, zlib.Z_RLE)
    return c.compress(raw) + c.flush()


@dataclass
class EmbedResult:
    """``V``: the marked vertices (exact values of the chosen precision), plus the figures."""
    V: np.ndarray
    precision: str
    n_vertices: int
    capacity_bits: int            # message-bit slots of the carrier (frame + message + padding)
    max_message_bytes: int        # longest message that fits (capacity minus the crypto frame)
    message_bytes: int
    bits_per_vertex: float        # capacity_bits / n (Table 4.4's "capacity in bits per vertex")
    thesis_bits_per_vertex: float  # 3 mean(32 - i - 1) over used vertices: the thesis' 32-bit bounding-cube count
    e_nonzero_ratio: float        # Table 4.4's "non-zero components of e / vertices", e = i - i' (levels)
    t_nonzero_ratio: float        # the same for what is stored, t - t' (cell exponents: i and floor(log2 L))
    e_stream_bytes: int           # compressed e (with its 4-byte length) in the LSBs
    lsb_slots: int
    levels: np.ndarray = field(repr=False)  # i per vertex (original mesh)
    t: np.ndarray = field(repr=False)       # cell exponents per vertex
    attempts: int = 1


@dataclass
class ExtractResult:
    found: bool
    message: bytes | None
    reason: str = ""


def capacity(mesh: Mesh, tolerance: float = 1.0, adaptive: bool | str = True, precision: str = "fixed32",
             levels: int | Callable[[Mesh], int | IntArray] | None = None) -> dict:
    """Capacity of ``mesh`` for one precision: bits, bits per vertex, longest message in bytes.

    ``mesh``: a Mesh with ``V`` (n, 3) float64; ``tolerance`` in degrees of normal change."""
    m = _check_mesh(mesh)
    precision = _check_precision(precision)
    level_fn = level_function(tolerance, adaptive, levels)
    fr, cm, i, t, lay = _carrier(m, precision, level_fn)
    n = m.n_vertices
    return {"precision": precision, "capacity_bits": lay.capacity, "bits_per_vertex": lay.capacity / n,
            "max_message_bytes": max(0, lay.capacity // 8 - crypto.OVERHEAD),
            "thesis_bits_per_vertex": _thesis_bpv(cm, i), "n_vertices": n,
            "level_min": int(np.min(i)), "level_max": int(np.max(i))}


NO_MESSAGE = "no message for this key"  # the one answer to a wrong key, a clean mesh and a damaged one
# A file with fewer than 160 LSB slots cannot hold even the corrective vector's salt and length: no
# embedding ever wrote one, and anyone can see it from the file, so saying so leaks nothing.
TOO_SMALL = "mesh too small to carry a message"


def _read_e(Vm, mesh, level_fn, precision, fr, key):
    """Recover t (eq. 4.3.27) from a marked carrier: (t, "", (salt, dkey)) or, when the LSBs hold
    no corrective vector for this key, (t', reason, (salt, dkey)) with t' the marked mesh's own
    exponents, so that the caller goes on with the same work whatever the file holds (docs/stego.md,
    "What an observer learns"). The LSB stream is salt | mask(length | deflate(e)) (``crypto.mask``); dkey is
    the key derived with that salt, the one derivation of an extraction; the frame repeats the salt."""
    t2, order2, first2, _ = _marked_order(Vm, mesh, level_fn, precision, fr)
    slots = int(_core.stego_lsb_capacity(Vm, precision, *fr, order2, first2))
    pre = crypto.SALT + 4
    nb = min(slots // 8, pre)
    head = _core.stego_read_lsb(Vm, precision, *fr, order2, first2, 8 * nb) if nb else b""
    head = bytes(head).ljust(pre, b"\0")
    dkey = crypto.derive(key, head[:crypto.SALT])  # zero-padded for a tiny mesh: the same work
    (ln,) = struct.unpack(">I", crypto.mask(dkey, head[crypto.SALT:]))
    fits = slots >= 8 * pre and 8 * (pre + ln) <= slots
    nbytes = pre + ln if fits else max(pre, slots // 8)  # a length that does not fit: read every slot
    raw = _core.stego_read_lsb(Vm, precision, *fr, order2, first2, 8 * nbytes) if slots >= 8 * nbytes else head
    comp = crypto.mask(dkey, raw[crypto.SALT:])[4:]
    groups = np.cumsum(first2, dtype=np.int64) - 1
    ngroups = int(groups[-1]) + 1
    try:  # bounded: a stream that inflates past the group count is no corrective vector either
        d = zlib.decompressobj(wbits=-15)
        e = np.frombuffer(d.decompress(comp, ngroups + 1), dtype=np.int8)
        ok = fits and d.eof
    except zlib.error:
        e, ok = np.zeros(0, dtype=np.int8), False
    salt_key = (head[:crypto.SALT], dkey)
    if slots < 8 * pre:
        return t2, TOO_SMALL, salt_key
    if not ok or e.size != ngroups:
        return t2, "no corrective vector", salt_key
    t = np.empty_like(t2)
    t[order2] = t2[order2] + e[groups]
    lo, hi = _core.stego_t_range(precision, fr[0])
    if t.min() < lo or t.max() > hi:
        return t2, "levels out of range", salt_key
    return t, "", salt_key


def _extract_frame_bits(V, mesh, level_fn, precision, fr, key):
    """The message (header -> length -> frame), or (None, reason).

    Every mesh takes the same steps (levels, pi_2, the LSB stream, one scrypt derivation, e, layout,
    header, one AES-GCM check) and every failure before the body gives :data:`NO_MESSAGE`, so that a
    wrong key cannot tell a stego mesh from a clean one (docs/stego.md)."""
    t, reason, (salt, dkey) = _read_e(V, mesh, level_fn, precision, fr, key)
    lay = _layout(V, t, precision, fr, mesh)
    hbits = min(8 * crypto.HEADER, lay.capacity)
    head = _core.stego_read_bits(V, t, precision, *fr, lay.order, lay.first, hbits) if hbits > 0 else b""
    h = crypto.open_header_with(head, dkey)  # pads a short header: the check runs in every case
    if h is None or reason or not hmac.compare_digest(bytes(head[:crypto.SALT]), salt):
        return None, TOO_SMALL if reason == TOO_SMALL else NO_MESSAGE
    n = h[0]
    total = 8 * (crypto.HEADER + n + crypto.TAG)
    if total > lay.capacity:
        return None, NO_MESSAGE
    frame = _core.stego_read_bits(V, t, precision, *fr, lay.order, lay.first, total)
    msg = crypto.open_body(frame, n, dkey)
    if msg is None:  # only reachable with the right key (the header authenticated)
        return None, "damaged message"
    return msg, ""


def embed(mesh: Mesh, message: bytes, key: str | bytes, tolerance: float = 1.0, adaptive: bool | str = True,
          precision: str = "fixed32", levels: int | Callable[[Mesh], int | IntArray] | None = None) -> EmbedResult:
    """Hide ``message`` (bytes; str is UTF-8 encoded) in ``mesh`` under ``key`` (§4.3.2).

    ``tolerance``: mean normal degradation budget in degrees; ``adaptive``: see
    :func:`level_function` (default: per-triangle levels, Table 4.4);
    ``precision``: the storage the marked vertices must survive (fixed32, float32, float64);
    ``levels``: override the levels (an int, or a callable mesh -> int | (n,) array).
    Returns an :class:`EmbedResult`; its ``V`` must be stored exactly (see ``docs/stego.md``).
    MeshError when the message is longer than the capacity (both numbers in the message).
    """
    m = _check_mesh(mesh)
    precision = _check_precision(precision)
    if isinstance(message, str):
        message = message.encode("utf-8")
    if not isinstance(message, (bytes, bytearray)):
        raise MeshError("message must be bytes or str")
    kb = crypto.key_bytes(key)
    level_fn = level_function(tolerance, adaptive, levels)
    n = m.n_vertices
    fr, cm, i, t, lay = _carrier(m, precision, level_fn)
    need = 8 * (len(message) + crypto.OVERHEAD)
    if need > lay.capacity:
        raise MeshError(f"message of {len(message)} bytes needs {need} bits with its {crypto.OVERHEAD}-byte "
                        f"encryption frame, but the carrier holds {lay.capacity} bits "
                        f"(at most {max(0, lay.capacity // 8 - crypto.OVERHEAD)} message bytes) at tolerance "
                        f"{tolerance} deg, precision {precision}")
    salt = os.urandom(crypto.SALT)
    dkey = crypto.derive(kb, salt)
    nbytes = (lay.capacity + 7) // 8
    for attempt in range(1, _MAX_ATTEMPTS + 1):
        frame = crypto.seal(bytes(message), dkey, salt)
        stream = frame + os.urandom(nbytes - len(frame))
        V1 = _core.stego_write_bits(lay.C, t, precision, *fr, lay.order, lay.first, stream, lay.capacity)
        t2, order2, first2, i2 = _marked_order(V1, m, level_fn, precision, fr)
        e_sorted = (t - t2)[order2].astype(np.int64)
        groups = np.cumsum(first2, dtype=np.int64) - 1
        lead = e_sorted[first2.astype(bool)]
        if not np.array_equal(lead[groups], e_sorted) or np.abs(lead).max(initial=0) > 127:
            continue  # two marked vertices collided with different e: new nonce, new bits
        comp = _compress_e(lead.astype(np.int8).tobytes())
        lsb = salt + crypto.mask(dkey, struct.pack(">I", len(comp)) + comp)  # crypto.py: random without the key
        slots = int(_core.stego_lsb_capacity(V1, precision, *fr, order2, first2))
        if 8 * len(lsb) > slots:
            raise MeshError(f"the compressed corrective vector ({8 * len(lsb)} bits with its salt) does not "
                            f"fit the {slots} LSB slots")
        # every LSB slot is written (random after the stream): no boundary between stream and cover bits
        fill = lsb + os.urandom(slots // 8 - len(lsb) + 1)
        V2 = _core.stego_write_lsb(V1, precision, *fr, order2, first2, fill, slots)
        # Verify what the extractor relies on: the same frame, e read back from the LSBs in pi_2 order
        # (pi_2 and t' do not depend on the LSBs, and pi_1 is a function of t and the quantized
        # vertices, which the message bits do not touch), and the frame bits read back in pi_1 order.
        E2, o2 = _core.stego_frame(V2, precision)
        if int(E2) != fr[0] or not np.array_equal(o2, fr[1]):
            continue
        back = _core.stego_read_lsb(V2, precision, *fr, order2, first2, 8 * len(lsb))
        if back != lsb:
            continue
        got = _core.stego_read_bits(V2, t, precision, *fr, lay.order, lay.first, 8 * len(frame))
        if got != frame:
            continue
        return EmbedResult(V=V2, precision=precision, n_vertices=n, capacity_bits=lay.capacity,
                           max_message_bytes=max(0, lay.capacity // 8 - crypto.OVERHEAD),
                           message_bytes=len(message), bits_per_vertex=lay.capacity / n,
                           thesis_bits_per_vertex=_thesis_bpv(cm, i),
                           e_nonzero_ratio=float(np.count_nonzero(i != i2)) / n,
                           t_nonzero_ratio=float(np.count_nonzero(t != t2)) / n,
                           e_stream_bytes=len(lsb), lsb_slots=slots, levels=np.asarray(i), t=t,
                           attempts=attempt)
    raise MeshError(f"embedding did not round-trip in {_MAX_ATTEMPTS} attempts (marked vertices collide); "
                    "try another tolerance or precision")


def extract(mesh: Mesh, key: str | bytes, tolerance: float = 1.0, adaptive: bool | str = True,
            precision: str = "fixed32",
            levels: int | Callable[[Mesh], int | IntArray] | None = None) -> ExtractResult:
    """The message hidden by :func:`embed` with the same key, tolerance, adaptive flag and precision,
    or ``found=False`` with reason :data:`NO_MESSAGE` (wrong key, damaged or clean mesh: never
    garbage, and the same answer for all three; "damaged message" only once the key's header
    authenticated).

    ``mesh``: a Mesh with ``V`` (n, 3) float64; ``tolerance`` in degrees of normal change."""
    m = _check_mesh(mesh)
    precision = _check_precision(precision)
    kb = crypto.key_bytes(key)
    level_fn = level_function(tolerance, adaptive, levels)
    # Vertices that are not carrier words of this precision are snapped to them and go through the
    # same steps: refusing them early would answer a clean mesh differently from a stego one.
    fr, V = _frame(m.V, precision)
    msg, reason = _extract_frame_bits(V, m, level_fn, precision, fr, kb)
    return ExtractResult(msg is not None, msg, reason)
