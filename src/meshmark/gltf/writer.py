"""Writing marked positions back into a copy of a glTF asset.

Only the POSITION elements that changed are rewritten, in place, as float32 in their buffer views
(same byte length, interleaved strides and sparse values honoured), and the ``min``/``max`` of the
accessors whose bounds changed are replaced in the JSON text (padded with spaces to their old length
when shorter). Every other byte, skins, joints and weights, morph targets, animations, materials,
images, extensions, extras, key order and number spelling, stays as it was; an unchanged asset is
written back byte for byte. Buffers from ``data:`` URIs are re-encoded in place; a changed external
``.bin`` is written beside the output under the output's name (the input's files are never touched),
and relative URIs of unchanged external files are rewritten when the output goes to another folder.
"""
from __future__ import annotations

import base64
import os
import urllib.parse

import numpy as np

from .._core import MeshError
from ..atomic import write_all
from . import accessors as acc
from .container import Container, _shown, glb_bytes, resolve_uri
from .jsonspans import find_spans
from .reader import GltfInfo, container_of
from .._typing import ArrayLike, PathLike


def _num(x) -> str:
    """Shortest spelling that reads back as this float32 (numpy's round-trip repr)."""
    s = str(np.float32(x))
    return s[:-2] if s.endswith(".0") and "e" not in s else s


def _bounds_text(v: np.ndarray) -> str:
    return "[" + ",".join(_num(x) for x in v) + "]"


def _old_bounds(a: dict, key: str):
    v = a.get(key)
    if isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v):
        return np.asarray(v, np.float64).astype(np.float32)
    return None


class _Plan:
    def __init__(self, c: Container):
        self.c = c
        self.buffers: dict = {}  # buffer index -> bytearray (copied on first write)
        self.edits: list = []  # (start, end, bytes) in the JSON text
        self.written: list = []  # (Span, accessor indices allowed to share it)
        self._spans = None

    @property
    def spans(self) -> dict:
        if self._spans is None:
            self._spans = find_spans(self.c.json_bytes)
        return self._spans

    def buf(self, i: int) -> bytearray:
        if i not in self.buffers:
            self.buffers[i] = bytearray(self.c.buffers[i].data)
        return self.buffers[i]

    def write_rows(self, span: acc.Span, rows: np.ndarray, values: np.ndarray, owners) -> None:
        view = np.ndarray((span.count, 3), "<f4", buffer=self.buf(span.buffer), offset=span.start,
                          strides=(span.stride, 4))
        view[rows] = values
        self.written.append((span, set(owners)))

    def replace(self, key, text: str, what: str) -> None:
        if key not in self.spans:
            raise MeshError(f"{what}: cannot locate {key} in the JSON text")
        a, b = self.spans[key]
        new = text.encode("utf-8")
        if len(new) < b - a:
            new += b" " * (b - a - len(new))
        self.edits.append((a, b, new))

    def set_bounds(self, ai: int, lo: np.ndarray, hi: np.ndarray, what: str) -> None:
        a = self.c.doc["accessors"][ai]
        for key, v in (("min", lo), ("max", hi)):
            old = _old_bounds(a, key)
            if old is not None and np.array_equal(old, v):
                continue
            if ("accessors", ai, key) in self.spans:
                self.replace(("accessors", ai, key), _bounds_text(v), what)
                continue
            start, end = self.spans[("accessors", ai)]  # insert before the closing brace
            self.edits.append((end - 1, end - 1, f',"{key}":{_bounds_text(v)}'.encode()))

    def json_text(self) -> bytes:
        if not self.edits:
            return self.c.json_bytes
        out, pos = [], 0
        text = self.c.json_bytes
        for a, b, new in sorted(self.edits, key=lambda e: (e[0], e[1])):
            if a < pos:
                raise MeshError("internal: overlapping JSON edits")
            out += [text[pos:a], new]
            pos = b
        out.append(text[pos:])
        new = b"".join(out)
        if self.c.kind == "glb" and len(new) > len(text):  # absorb growth into the chunk's space padding
            trailing = len(new) - len(new.rstrip(b" "))
            if len(new) - len(text) <= trailing:
                new = new[:len(text)]
        return new


