"""glTF cases for the reader fuzz engine (tests/fuzz_readers.py): seed files and mutations.

Seeds: the shared Fox.glb and hand-built octahedra (tests/gltf_assets.py) as .glb and .gltf with
interleaved, sparse, quantized, strip and morph-target storage. Mutations: half of them are the
engine's byte-level ones (truncation, flipped bytes, hostile words: they hit the GLB header and chunk
lengths), half act on the JSON and repack the file with consistent lengths, so that they reach the
accessor and buffer checks behind the container: a number set to a hostile value (counts, offsets,
strides, indices of accessors/views/buffers, component types), a field deleted or given the wrong
type, a node made its own child, the JSON nested deeply or cut.
"""
from __future__ import annotations

import json
import os
import struct

import numpy as np

from gltf_assets import asset, glb_bytes, gltf_bytes

HOSTILE_NUMBERS = [-1, 0, 1, 3, 4, 5, 7, 12, 13, 252, 253, 255, 256, 65535, 2**31 - 1, 2**31, 2**32 - 1, 2**32,
                   2**53, 10**30, 5120, 5125, 5126, 1.5, -0.0, 1e308]
WRONG_TYPES = ["x", None, [], {}, True, [1, 2], {"a": 1}]


def bases(shared: str) -> list[dict]:
    out = []
    with open(os.path.join(shared, "rigged", "Fox.glb"), "rb") as f:
        out.append({"name": "rigged/Fox.glb", "ext": "glb", "data": f.read()})
    for kw in ({}, {"interleaved": True, "strip": True}, {"sparse": True, "morph": True}, {"quantized": True},
               {"shared": False, "lines": True}):
        doc, blob = asset(**kw)
        name = "octahedron " + (",".join(kw) or "plain")
        out.append({"name": name + " glb", "ext": "glb", "data": glb_bytes(doc, blob)})
        out.append({"name": name + " gltf", "ext": "gltf", "data": gltf_bytes(doc, blob)})
    return out


def _split(data: bytes, ext: str):
    """(doc, the GLB's chunks after the JSON) or None if the seed is not parseable."""
    try:
        if ext == "gltf":
            return json.loads(data), None
        n = struct.unpack_from("<I", data, 12)[0]
        return json.loads(data[20:20 + n]), data[20 + n:]
    except Exception:
        return None


def _pack(doc, rest, ext: str, deep: int = 0) -> bytes:
    text = json.dumps(doc).encode()
    if deep:  # a key whose value nests `deep` arrays
        text = b'{"deep":' + b"[" * deep + b"]" * deep + b"," + text[1:]
    if ext == "gltf":
        return text
    text += b" " * ((-len(text)) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def _paths(node, prefix=()):
    """Every (path, value) in the JSON, skipping long number arrays (animation data, min/max)."""
    yield prefix, node
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, prefix + (k,))
    elif isinstance(node, list) and len(node) <= 64 and not all(isinstance(x, (int, float)) for x in node):
        for i, v in enumerate(node):
            yield from _paths(v, prefix + (i,))


def _set(doc, path, value):
    d = doc
    for k in path[:-1]:
        d = d[k]
    if value is _DELETE:
        del d[path[-1]]
    else:
        d[path[-1]] = value


_DELETE = object()


def mutate(data: bytes, ext: str, rng: np.random.Generator, byte_mutate) -> tuple[bytes, str]:
    """One seeded glTF case: byte-level (``byte_mutate``) or JSON-level; returns bytes and what was done."""
    parsed = _split(data, ext)
    if parsed is None or rng.random() < 0.5:
        return byte_mutate(data, rng)
    doc, rest = parsed
    done = []
    for _ in range(int(rng.choice([1, 2], p=[0.7, 0.3]))):
        op = int(rng.integers(0, 6))
        items = [(p, v) for p, v in _paths(doc) if p and (p[0] not in ("animations",) or len(p) < 5)]
        nums = [(p, v) for p, v in items if isinstance(v, (int, float)) and not isinstance(v, bool)]
        if op <= 2 and nums:  # a number (weighted towards the geometry's)
            geo = [x for x in nums if x[0][0] in ("accessors", "bufferViews", "buffers", "meshes")] or nums
            p, v = geo[int(rng.integers(0, len(geo)))]
            new = HOSTILE_NUMBERS[int(rng.integers(0, len(HOSTILE_NUMBERS)))]
            _set(doc, p, new)
            done.append(f"{'/'.join(map(str, p))}: {v!r} -> {new!r}")
        elif op == 3 and items:  # wrong type or deleted
            p, _ = items[int(rng.integers(0, len(items)))]
            new = _DELETE if rng.random() < 0.4 else WRONG_TYPES[int(rng.integers(0, len(WRONG_TYPES)))]
            _set(doc, p, new)
            done.append(f"{'/'.join(map(str, p))}: {'deleted' if new is _DELETE else repr(new)}")
        elif op == 4 and isinstance(doc.get("nodes"), list) and doc["nodes"]:  # a cycle in the node graph
            i = int(rng.integers(0, len(doc["nodes"])))
            if isinstance(doc["nodes"][i], dict):
                doc["nodes"][i]["children"] = [i, 0]
            done.append(f"node {i} its own child")
        else:  # deep nesting or cut JSON
            if rng.random() < 0.5:
                return _pack(doc, rest, ext, deep=int(rng.choice([100, 5000, 200000]))), "; ".join(done + ["deep nesting"])
            else:
                text = _pack(doc, rest, ext)
                cut = int(rng.integers(20, max(21, len(text) // 2)))
                return text[:cut] if ext == "gltf" else _recut(text, cut), "; ".join(done + [f"JSON cut at {cut}"])
    try:
        return _pack(doc, rest, ext), "; ".join(done) or "unchanged"
    except (ValueError, RecursionError):
        return data, "unchanged"


def _recut(glb: bytes, cut: int) -> bytes:
    """A GLB whose JSON chunk is cut to ``cut`` bytes (lengths kept consistent)."""
    n = struct.unpack_from("<I", glb, 12)[0]
    text, rest = glb[20:20 + min(cut, n)], glb[20 + n:]
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + rest
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body
