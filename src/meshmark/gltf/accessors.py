"""glTF accessors: where an accessor's elements lie in its buffer (checked against every bound before
anything is allocated), their values as numpy arrays (strided views, sparse substitutions,
normalized integers), and primitive modes turned into triangles.

The accessor's JSON is typed through pygltflib's model (:class:`pygltflib.Accessor`,
:class:`pygltflib.BufferView`), which fills the spec's defaults; every field is then checked here,
since a hostile file can put anything in any field.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import pygltflib

from .._core import MeshError

# componentType -> (numpy dtype, bytes)  (glTF 2.0 §3.6.2.2)
COMPONENTS = {pygltflib.BYTE: ("<i1", 1), pygltflib.UNSIGNED_BYTE: ("<u1", 1), pygltflib.SHORT: ("<i2", 2),
              pygltflib.UNSIGNED_SHORT: ("<u2", 2), pygltflib.UNSIGNED_INT: ("<u4", 4), pygltflib.FLOAT: ("<f4", 4)}
N_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
MODES = {pygltflib.POINTS: "points", pygltflib.LINES: "lines", pygltflib.LINE_LOOP: "line loop",
         pygltflib.LINE_STRIP: "line strip", pygltflib.TRIANGLES: "triangles",
         pygltflib.TRIANGLE_STRIP: "triangle strip", pygltflib.TRIANGLE_FAN: "triangle fan"}
MAX_STRIDE = 252  # glTF 2.0: bufferView.byteStride in [4, 252]


def _int(v, what: str, lo: int = 0, hi: int = 1 << 62) -> int:
    if isinstance(v, bool) or not isinstance(v, int) or not lo <= v <= hi:
        raise MeshError(f"{what} is {v!r}, not an integer in [{lo}, {hi}]")
    return v


def _typed(cls, d, what: str):
    if not isinstance(d, dict):
        raise MeshError(f"{what} is not a JSON object")
    try:
        with warnings.catch_warnings():  # dataclasses_json warns about missing required fields: checked below
            warnings.simplefilter("ignore")
            return cls.from_dict(d)
    except Exception as exc:  # dataclasses_json raises whatever the field's type conversion raises
        raise MeshError(f"{what}: a field has the wrong type ({type(exc).__name__}: {str(exc)[:120]})") from None


def _item(doc: dict, top: str, i, what: str):
    arr = doc.get(top)
    if not isinstance(arr, list):
        raise MeshError(f"{what}: the file has no '{top}' array")
    _int(i, what, 0, len(arr) - 1)
    return arr[i]


@dataclass(frozen=True)
class Span:
    """Where elements lie in a buffer: element ``i`` occupies bytes ``start + i * stride`` to
    ``start + i * stride + size`` of buffer ``buffer``."""
    buffer: int
    start: int
    stride: int
    size: int
    count: int
    view: int | None = None

    @property
    def end(self) -> int:
        return self.start + (self.count - 1) * self.stride + self.size if self.count else self.start


@dataclass(frozen=True)
class Layout:
    """An accessor's typed description and where its dense elements lie (``span`` is None when the
    accessor has no bufferView: its elements are zeros, then the sparse substitutions)."""
    index: int
    dtype: str
    n_components: int
    normalized: bool
    count: int
    span: Span | None
    sparse: dict | None
    component_type: int


def _view_span(doc, buffers, view_index, byte_offset: int, elem: int, align: int, count: int, what: str,
               allow_stride: bool = True) -> Span:
    v = _typed(pygltflib.BufferView, _item(doc, "bufferViews", view_index, f"{what}: bufferView"),
               f"{what}: bufferView {view_index}")
    b = _int(v.buffer, f"{what}: bufferView {view_index}.buffer", 0, len(buffers) - 1)
    voff = _int(v.byteOffset or 0, f"{what}: bufferView {view_index}.byteOffset")
    vlen = _int(v.byteLength, f"{what}: bufferView {view_index}.byteLength", 1)
    if voff + vlen > buffers[b].byte_length:
        raise MeshError(f"{what}: bufferView {view_index} (bytes {voff}..{voff + vlen}) runs past buffer {b} "
                        f"({buffers[b].byte_length} bytes)")
    stride = elem
    if v.byteStride is not None and allow_stride:
        stride = _int(v.byteStride, f"{what}: bufferView {view_index}.byteStride", 4, MAX_STRIDE)
        if stride < elem:
            raise MeshError(f"{what}: bufferView {view_index}.byteStride {stride} is smaller than an element ({elem} bytes)")
    if (voff + byte_offset) % align or stride % align:
        raise MeshError(f"{what}: data not aligned to its {align}-byte components (offset {voff + byte_offset}, "
                        f"stride {stride})")
    need = byte_offset + (count - 1) * stride + elem if count else byte_offset
    if need > vlen:
        raise MeshError(f"{what}: {count} elements of {elem} bytes (stride {stride}) from byte {byte_offset} need "
                        f"{need} bytes; bufferView {view_index} has {vlen}")
    return Span(b, voff + byte_offset, stride, elem, count, view_index)


def layout(doc: dict, buffers: list, ai, types: tuple, what: str) -> Layout:
    """The checked layout of accessor ``ai`` whose type must be one of ``types``."""
    what = f"{what} (accessor {ai})"
    a = _typed(pygltflib.Accessor, _item(doc, "accessors", ai, what), what)
    if a.componentType not in COMPONENTS:
        raise MeshError(f"{what}: componentType {a.componentType!r} is not a glTF component type")
    if a.type not in types:
        raise MeshError(f"{what}: type {a.type!r}, expected {' or '.join(types)}")
    dt, csize = COMPONENTS[a.componentType]
    nc = N_COMPONENTS[a.type]
    count = _int(a.count, f"{what}: count", 1, 1 << 31)
    off = _int(a.byteOffset or 0, f"{what}: byteOffset")
    span = None
    if a.bufferView is not None:
        span = _view_span(doc, buffers, a.bufferView, off, nc * csize, csize, count, what)
    sparse = None
    if a.sparse is not None:
        sparse = _sparse(doc, buffers, a, count, nc * csize, csize, what)
    if span is None:
        cap = 16 * sum(b.byte_length for b in buffers) + (1 << 20)
        if count * nc * csize > cap:
            raise MeshError(f"{what}: {count} elements without a bufferView: more than the file could describe")
    return Layout(ai, dt, nc, bool(a.normalized), count, span, sparse, a.componentType)


def _sparse(doc, buffers, a, count: int, elem: int, csize: int, what: str) -> dict:
    s = a.sparse
    n = _int(s.count, f"{what}: sparse.count", 1, count)
    ind, val = s.indices, s.values
    if ind is None or val is None:
        raise MeshError(f"{what}: sparse without indices or values")
    ict = ind.componentType
    if ict not in (pygltflib.UNSIGNED_BYTE, pygltflib.UNSIGNED_SHORT, pygltflib.UNSIGNED_INT):
        raise MeshError(f"{what}: sparse.indices.componentType {ict!r} is not an unsigned integer type")
    idt, isz = COMPONENTS[ict]
    ispan = _view_span(doc, buffers, ind.bufferView, _int(ind.byteOffset or 0, f"{what}: sparse.indices.byteOffset"),
                       isz, isz, n, f"{what}: sparse.indices", allow_stride=False)
    vspan = _view_span(doc, buffers, val.bufferView, _int(val.byteOffset or 0, f"{what}: sparse.values.byteOffset"),
                       elem, csize, n, f"{what}: sparse.values", allow_stride=False)
    idx = strided(buffers, ispan, idt, 1)[:, 0].astype(np.int64)
    if idx.size and (idx.max() >= count or np.any(np.diff(idx) <= 0)):
        raise MeshError(f"{what}: sparse indices must be strictly increasing and below the count {count}")
    return {"indices": idx, "values": vspan}


def strided(buffers: list, span: Span, dtype: str, n_components: int) -> np.ndarray:
    """``(count, n_components)`` copy of the elements of ``span``."""
    buf = buffers[span.buffer].data
    if span.count == 0:
        return np.zeros((0, n_components), dtype)
    a = np.ndarray((span.count, n_components), dtype=np.dtype(dtype), buffer=buf, offset=span.start,
                   strides=(span.stride, np.dtype(dtype).itemsize))
    return a.copy()


def raw_values(buffers: list, lay: Layout) -> np.ndarray:
    """``(count, n)`` the accessor's elements in their stored type (sparse substitutions applied)."""
    if lay.span is not None:
        out = strided(buffers, lay.span, lay.dtype, lay.n_components)
    else:
        out = np.zeros((lay.count, lay.n_components), lay.dtype)
    if lay.sparse is not None:
        out[lay.sparse["indices"]] = strided(buffers, lay.sparse["values"], lay.dtype, lay.n_components)
    return out


