"""The keyfile: a versioned JSON file holding everything ``extract`` needs.

It is written by ``embed`` and kept by the owner; the marked mesh can be shared without it. Fields:

``format`` ("meshmark-keyfile"), ``version`` (2), ``method``, ``params`` (the method's parameters
as used), ``weld`` (whether vertices at equal positions were welded before the method ran; extraction
welds the same way), ``key``, ``payload`` (``kind``, ``n_bits``, ``bits`` as a 0/1 string, ``sha256`` of that
string), ``coding`` (``scheme``: ``"tbcc7-r13-mac20"`` with ``info_bits``, ``check_bits``, ``n_coded``
(:mod:`.coding`), or the older ``"repeat"`` with ``frame_bits``, ``n_coded``), ``choice`` (how the
parameters were chosen: ``mode`` "auto" / "thesis" / "given" and the rule's details, :mod:`.auto`;
optional), ``side_info`` (method data
such as bin ranges and the carrier list), ``mesh`` (vertex/face counts of the mesh the method ran on,
i.e. after welding, the input's counts and the bounding-box diagonal of the marked mesh),
``meshmark_version`` and ``created``.

Version 1 (before welding existed) is still read: it has no ``weld`` field and means ``weld=False``.
"""
from __future__ import annotations

import datetime
import hashlib
import json
import os
from dataclasses import dataclass, field

from .._core import MeshError

FORMAT = "meshmark-keyfile"
VERSION = 2
READABLE_VERSIONS = (1, 2)  # version 1: no "weld" field, read as weld=False


@dataclass
class Keyfile:
    method: str
    params: dict
    key: str
    payload: dict
    coding: dict
    side_info: dict
    mesh: dict
    weld: bool = False
    choice: dict = None
    meshmark_version: str = ""
    created: str = field(default_factory=lambda: datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"))

    def to_dict(self) -> dict:
        return {"format": FORMAT, "version": VERSION, "method": self.method, "params": self.params,
                "weld": bool(self.weld), "key": self.key, "payload": self.payload, "coding": self.coding, "side_info": self.side_info,
                "mesh": self.mesh, **_choice_field(self.choice), "meshmark_version": self.meshmark_version,
                "created": self.created}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1)

    @classmethod
    def from_dict(cls, d, source: str = "keyfile") -> "Keyfile":
        def bad(msg):
            raise MeshError(f"{source}: {msg}")
        if not isinstance(d, dict):
            bad("not a JSON object")
        if d.get("format") != FORMAT:
            bad(f"not a meshmark keyfile (format is {d.get('format')!r}, expected {FORMAT!r})")
        version = d.get("version")
        if version not in READABLE_VERSIONS or isinstance(version, bool):
            bad(f"keyfile version {version!r} is not supported (this meshmark reads versions "
                f"{', '.join(map(str, READABLE_VERSIONS))})")
        weld = False
        if version >= 2:
            weld = d.get("weld")
            if not isinstance(weld, bool):
                bad("field 'weld' is missing or not true/false")
        from .framework import METHODS
        if d.get("method") not in METHODS:
            bad(f"unknown method {d.get('method')!r} (known: {', '.join(METHODS)})")
        for k, t in [("params", dict), ("key", str), ("payload", dict), ("coding", dict), ("side_info", dict), ("mesh", dict)]:
            if not isinstance(d.get(k), t):
                bad(f"field {k!r} is missing or not a {t.__name__}")
        p = d["payload"]
        bits = p.get("bits")
        if p.get("kind") not in ("text", "bits") or not isinstance(bits, str) or set(bits) - {"0", "1"} or not bits:
            bad("payload must have kind 'text' or 'bits' and a non-empty 0/1 bit string")
        if p.get("n_bits") != len(bits):
            bad(f"payload n_bits ({p.get('n_bits')}) does not match its bit string ({len(bits)} bits)")
        if p.get("sha256") != hashlib.sha256(bits.encode()).hexdigest():
            bad("payload digest does not match its bits (the keyfile was edited or corrupted)")
        c = d["coding"]
        _check_coding(c, len(bits), bad)
        choice = _read_choice(d, bad)
        return cls(method=d["method"], params=d["params"], key=d["key"], payload=p, coding=c, weld=weld, choice=choice,
                   side_info=d["side_info"], mesh=d["mesh"], meshmark_version=str(d.get("meshmark_version", "")),
                   created=str(d.get("created", "")))


