"""Reading the triangle meshes of a glTF 2.0 asset as one carrier.

Every primitive of every entry of ``meshes`` whose mode is TRIANGLES, TRIANGLE_STRIP or
TRIANGLE_FAN is read (strips and fans become triangles; points and lines are skipped with a note).
Positions are those of the POSITION accessor, in the primitive's own (accessor) space: node
transforms, skins and morph weights are not applied, so a posed export (where the exporter wrote
the deformed positions) reads as posed and the rest asset as at rest. Primitives that share a
POSITION accessor, or whose POSITION accessors name the same bytes, are one vertex block (read once;
their triangles are pooled, an exact repeat of a triangle kept once). The blocks are joined with
:func:`meshmark.parts.join` in order of first appearance, and :class:`GltfInfo` records which
accessors went where, so that :func:`meshmark.gltf.write_positions` can write marked positions back.
"""
from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass, field

import numpy as np
import pygltflib

from .._core import MeshError
from ..mesh import Mesh
from ..parts import Joined, join
from . import accessors as acc
from .container import Container, _shown, load
from .._typing import PathLike

TRIANGLE_MODES = (pygltflib.TRIANGLES, pygltflib.TRIANGLE_STRIP, pygltflib.TRIANGLE_FAN)


@dataclass(frozen=True)
class Part:
    """One vertex block of the carrier: a POSITION accessor and the primitives that use it.

    accessor : index of the POSITION accessor (the first one, if several name the same bytes);
    aliases : every POSITION accessor index read as this block;
    primitives : ``(mesh, primitive)`` index pairs whose triangles are in the block;
    n_vertices, n_faces : the block's vertex count (every element of the accessor, referenced or
        not) and triangle count;
    encoding : ``"float32"``, or the integer type of quantized positions (``"int16 normalized"``...);
    interleaved, sparse : how the positions are stored.
    """
    accessor: int
    aliases: tuple
    primitives: tuple
    name: str
    n_vertices: int
    n_faces: int
    encoding: str
    interleaved: bool
    sparse: bool
    morph_targets: int

    def to_dict(self) -> dict:
        """The JSON-ready summary of one primitive (accessor, primitives, name, counts, encoding,
        morph targets); no arrays."""
        return {"accessor": self.accessor, "aliases": list(self.aliases),
                "primitives": [list(p) for p in self.primitives], "name": self.name, "n_vertices": self.n_vertices,
                "n_faces": self.n_faces, "encoding": self.encoding, "interleaved": self.interleaved,
                "sparse": self.sparse, "morph_targets": self.morph_targets}


@dataclass
class GltfInfo:
    """What :func:`read` took from the asset, enough to write marked positions back exactly.

    path, container : the file and ``"glb"`` / ``"gltf"``; sha256 : of the file's bytes as read (the
    writer refuses a source that changed since);
    parts : the :class:`Part` blocks in carrier order; joined : their :class:`~meshmark.parts.Joined`
    offsets; notes : what was skipped or converted, in words.
    """
    path: str
    container: str
    sha256: str
    parts: list
    joined: Joined
    notes: list = field(default_factory=list)
    n_file_faces: int = 0
    n_dropped_faces: int = 0
    skinned: bool = False
    n_animations: int = 0

    def to_dict(self) -> dict:
        """The JSON-ready summary of the asset (container, parts, skinned, n_animations, notes); no arrays."""
        return {"container": self.container, "n_parts": len(self.parts), "parts": [p.to_dict() for p in self.parts],
                "skinned": self.skinned, "n_animations": self.n_animations, "notes": list(self.notes)}


def _encoding(lay: acc.Layout) -> str:
    if lay.dtype == "<f4":
        return "float32"
    name = {"<i1": "int8", "<u1": "uint8", "<i2": "int16", "<u2": "uint16", "<u4": "uint32"}[lay.dtype]
    return name + (" normalized" if lay.normalized else "")


def _alias_key(lay: acc.Layout):
    """Accessors naming the same bytes the same way are one vertex block."""
    if lay.sparse is not None or lay.span is None:
        return ("accessor", lay.index)
    s = lay.span
    return ("bytes", s.buffer, s.start, s.stride, lay.count, lay.dtype, lay.normalized)


def _primitives(doc: dict, where: str):
    meshes = doc.get("meshes", [])
    if not isinstance(meshes, list):
        raise MeshError(f"{where}: 'meshes' is not an array")
    for mi, m in enumerate(meshes):
        if not isinstance(m, dict) or not isinstance(m.get("primitives"), list):
            raise MeshError(f"{where}: mesh {mi} has no 'primitives' array")
        for pi, p in enumerate(m["primitives"]):
            yield mi, pi, m.get("name"), acc._typed(pygltflib.Primitive, p, f"{where}: mesh {mi} primitive {pi}")