def to_float(raw: np.ndarray, lay: Layout) -> np.ndarray:
    """Stored values as float64: floats as they are, normalized integers by glTF 2.0 §3.11's rule
    (``max(c / (2^(b-1) - 1), -1)`` signed, ``c / (2^b - 1)`` unsigned), other integers as numbers."""
    x = raw.astype(np.float64)
    if lay.normalized and raw.dtype.kind in "iu":
        info = np.iinfo(raw.dtype)
        x = np.maximum(x / info.max, -1.0) if raw.dtype.kind == "i" else x / info.max
    return x


def indices(doc, buffers, ai, n_vertices: int, what: str) -> np.ndarray:
    """``(k,) int64`` vertex indices of a primitive, each checked below ``n_vertices``."""
    lay = layout(doc, buffers, ai, ("SCALAR",), f"{what} indices")
    if lay.component_type not in (pygltflib.UNSIGNED_BYTE, pygltflib.UNSIGNED_SHORT, pygltflib.UNSIGNED_INT):
        raise MeshError(f"{what} indices (accessor {ai}): componentType {lay.component_type} is not an unsigned integer type")
    idx = raw_values(buffers, lay)[:, 0].astype(np.int64)
    if idx.size and idx.max() >= n_vertices:
        k = int(np.argmax(idx >= n_vertices))
        raise MeshError(f"{what} indices (accessor {ai}): index {k} is {int(idx[k])}, the primitive has "
                        f"{n_vertices} vertices")
    return idx


def triangles(idx: np.ndarray, mode: int, what: str) -> np.ndarray:
    """``(t, 3) int64`` triangles of a TRIANGLES / TRIANGLE_STRIP / TRIANGLE_FAN index list (glTF 2.0
    §3.7.2.1: strip triangle i is (i, i+1+i%2, i+2-i%2), fan triangle i is (i+1, i+2, 0))."""
    k = idx.size
    if mode == pygltflib.TRIANGLES:
        if k % 3:
            raise MeshError(f"{what}: {k} indices for triangles, not a multiple of 3")
        return idx.reshape(-1, 3)
    if k < 3:
        return np.zeros((0, 3), np.int64)
    i = np.arange(k - 2)
    if mode == pygltflib.TRIANGLE_STRIP:
        return np.stack([idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]], axis=1)
    return np.stack([idx[i + 1], idx[i + 2], np.full(k - 2, idx[0])], axis=1)  # fan
