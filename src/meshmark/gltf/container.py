"""The glTF 2.0 container: a ``.glb`` (header, JSON chunk, BIN chunk, further chunks) or a ``.gltf``
(JSON text) and the buffers it names (the GLB's BIN chunk, ``data:`` URIs, external files).

Everything is bounded before it is read: the GLB header and chunk lengths against the file's size,
a buffer's ``byteLength`` against the bytes that hold it, an external buffer's size against its
declared length, so a hostile file costs at most its own size (plus its external buffers) in memory.
The JSON text is kept as bytes: the writer edits it in place (:mod:`.jsonspans`), so every byte that
does not change stays as it was.
"""
from __future__ import annotations

import base64
import binascii
import json
import os
import struct
import urllib.parse
from dataclasses import dataclass, field

from .._core import MeshError

GLB_MAGIC = b"glTF"
CHUNK_JSON = 0x4E4F534A
CHUNK_BIN = 0x004E4942
MAX_FILE_BYTES = 1 << 34  # 16 GiB: larger files are refused before anything is read
MAX_JSON_DEPTH = 64  # glTF nests a few levels; deeper JSON is refused before json.loads recurses

# Extensions that store positions elsewhere (compressed): refused with "decompress first".
COMPRESSION_EXTENSIONS = {
    "KHR_draco_mesh_compression": "Draco",
    "EXT_meshopt_compression": "meshopt",
    "KHR_meshopt_compression": "meshopt",
}


@dataclass
class Buffer:
    """One entry of ``buffers``: its bytes and where they are stored.

    kind : ``"glb"`` (the GLB's BIN chunk), ``"data"`` (a ``data:`` URI in the JSON) or ``"file"``
        (an external file, ``path``); ``uri`` is the URI as written in the JSON.
    """
    index: int
    kind: str
    data: bytes
    byte_length: int
    uri: str | None = None
    path: str | None = None


@dataclass
class Container:
    """A parsed glTF file: the JSON (bytes and dict), its buffers and, for GLB, the chunk layout.

    chunks : GLB only, ``[(type, bytes)]`` of every chunk in file order (JSON first).
    """
    path: str
    kind: str  # "glb" or "gltf"
    raw: bytes
    json_bytes: bytes
    doc: dict
    buffers: list[Buffer] = field(default_factory=list)
    chunks: list = field(default_factory=list)
    bin_chunk_index: int | None = None

    @property
    def folder(self) -> str:
        return os.path.dirname(os.path.abspath(self.path))


def _shown(path) -> str:
    return os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def _read_file(path) -> bytes:
    try:
        size = os.path.getsize(path)
        if size > MAX_FILE_BYTES:
            raise MeshError(f"{_shown(path)}: {size} bytes, more than the {MAX_FILE_BYTES}-byte limit")
        with open(path, "rb") as f:
            return f.read()
    except OSError as exc:
        raise MeshError(f"cannot read '{_shown(path)}': {exc.strerror or exc}") from None


def _json_depth_ok(text: bytes) -> bool:
    """Whether brackets nest at most MAX_JSON_DEPTH deep (strings skipped), so json.loads cannot
    exhaust the stack on a hostile file."""
    from .jsonspans import max_depth
    return max_depth(text) <= MAX_JSON_DEPTH


def parse_json(text: bytes, where: str) -> dict:
    """The glTF JSON as a dict; MeshError naming ``where`` on anything that is not a JSON object."""
    body = text.rstrip(b" \t\r\n\x00")
    if body.startswith(b"\xef\xbb\xbf"):
        body = body[3:]
    if not body:
        raise MeshError(f"{where}: the JSON is empty")
    if not _json_depth_ok(body):
        raise MeshError(f"{where}: the JSON nests deeper than {MAX_JSON_DEPTH} levels")
    try:
        doc = json.loads(body.decode("utf-8"))
    except UnicodeDecodeError as exc:
        raise MeshError(f"{where}: the JSON is not UTF-8 (byte {exc.start})") from None
    except json.JSONDecodeError as exc:
        raise MeshError(f"{where}: bad JSON at line {exc.lineno} column {exc.colno}: {exc.msg}") from None
    except RecursionError:
        raise MeshError(f"{where}: the JSON nests too deep") from None
    if not isinstance(doc, dict):
        raise MeshError(f"{where}: the JSON is a {type(doc).__name__}, not an object")
    asset = doc.get("asset")
    version = asset.get("version") if isinstance(asset, dict) else None
    if not isinstance(version, str):
        raise MeshError(f"{where}: no asset.version: not a glTF 2.0 file")
    if not version.startswith("2."):
        raise MeshError(f"{where}: glTF version {version!r}; only glTF 2.0 is supported")
    return doc


def _parse_glb(path: str, raw: bytes) -> Container:
    where = _shown(path)
    if len(raw) < 12:
        raise MeshError(f"{where}: {len(raw)} bytes, too short for a GLB header (12 bytes)")
    magic, version, length = struct.unpack_from("<4sII", raw, 0)
    if magic != GLB_MAGIC:
        raise MeshError(f"{where}: not a GLB file (magic {magic!r}, expected b'glTF')")
    if version != 2:
        raise MeshError(f"{where}: GLB version {version}; only glTF 2.0 is supported")
    if length != len(raw):
        raise MeshError(f"{where}: the GLB header gives {length} bytes but the file has {len(raw)} (truncated or padded)")
    chunks, off = [], 12
    while off < length:
        if length - off < 8:
            raise MeshError(f"{where}: {length - off} stray bytes at byte {off}, too few for a chunk header")
        clen, ctype = struct.unpack_from("<II", raw, off)
        if clen > length - off - 8:
            raise MeshError(f"{where}: chunk {len(chunks)} at byte {off} declares {clen} bytes, "
                            f"only {length - off - 8} remain")
        chunks.append((ctype, raw[off + 8:off + 8 + clen]))
        off += 8 + clen
    if not chunks or chunks[0][0] != CHUNK_JSON:
        raise MeshError(f"{where}: the first GLB chunk is not JSON")
    doc = parse_json(chunks[0][1], where)
    bin_index = 1 if len(chunks) > 1 and chunks[1][0] == CHUNK_BIN else None
    c = Container(path=path, kind="glb", raw=raw, json_bytes=chunks[0][1], doc=doc, chunks=chunks,
                  bin_chunk_index=bin_index)
    c.buffers = _buffers(c, chunks[bin_index][1] if bin_index is not None else None)
    return c


