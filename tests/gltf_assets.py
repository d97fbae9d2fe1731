"""Hand-built glTF 2.0 assets for the glTF tests and the reader fuzz campaign (written byte by byte
with struct/json/base64 here, independently of meshmark's writer).

``asset(...)`` returns ``(doc, blob)``: a JSON dict and its one binary buffer. The mesh is an
octahedron (6 vertices, 8 triangles) split into primitives in several ways, stored with the options
given; ``glb_bytes`` / ``gltf_bytes`` pack it.
"""
from __future__ import annotations

import base64
import json
import struct

import numpy as np

OCTA_V = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], np.float32) * 0.75
OCTA_F = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]], np.uint16)


class _Blob:
    def __init__(self):
        self.data = bytearray()
        self.views = []

    def add(self, payload: bytes, stride=None, target=None) -> int:
        self.data += b"\0" * ((-len(self.data)) % 4)
        v = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)}
        if stride:
            v["byteStride"] = stride
        if target:
            v["target"] = target
        self.data += payload
        self.views.append(v)
        return len(self.views) - 1


def asset(interleaved=False, shared=True, strip=False, lines=False, morph=False, sparse=False, quantized=False,
          extras=True):
    """The octahedron as a glTF document and its buffer; see the module docstring."""
    b = _Blob()
    V, N = OCTA_V, OCTA_V / np.linalg.norm(OCTA_V, axis=1, keepdims=True)
    acc = []
    if quantized:
        q = np.round(V / 0.75 * 32767).astype("<i2")
        rec = np.zeros((6, 4), "<i2")
        rec[:, :3] = q
        pv = b.add(rec.tobytes(), stride=8, target=34962)
        acc.append({"bufferView": pv, "componentType": 5122, "normalized": True, "count": 6, "type": "VEC3",
                    "min": [-1, -1, -1], "max": [1, 1, 1]})
    elif interleaved:
        rec = np.hstack([V, N]).astype("<f4")
        pv = b.add(rec.tobytes(), stride=24, target=34962)
        acc.append({"bufferView": pv, "byteOffset": 0, "componentType": 5126, "count": 6, "type": "VEC3",
                    "min": V.min(0).tolist(), "max": V.max(0).tolist()})
        acc.append({"bufferView": pv, "byteOffset": 12, "componentType": 5126, "count": 6, "type": "VEC3"})
    else:
        pv = b.add(V.astype("<f4").tobytes(), target=34962)
        acc.append({"bufferView": pv, "componentType": 5126, "count": 6, "type": "VEC3",
                    "min": V.min(0).tolist(), "max": V.max(0).tolist()})
        acc.append({"bufferView": b.add(N.astype("<f4").tobytes(), target=34962), "componentType": 5126, "count": 6,
                    "type": "VEC3"})
    if sparse:  # POSITION = zeros + 6 substituted vertices (all of them) over a dense copy
        acc[0]["sparse"] = {"count": 3, "indices": {"bufferView": b.add(np.array([1, 3, 5], "<u4").tobytes()),
                                                    "componentType": 5125},
                            "values": {"bufferView": b.add(V[[1, 3, 5]].astype("<f4").tobytes())}}
    prims = []
    halves = [OCTA_F[:4], OCTA_F[4:]] if shared else [OCTA_F]
    for h in halves:
        acc.append({"bufferView": b.add(h.astype("<u2").tobytes(), target=34963), "componentType": 5123,
                    "count": int(h.size), "type": "SCALAR"})
        p = {"attributes": {"POSITION": 0, "NORMAL": 1 if not quantized else 0}, "indices": len(acc) - 1}
        prims.append(p)
    if quantized:
        for p in prims:
            del p["attributes"]["NORMAL"]
    if morph:
        acc.append({"bufferView": b.add((np.ones((6, 3)) * 0.1).astype("<f4").tobytes()), "componentType": 5126,
                    "count": 6, "type": "VEC3", "min": [0.1] * 3, "max": [0.1] * 3})
        prims[0]["targets"] = [{"POSITION": len(acc) - 1}]
    meshes = [{"name": "octa", "primitives": prims, **({"extras": {"note": "keep me"}} if extras else {})}]
    if strip:  # a second mesh: one strip quad (4 vertices, 2 triangles)
        S = np.array([[2, 0, 0], [3, 0, 0], [2, 1, 0], [3, 1, 0]], "<f4")
        acc.append({"bufferView": b.add(S.tobytes()), "componentType": 5126, "count": 4, "type": "VEC3",
                    "min": S.min(0).tolist(), "max": S.max(0).tolist()})
        meshes.append({"name": "strip", "primitives": [{"attributes": {"POSITION": len(acc) - 1}, "mode": 5}]})
    if lines:
        meshes.append({"name": "wire", "primitives": [{"attributes": {"POSITION": 0}, "mode": 1}]})
    doc = {"asset": {"version": "2.0", "generator": "meshmark tests"},
           "extensionsUsed": ["KHR_mesh_quantization"] if quantized else [],
           "scene": 0, "scenes": [{"nodes": [0]}],
           "nodes": [{"mesh": 0, "name": "octa", "translation": [0, 1, 0]}]
           + [{"mesh": i} for i in range(1, len(meshes))],
           "meshes": meshes, "accessors": acc, "bufferViews": b.views,
           "buffers": [{"byteLength": len(b.data)}]}
    if not quantized:
        del doc["extensionsUsed"]
    doc["scenes"][0]["nodes"] += list(range(1, len(meshes)))
    if extras:
        doc["extras"] = {"studio": "meshmark tests", "ünïcode": "✓"}
    return doc, bytes(b.data)


def glb_bytes(doc: dict, blob: bytes, indent=None) -> bytes:
    text = json.dumps(doc, indent=indent, ensure_ascii=False).encode("utf-8")
    text += b" " * ((-len(text)) % 4)
    blob = blob + b"\0" * ((-len(blob)) % 4)
    doc_len = 12 + 8 + len(text) + 8 + len(blob)
    return (struct.pack("<4sII", b"glTF", 2, doc_len) + struct.pack("<II", len(text), 0x4E4F534A) + text
            + struct.pack("<II", len(blob), 0x004E4942) + blob)


def gltf_bytes(doc: dict, blob: bytes, uri: str | None = None, indent=2) -> bytes:
    """A .gltf: the buffer as a data: URI, or named ``uri`` (the caller writes the .bin)."""
    d = json.loads(json.dumps(doc))
    d["buffers"][0]["uri"] = uri or ("data:application/octet-stream;base64," + base64.b64encode(blob).decode())
    return json.dumps(d, indent=indent, ensure_ascii=False).encode("utf-8")