def _check_coding(c: dict, n_bits: int, bad) -> None:
    """The ``coding`` field: the convolutional scheme (:mod:`.coding`) or the older repetition code."""
    from . import coding
    if not isinstance(c.get("n_coded"), int) or isinstance(c.get("n_coded"), bool):
        bad("coding must have an integer n_coded")
    if c.get("scheme") == coding.SCHEME:
        if c.get("info_bits") != coding.info_bits(n_bits) or c.get("check_bits") != coding.CHECK_BITS:
            bad(f"coding sizes are inconsistent with the payload (info_bits must be {coding.info_bits(n_bits)}, "
                f"check_bits {coding.CHECK_BITS})")
        if c["n_coded"] < coding.min_carriers(n_bits):
            bad(f"coding: {c['n_coded']} coded bits cannot carry {n_bits} payload bits")
    elif c.get("scheme") == "repeat":
        if not isinstance(c.get("frame_bits"), int):
            bad("coding scheme 'repeat' needs an integer frame_bits")
        if c["frame_bits"] != n_bits + 16 or c["n_coded"] < c["frame_bits"]:
            bad("coding sizes are inconsistent with the payload")
    else:
        bad(f"coding scheme must be {coding.SCHEME!r} or 'repeat', got {c.get('scheme')!r}")


def _choice_field(choice) -> dict:
    """The optional ``choice`` field as written (left out when unknown)."""
    return {} if choice is None else {"choice": choice}


def _read_choice(d: dict, bad):
    choice = d.get("choice")
    if choice is not None and (not isinstance(choice, dict) or choice.get("mode") not in ("auto", "thesis", "given")):
        bad("field 'choice' must be an object with mode 'auto', 'thesis' or 'given'")
    return choice


def refuse_overwrite(path, overwrite: bool, how: str = "overwrite=True") -> None:
    """MeshError if ``path`` exists and ``overwrite`` is not set: a keyfile is never replaced silently
    (losing it loses the mark)."""
    path = os.fspath(path)
    if not overwrite and os.path.exists(path):
        raise MeshError(f"the keyfile '{path}' already exists; pass {how} to replace it (the marks made with "
                        "it can no longer be read without it)")


def save_keyfile(keyfile: Keyfile, path: str | os.PathLike, overwrite: bool = False) -> None:
    """Write the keyfile as JSON (atomically: a temporary file then a rename). An existing file is
    replaced only with ``overwrite=True`` (MeshError otherwise)."""
    path = os.fspath(path)
    refuse_overwrite(path, overwrite)
    tmp = path + ".tmp"
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(keyfile.to_json())
        os.replace(tmp, path)
    except OSError as exc:
        raise MeshError(f"cannot write keyfile '{path}': {exc.strerror or exc}") from None


def load_keyfile(path_or_keyfile) -> Keyfile:
    """Read and validate a keyfile (a path, or a Keyfile which is returned as is)."""
    if isinstance(path_or_keyfile, Keyfile):
        return path_or_keyfile
    path = os.fspath(path_or_keyfile)
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except OSError as exc:
        raise MeshError(f"cannot read keyfile '{path}': {exc.strerror or exc}") from None
    try:
        d = json.loads(text)
    except json.JSONDecodeError as exc:
        raise MeshError(f"keyfile '{path}' is not valid JSON (line {exc.lineno}: {exc.msg}); it may be corrupt") from None
    return Keyfile.from_dict(d, source=f"keyfile '{path}'")