def _decode_data_uri(uri: str, where: str) -> bytes:
    head, sep, payload = uri.partition(",")
    if not sep:
        raise MeshError(f"{where}: a data: URI without a ',' separator")
    if not head.endswith(";base64"):
        return urllib.parse.unquote_to_bytes(payload)
    try:
        return base64.b64decode(payload, validate=True)
    except (binascii.Error, ValueError):
        raise MeshError(f"{where}: the data: URI is not valid base64") from None


def resolve_uri(folder: str, uri: str) -> str:
    """The file a relative URI names, under ``folder`` (percent-escapes decoded)."""
    rel = urllib.parse.unquote(uri)
    return rel if os.path.isabs(rel) else os.path.join(folder, rel)


def _buffers(c: Container, bin_chunk: bytes | None) -> list[Buffer]:
    where = _shown(c.path)
    entries = c.doc.get("buffers", [])
    if not isinstance(entries, list):
        raise MeshError(f"{where}: 'buffers' is not an array")
    out = []
    for i, b in enumerate(entries):
        w = f"{where}: buffer {i}"
        if not isinstance(b, dict):
            raise MeshError(f"{w} is not an object")
        n = b.get("byteLength")
        if isinstance(n, bool) or not isinstance(n, int) or n < 0:
            raise MeshError(f"{w}: byteLength {n!r} is not a non-negative integer")
        uri = b.get("uri")
        if uri is None:
            if c.kind != "glb" or i != 0 or bin_chunk is None:
                raise MeshError(f"{w} has no uri and is not the GLB's BIN chunk")
            if n > len(bin_chunk):
                raise MeshError(f"{w}: byteLength {n} exceeds the BIN chunk's {len(bin_chunk)} bytes")
            out.append(Buffer(i, "glb", bin_chunk, n))
            continue
        if not isinstance(uri, str):
            raise MeshError(f"{w}: uri is not a string")
        if uri.startswith("data:"):
            if len(uri) > 2 * len(c.json_bytes) + 16:
                raise MeshError(f"{w}: data: URI longer than the JSON")
            data = _decode_data_uri(uri, w)
            kind, path = "data", None
        else:
            if "://" in uri:
                raise MeshError(f"{w}: remote URI {uri!r} (only data: URIs and local files are read)")
            path = resolve_uri(c.folder, uri)
            try:
                size = os.path.getsize(path)
            except OSError as exc:
                raise MeshError(f"{w}: cannot read '{_shown(path)}': {exc.strerror or exc}") from None
            if size < n:
                raise MeshError(f"{w}: '{_shown(path)}' has {size} bytes, byteLength says {n}")
            data, kind = _read_file(path), "file"
        if len(data) < n:
            raise MeshError(f"{w}: holds {len(data)} bytes, byteLength says {n}")
        out.append(Buffer(i, kind, data, n, uri=uri, path=path))
    return out


def load(path) -> Container:
    """Read a ``.glb`` or ``.gltf`` (by its first bytes: a GLB starts with ``glTF``)."""
    raw = _read_file(path)
    path = os.fsdecode(path) if isinstance(path, bytes) else os.fspath(path)
    if not raw:
        raise MeshError(f"{_shown(path)}: the file is empty")
    if raw[:4] == GLB_MAGIC:
        c = _parse_glb(path, raw)
    else:
        doc = parse_json(raw, _shown(path))
        c = Container(path=path, kind="gltf", raw=raw, json_bytes=raw, doc=doc)
        c.buffers = _buffers(c, None)
    _refuse_compression(c)
    return c


def _refuse_compression(c: Container) -> None:
    used = c.doc.get("extensionsUsed", [])
    req = c.doc.get("extensionsRequired", [])
    names = [x for x in (used if isinstance(used, list) else []) + (req if isinstance(req, list) else [])
             if isinstance(x, str)]
    for name in names:
        if name in COMPRESSION_EXTENSIONS:
            raise MeshError(f"{_shown(c.path)}: the meshes are {COMPRESSION_EXTENSIONS[name]}-compressed ({name}); "
                            "decompress first (e.g. gltf-transform copy, or re-export without compression)")


def glb_bytes(json_bytes: bytes, chunks: list, bin_chunk_index: int | None, bin_data: bytes | None,
              pad: bool = True) -> bytes:
    """A GLB from a JSON text (padded with spaces to 4 bytes when ``pad``) and the other chunks as
    they were (the BIN chunk replaced by ``bin_data`` of the same length)."""
    pad = (-len(json_bytes)) % 4 if pad else 0
    parts = [(CHUNK_JSON, json_bytes + b" " * pad)]
    for i, (ctype, data) in enumerate(chunks[1:], start=1):
        parts.append((ctype, bin_data if i == bin_chunk_index and bin_data is not None else data))
    total = 12 + sum(8 + len(d) for _, d in parts)
    out = [struct.pack("<4sII", GLB_MAGIC, 2, total)]
    for ctype, data in parts:
        out.append(struct.pack("<II", len(data), ctype))
        out.append(data)
    return b"".join(out)