def _mark_part(plan: _Plan, part, Vp: np.ndarray, where: str) -> None:
    c = plan.c
    lay = acc.layout(c.doc, c.buffers, part.accessor, ("VEC3",), f"{where}: POSITION")
    old = acc.raw_values(c.buffers, lay)
    if lay.dtype != "<f4":
        if np.array_equal(acc.to_float(old, lay), Vp):
            return
        raise MeshError(f"{where}: POSITION accessor {part.accessor} is quantized ({part.encoding}, "
                        "KHR_mesh_quantization): marked positions cannot be written back without rounding them "
                        "to its grid; dequantize the asset first (e.g. gltf-transform dequantize)")
    with np.errstate(over="ignore"):
        new = Vp.astype(np.float32)
    if not np.isfinite(new).all():
        raise MeshError(f"{where}: a marked position overflows float32")
    rows = np.any(new != old, axis=1)
    if not rows.any():
        return
    owners = part.aliases
    if lay.sparse is not None:
        idx = lay.sparse["indices"]
        in_sparse = np.zeros(lay.count, bool)
        in_sparse[idx] = True
        srows = rows[idx]
        if srows.any():
            plan.write_rows(lay.sparse["values"], srows, new[idx][srows], owners)
        dense = rows & ~in_sparse
        if dense.any():
            if lay.span is None:
                raise MeshError(f"{where}: POSITION accessor {part.accessor} is sparse without a bufferView: vertex "
                                f"{int(np.argmax(dense))} is not stored and cannot change")
            plan.write_rows(lay.span, dense, new[dense], owners)
    else:
        plan.write_rows(lay.span, rows, new[rows], owners)
    lo, hi = new.min(axis=0), new.max(axis=0)
    for ai in part.aliases:
        plan.set_bounds(ai, lo, hi, where)


def _elem_size(a: dict) -> int:
    ct = acc.COMPONENTS.get(a.get("componentType"), (None, 4))[1]
    return ct * {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4, "MAT2": 4, "MAT3": 12, "MAT4": 16}.get(a.get("type"), 16)


def _check_overlaps(plan: _Plan, where: str) -> None:
    """No other accessor, image or buffer view may share a rewritten byte (else the rewrite would
    change it too)."""
    doc = plan.c.doc
    views = doc.get("bufferViews") or []
    touched = {}
    for span, owners in plan.written:
        touched.setdefault(span.view, []).append((span, owners))
    ranges = {}
    for vi in touched:
        v = views[vi]
        ranges[vi] = (v.get("buffer"), v.get("byteOffset", 0), v.get("byteOffset", 0) + v.get("byteLength", 0))
    for vi, v in enumerate(views):  # another view over the same bytes
        if vi in touched or not isinstance(v, dict):
            continue
        lo = v.get("byteOffset", 0) if isinstance(v.get("byteOffset", 0), int) else 0
        hi = lo + (v.get("byteLength") if isinstance(v.get("byteLength"), int) else 0)
        for tb, tlo, thi in ranges.values():
            if v.get("buffer") == tb and lo < thi and tlo < hi:
                for span, _ in (s for lst in touched.values() for s in lst):
                    if span.buffer == tb and lo < span.end and span.start < hi:
                        raise MeshError(f"{where}: bufferView {vi} overlaps the rewritten positions; "
                                        "they cannot change without changing it")
    for ii, im in enumerate(doc.get("images") or []):
        if isinstance(im, dict) and im.get("bufferView") in touched:
            raise MeshError(f"{where}: image {ii} is stored in bufferView {im.get('bufferView')} with rewritten positions")
    for ai, a in enumerate(doc.get("accessors") or []):
        if not isinstance(a, dict):
            continue
        refs = [(a.get("bufferView"), a.get("byteOffset", 0), _elem_size(a), a.get("count", 0))]
        sp = a.get("sparse")
        if isinstance(sp, dict):
            for part, size in (("indices", 4), ("values", _elem_size(a))):
                d = sp.get(part) if isinstance(sp.get(part), dict) else {}
                refs.append((d.get("bufferView"), d.get("byteOffset", 0), size, sp.get("count", 0)))
        for vi, off, size, count in refs:
            if vi not in touched or not isinstance(off, int) or not isinstance(count, int):
                continue
            v = views[vi]
            stride = v.get("byteStride") or size
            start = v.get("byteOffset", 0) + off
            end = start + max(count - 1, 0) * stride + size
            for span, owners in touched[vi]:
                if ai in owners or not (start < span.end and span.start < end):
                    continue
                if stride == span.stride and span.stride > 0:
                    a0, b0 = span.start % stride, start % stride
                    if (b0 - a0) % stride >= span.size and (a0 - b0) % stride >= size:
                        continue  # interleaved: other bytes of the same rows
                raise MeshError(f"{where}: accessor {ai} shares bytes of bufferView {vi} with the rewritten "
                                "positions; they cannot change without changing it")


def _sidecar_names(out_path: str, indices: list) -> dict:
    stem = os.path.splitext(out_path)[0]
    if len(indices) == 1:
        return {indices[0]: stem + ".bin"}
    return {i: f"{stem}_{i}.bin" for i in indices}


def _quote(path: str) -> str:
    return urllib.parse.quote(path.replace(os.sep, "/"), safe="/")