def read(path: PathLike, *, drop_collapsed: bool = True) -> tuple[Mesh, GltfInfo]:
    """Read a ``.glb`` / ``.gltf`` as one :class:`~meshmark.Mesh` and its :class:`GltfInfo`.

    Triangles that repeat a vertex (strip restarts, collapsed triangles) are dropped and counted
    (``drop_collapsed=False``: a MeshError). Raises MeshError naming the accessor, buffer view or
    chunk at fault for a malformed file, and for Draco/meshopt-compressed meshes ("decompress first").
    """
    c = load(path)
    where = _shown(c.path)
    doc, notes = c.doc, []
    blocks: dict = {}  # alias key -> block
    n_file_faces = n_dropped = 0
    for mi, pi, mname, p in _primitives(doc, where):
        w = f"{where}: mesh {mi} primitive {pi}"
        ext = p.extensions if isinstance(p.extensions, dict) else {}
        for name in ext:
            if name in ("KHR_draco_mesh_compression",):
                raise MeshError(f"{w} is Draco-compressed ({name}); decompress first")
        mode = p.mode if p.mode is not None else pygltflib.TRIANGLES
        if mode not in acc.MODES:
            raise MeshError(f"{w}: mode {mode!r} is not a glTF primitive mode")
        if mode not in TRIANGLE_MODES:
            notes.append(f"mesh {mi} primitive {pi}: {acc.MODES[mode]} skipped (not triangles)")
            continue
        attrs = p.attributes if isinstance(p.attributes, dict) else {}
        pos = attrs.get("POSITION")
        if pos is None:
            notes.append(f"mesh {mi} primitive {pi}: no POSITION attribute, skipped")
            continue
        lay = acc.layout(doc, c.buffers, pos, ("VEC3",), f"{w} POSITION")
        key = _alias_key(lay)
        if key not in blocks:
            V = acc.to_float(acc.raw_values(c.buffers, lay), lay)
            if not np.isfinite(V).all():
                bad = int(np.argmax(~np.isfinite(V).all(axis=1)))
                raise MeshError(f"{w} POSITION (accessor {pos}): vertex {bad} is not finite {tuple(V[bad])}")
            blocks[key] = {"layout": lay, "V": V, "tris": [], "prims": [], "aliases": [], "name": mname or "",
                           "targets": 0}
        b = blocks[key]
        if pos not in b["aliases"]:
            b["aliases"].append(pos)
        idx = (acc.indices(doc, c.buffers, p.indices, lay.count, w) if p.indices is not None
               else np.arange(lay.count, dtype=np.int64))
        T = acc.triangles(idx, mode, w)
        n_file_faces += len(T)
        bad = (T[:, 0] == T[:, 1]) | (T[:, 1] == T[:, 2]) | (T[:, 0] == T[:, 2])
        if bad.any():
            if not drop_collapsed:
                raise MeshError(f"{w}: triangle {int(np.argmax(bad))} repeats a vertex")
            n_dropped += int(bad.sum())
            T = T[~bad]
        b["tris"].append(T)
        b["prims"].append((mi, pi))
        targets = p.targets if isinstance(p.targets, list) else []
        b["targets"] = max(b["targets"], len(targets))
        if mode != pygltflib.TRIANGLES:
            notes.append(f"mesh {mi} primitive {pi}: {acc.MODES[mode]} converted to {len(T)} triangles")
    parts, meshes = [], []
    for b in blocks.values():
        T = np.concatenate(b["tris"]) if b["tris"] else np.zeros((0, 3), np.int64)
        if len(b["tris"]) > 1:  # primitives sharing the vertices: an exact repeat of a triangle once
            _, first = np.unique(np.sort(T, axis=1), axis=0, return_index=True)
            n_dropped += len(T) - len(first)
            T = T[np.sort(first)]
        if len(T) == 0:
            notes.append(f"POSITION accessor {b['layout'].index}: no triangle left, skipped")
            continue
        lay = b["layout"]
        meshes.append((b["V"], T.astype(np.int32)))
        parts.append(Part(accessor=b["aliases"][0], aliases=tuple(b["aliases"]), primitives=tuple(b["prims"]),
                          name=b["name"], n_vertices=lay.count, n_faces=len(T), encoding=_encoding(lay),
                          interleaved=lay.span is not None and lay.span.stride != lay.span.size,
                          sparse=lay.sparse is not None, morph_targets=b["targets"]))
        if b["targets"]:
            notes.append(f"POSITION accessor {lay.index}: {b['targets']} morph target(s); the base positions "
                         "are read (targets are offsets added at run time)")
    if not meshes:
        raise MeshError(f"{where}: no triangle mesh in the file" + (f" ({'; '.join(notes[:3])})" if notes else ""))
    joined = join(meshes)
    info = GltfInfo(path=os.path.abspath(c.path), container=c.kind, sha256=hashlib.sha256(c.raw).hexdigest(),
                    parts=parts, joined=joined, notes=notes, n_file_faces=n_file_faces, n_dropped_faces=n_dropped,
                    skinned=_skinned(doc), n_animations=len(doc.get("animations") or []))
    return joined.mesh, info


def _skinned(doc: dict) -> bool:
    nodes = doc.get("nodes") or []
    return isinstance(nodes, list) and any(isinstance(n, dict) and "skin" in n and "mesh" in n for n in nodes)


def container_of(info: GltfInfo) -> Container:
    """The source file of ``info`` again, checked unchanged since it was read."""
    c = load(info.path)
    if hashlib.sha256(c.raw).hexdigest() != info.sha256:
        raise MeshError(f"{_shown(info.path)} changed since it was read; read it again before writing")
    return c
