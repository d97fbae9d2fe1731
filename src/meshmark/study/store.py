"""A content-addressed store of marked meshes, so later studies (steganalysis) reuse them.

Layout under ``root``::

    objects/ab/abcdef....npz     the mesh (V, face_indices, face_offsets), named by the blake2b-128
                                 digest of its own bytes (identical meshes are stored once)
    refs/12/1234....json         key -> {"object": digest, "meta": {...}} (keyfile, capacity, ...)

``key`` is any string the caller chooses; studies use :func:`meshmark.study.spec.embed_key` (a hash of
the mesh content, method, parameters, payload size, key template and seed). Writes are atomic (a
temporary file renamed into place), so a killed run leaves no half object; concurrent writers of the
same object write the same bytes.

    >>> s = Store("out/store")
    >>> digest = s.put("my-key", mesh, keyfile=kf.to_dict())
    >>> hit = s.get("my-key")       # StoredMesh(mesh, meta, digest) or None
"""
from __future__ import annotations

import hashlib
import io
import json
import os
import pathlib
import tempfile
from dataclasses import dataclass

import numpy as np

from .._core import MeshError
from ..mesh import Mesh
from .._typing import PathLike
from typing import Any, Iterator


@dataclass
class StoredMesh:
    mesh: Mesh
    meta: dict
    digest: str


def _atomic_write(path: pathlib.Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".tmp-")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(data)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


class Store:
    def __init__(self, root: PathLike) -> None:
        self.root = pathlib.Path(root)

    def _ref(self, key: str) -> pathlib.Path:
        if not isinstance(key, str) or not key or "/" in key or key.startswith("."):
            raise MeshError(f"store key must be a non-empty string without '/', got {key!r}")
        return self.root / "refs" / key[:2] / f"{key}.json"

    def _obj(self, digest: str) -> pathlib.Path:
        return self.root / "objects" / digest[:2] / f"{digest}.npz"

    def put(self, key: str, mesh: Mesh, **meta: Any) -> str:
        """Store ``mesh`` under ``key`` with JSON-serialisable ``meta``; returns the content digest."""
        buf = io.BytesIO()
        np.savez(buf, V=np.ascontiguousarray(mesh.V), face_indices=np.ascontiguousarray(mesh.face_indices),
                 face_offsets=np.ascontiguousarray(mesh.face_offsets))
        data = buf.getvalue()
        digest = hashlib.blake2b(data, digest_size=16).hexdigest()
        obj = self._obj(digest)
        if not obj.exists():
            _atomic_write(obj, data)
        _atomic_write(self._ref(key), json.dumps({"object": digest, "meta": meta}, sort_keys=True).encode())
        return digest

    def get(self, key: str) -> StoredMesh | None:
        """The mesh stored under ``key`` (or under a content digest), or None."""
        ref = self._ref(key)
        if ref.exists():
            d = json.loads(ref.read_text())
            digest, meta = d["object"], d["meta"]
        elif self._obj(key).exists():
            digest, meta = key, {}
        else:
            return None
        with np.load(self._obj(digest)) as z:
            m = Mesh.from_polygons(z["V"], z["face_indices"], z["face_offsets"], validate=False)
        return StoredMesh(m, meta, digest)

    def __contains__(self, key: str) -> bool:
        return self._ref(key).exists() or self._obj(key).exists()

    def keys(self) -> Iterator[str]:
        """The keys of the stored marked meshes, sorted."""
        for p in sorted((self.root / "refs").glob("*/*.json")):
            yield p.stem