def plan_write(info: GltfInfo, V: ArrayLike, out_path: PathLike) -> list:
    """The files that hold the asset of ``info`` with the joined vertex positions ``V`` (``(n, 3)``, as
    returned by :func:`meshmark.gltf.read` and then marked): ``[(path, bytes)]``, the asset first,
    then any external ``.bin`` written beside it. Nothing is written. Raises MeshError if the output's
    container differs from the input's, the positions do not fit the asset, the source changed since
    it was read, or a rewritten byte is shared with other data."""
    out_path = os.fspath(out_path)
    ext = os.path.splitext(out_path)[1].lower()
    if ext not in (".glb", ".gltf"):
        raise MeshError(f"{_shown(out_path)}: a glTF asset is written as .glb or .gltf")
    c = container_of(info)
    where = _shown(c.path)
    if ext[1:] != c.kind:
        raise MeshError(f"{_shown(out_path)}: the asset is a .{c.kind}; write the marked copy as a .{c.kind} too "
                        "(converting the container would rewrite the whole file)")
    V = np.asarray(V, dtype=np.float64)
    n = int(info.joined.offsets[-1])
    if V.ndim != 2 or V.shape != (n, 3):
        raise MeshError(f"the positions have shape {V.shape}, the asset's carrier has ({n}, 3)")
    if not np.isfinite(V).all():
        raise MeshError(f"vertex {int(np.argmax(~np.isfinite(V).all(axis=1)))} is not finite")
    plan = _Plan(c)
    for part, Vp in zip(info.parts, info.joined.split(V)):
        _mark_part(plan, part, Vp, f"{where}: POSITION accessor {part.accessor}")
    if plan.written:
        _check_overlaps(plan, where)
    files, sidecars = [], []
    changed = sorted(plan.buffers)
    side = _sidecar_names(out_path, [i for i in changed if c.buffers[i].kind == "file"])
    inputs = {os.path.abspath(b.path) for b in c.buffers if b.path} | {os.path.abspath(c.path)}
    out_folder = os.path.dirname(os.path.abspath(out_path))
    for i in changed:
        b = c.buffers[i]
        data = bytes(plan.buffers[i])
        if b.kind == "data":
            head = b.uri.partition(",")[0]
            if not head.endswith(";base64"):
                head += ";base64"
            plan.replace(("buffers", i, "uri"), '"' + head + "," + base64.b64encode(data).decode("ascii") + '"',
                         f"{where}: buffer {i}")
        elif b.kind == "file":
            target = side[i]
            if os.path.abspath(target) in inputs:
                raise MeshError(f"{_shown(target)} is a file of the input asset; write the copy elsewhere")
            sidecars.append((target, data))
            plan.replace(("buffers", i, "uri"), '"' + _quote(os.path.basename(target)) + '"', f"{where}: buffer {i}")
    if out_folder != c.folder:  # unchanged external files, named relative to the output
        for top, items in (("buffers", c.doc.get("buffers") or []), ("images", c.doc.get("images") or [])):
            for i, d in enumerate(items):
                uri = d.get("uri") if isinstance(d, dict) else None
                if (not isinstance(uri, str) or uri.startswith("data:") or "://" in uri or os.path.isabs(uri)
                        or (top == "buffers" and i in changed)):
                    continue
                rel = os.path.relpath(os.path.abspath(resolve_uri(c.folder, uri)), out_folder)
                plan.replace((top, i, "uri"), '"' + _quote(rel) + '"', f"{where}: {top} {i}")
    text = plan.json_text()
    if c.kind == "glb":
        bin_data = bytes(plan.buffers[0]) if 0 in plan.buffers and c.buffers[0].kind == "glb" else None
        if text is c.json_bytes and bin_data is None:
            main = c.raw
        else:
            main = glb_bytes(text, c.chunks, c.bin_chunk_index, bin_data, pad=len(text) != len(c.json_bytes))
    else:
        main = text
    files.append((out_path, main))
    return files + sidecars


def write_positions(info: GltfInfo, V: ArrayLike, out_path: PathLike, overwrite: bool = True) -> list:
    """Write the asset of ``info`` with positions ``V`` to ``out_path`` (and any external ``.bin``
    beside it), all files or none. Returns the paths written. ``overwrite=False``: MeshError naming
    the first file that exists (before anything is written).

    ``V``: (n, 3) float64 positions, one row per vertex of the joined mesh :func:`read` returned, in mesh units
    (each primitive's own space)."""
    files = plan_write(info, V, out_path)
    write_all([(p, (lambda data: lambda tmp: _write_bytes(tmp, data))(d)) for p, d in files],
              what=["glTF asset"] + ["glTF buffer"] * (len(files) - 1), overwrite=overwrite)
    return [p for p, _ in files]


def _write_bytes(path: str, data: bytes) -> None:
    with open(path, "wb") as f:
        f.write(data)
