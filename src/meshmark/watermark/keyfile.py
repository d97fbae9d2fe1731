"""The keyfile: a versioned JSON file holding everything ``extract`` needs.

It is written by ``embed`` and kept by the owner; the marked mesh can be shared without it. Fields:

``format`` ("meshmark-keyfile"), ``version`` (3), ``method``, ``params`` (the method's parameters
as used), ``weld`` (whether vertices at equal positions were welded before the method ran; extraction
welds the same way), ``key``, ``payload`` (``kind``, ``n_bits``, ``bits`` as a 0/1 string, ``sha256`` of that
string), ``coding`` (``scheme``: ``"keyed-aes-ml-v1"``, ``"tbcc9-r14-mac20"`` or ``"tbcc7-r13-mac20"``, with
``info_bits``, ``check_bits``, ``n_coded`` (:mod:`.coding`), or the older ``"repeat"`` with ``frame_bits``, ``n_coded``), ``choice`` (how the
parameters were chosen: ``mode`` "auto" / "thesis" / "given" and the rule's details, :mod:`.auto`;
optional), ``side_info`` (method data
such as bin ranges and the carrier list), ``mesh`` (vertex/face counts of the mesh the method ran on,
i.e. after welding, the input's counts and the bounding-box diagonal of the marked mesh),
``meshmark_version``, ``created`` and (version 3) ``tag``.

Version 3 adds ``tag``: HMAC-SHA256, keyed by the key, of the canonical JSON of every other field,
so a keyfile changed after it was written is reported as changed (``verify_keyfile_tag``). The key
itself may be left out (``store_key=False``, ``meshmark embed --no-store-key``: ``"key_stored":
false``); extraction then needs the key, and the tag also tells a wrong key.
Every field is checked by one validation layer, :mod:`.keyfile_schema` (``validate_keyfile_dict``),
before anything in it is used: types, ranges, ordering (``lo < hi``), UTF-8, the method's own
parameters and side information, for every version and method; every refusal is a MeshError naming
the field. Top-level fields not in the schema are allowed (a newer meshmark may add some) but must
be plain JSON within the nesting limit.

Versions 1 (before welding existed: no ``weld`` field, read as ``weld=False``) and 2 are still read;
they have no tag and cannot be checked for changes.
"""
from __future__ import annotations

import datetime
import hashlib
import hmac
import json
import math
import os
from dataclasses import dataclass, field

from .._core import MeshError
from ..atomic import read_at_most
from . import keyfile_schema as _schema
from .keyfile_schema import (FIELDS, FORMAT, MAX_CARRIER_ID, MAX_DEPTH, MESH_CHECKS, PARAM_CHECKS,  # noqa: F401
                             READABLE_VERSIONS, REQUIRED, SIDE_CHECKS, VERSION, _float, _int, _optional, _short, _type)
from .._typing import PathLike
from typing import Any

MAX_BYTES = 256 << 20  # a keyfile holds one id per carrier: far below this even for huge meshes


class KeyRequired(MeshError):
    """The keyfile was written without its key (``store_key=False``) and no key was given."""


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
    store_key: bool = True  # False: the key is left out of the written keyfile (verification asks for it)
    tagged: bool = True     # False: read from a file without an HMAC tag (version 1-2), unchecked
    meshmark_version: str = ""
    created: str = field(default_factory=lambda: datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"))

    def to_dict(self) -> dict:
        """The fields as written (without the tag; with the key only if ``store_key``)."""
        d = {"format": FORMAT, "version": VERSION, "method": self.method, "params": self.params,
             "weld": bool(self.weld), "key": self.key, "payload": self.payload, "coding": self.coding, "side_info": self.side_info,
             "mesh": self.mesh, **_choice_field(self.choice), "meshmark_version": self.meshmark_version, "created": self.created}
        if not self.store_key:
            del d["key"]
            d["key_stored"] = False
        return d

    def to_json(self) -> str:
        """The keyfile as written: the fields and their HMAC-SHA256 tag."""
        return json.dumps(sign_keyfile(self.to_dict(), self.key), indent=1)

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str = "keyfile") -> "Keyfile":
        """A Keyfile from its parsed JSON, after :func:`validate_keyfile_dict` (the tag is checked by
        :func:`load_keyfile`, which knows the key)."""
        validate_keyfile_dict(d, source)
        stored = "key" in d
        choice = d.get("choice")
        return cls(method=d["method"], params=d["params"], key=d.get("key"), payload=d["payload"], coding=d["coding"],
                   weld=d["weld"] if d["version"] >= 2 else False, store_key=stored, choice=choice,
                   side_info=d["side_info"], mesh=d["mesh"],
                   meshmark_version=str(d.get("meshmark_version", "")), created=str(d.get("created", "")))


# --- schema (keyfile_schema.py) ---------------------------------------------------------------
def validate_keyfile_dict(d, source: str = "keyfile") -> None:
    """Check a parsed keyfile against the schema (:mod:`.keyfile_schema`) before anything in it is
    used: MeshError naming the field. Does not check the tag (see :func:`verify_keyfile_tag`)."""
    from .methods import METHODS
    _schema.validate(d, source, METHODS)


# --- integrity tag ------------------------------------------------------------------------------
def _canonical(d: dict) -> bytes:
    body = {k: v for k, v in d.items() if k != "tag"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False).encode()


def keyfile_tag(d: dict, key: str) -> str:
    """HMAC-SHA256 keyed by the key (UTF-8) of the canonical JSON of every field but ``tag``."""
    from .keys import check_key
    key = check_key(key)  # a str that encodes as UTF-8 (no lone surrogates): MeshError otherwise
    return hmac.new(key.encode("utf-8"), b"meshmark-keyfile-tag/v1\0" + _canonical(d), hashlib.sha256).hexdigest()


def sign_keyfile(d: dict, key: str) -> dict:
    """``d`` with its ``tag``."""
    return {**{k: v for k, v in d.items() if k != "tag"}, "tag": keyfile_tag(d, key)}


def verify_keyfile_tag(d: dict, key: str, source: str = "keyfile") -> bool:
    """Check the tag with ``key``; MeshError if it does not match. Returns False for an untagged
    (version 1-2) keyfile, which cannot be checked."""
    tag = d.get("tag")
    if tag is None:
        return False
    if not isinstance(tag, str) or not _schema.TAG_RE.fullmatch(tag):
        raise MeshError(f"{source}: field 'tag' must be 64 lowercase hexadecimal digits (an HMAC-SHA256), "
                        f"got {_short(tag)}")
    if not hmac.compare_digest(tag.encode("ascii"), keyfile_tag(d, key).encode("ascii")):
        if "key" in d:
            raise MeshError(f"{source} was changed after it was written: its HMAC-SHA256 tag does not match "
                            "its content (edited, corrupted, or tampered with)")
        raise MeshError(f"{source}: the key is wrong, or the keyfile was changed after it was written "
                        "(its HMAC-SHA256 tag does not match)")
    return True


def _choice_field(choice) -> dict:
    """The optional ``choice`` field as written (left out when unknown)."""
    return {} if choice is None else {"choice": choice}


def refuse_overwrite(path, overwrite: bool, how: str = "overwrite=True") -> None:
    """MeshError if ``path`` exists and ``overwrite`` is not set: a keyfile is never replaced silently
    (losing it loses the mark)."""
    path = os.fspath(path)
    if not overwrite and os.path.exists(path):
        raise MeshError(f"the keyfile '{path}' already exists; pass {how} to replace it (the marks made with "
                        "it can no longer be read without it)")



def save_keyfile(keyfile: Keyfile, path: str | os.PathLike, overwrite: bool = False) -> None:
    """Write the keyfile as JSON with its tag (atomically: a private temporary file then a rename);
    the file is readable by its owner only (0600) whatever the umask. An existing file is replaced
    only with ``overwrite=True`` (MeshError otherwise)."""
    from ..atomic import write_text
    refuse_overwrite(path, overwrite)
    write_text(path, keyfile.to_json(), private=True)


def _reject_constant(name):
    raise ValueError(f"{name} is not allowed in a keyfile")


def _finite_float(text):
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"the number {text[:40]} is out of range")
    return v


def parse_keyfile_text(raw: bytes, source: str) -> dict:
    """The JSON object of a keyfile's bytes: MeshError if it is not UTF-8 JSON, has NaN/Infinity or
    numbers out of range, or nests too deeply for the parser."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MeshError(f"{source} is not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start}); "
                        "it may be corrupt") from None
    try:
        return json.loads(text, parse_constant=_reject_constant, parse_float=_finite_float)
    except json.JSONDecodeError as exc:
        raise MeshError(f"{source} is not valid JSON (line {exc.lineno}: {exc.msg}); it may be corrupt") from None
    except RecursionError:
        raise MeshError(f"{source} is nested too deeply (corrupt or not a meshmark keyfile)") from None
    except ValueError as exc:  # NaN/Infinity, 1e999, integers beyond Python's digit limit
        raise MeshError(f"{source}: {exc}") from None


def load_keyfile(path_or_keyfile: Keyfile | PathLike, key: str | None = None) -> Keyfile:
    """Read, validate and check a keyfile (a path, or a Keyfile which is validated and returned).

    The tag is checked with the keyfile's own key, or with ``key`` when the keyfile holds none
    (written with ``store_key=False``); such a keyfile without ``key`` raises :class:`KeyRequired`.
    A Keyfile object (made in this process, or changed after loading) goes through the same schema.
    """
    if isinstance(path_or_keyfile, Keyfile):
        kf = path_or_keyfile
        if kf.key is None and key is not None:
            import dataclasses
            kf = dataclasses.replace(kf, key=key)
        d = kf.to_dict()
        if kf.key is None:
            d.pop("key", None)
            d["key_stored"] = False
        elif "key" not in d:
            d = {**d, "key": kf.key}
            d.pop("key_stored")
        validate_keyfile_dict(d, "keyfile")
        return kf
    path = os.fspath(path_or_keyfile)
    shown = os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    source = f"keyfile '{shown}'"
    raw = read_at_most(path, MAX_BYTES, source, " (not a meshmark keyfile)")
    d = parse_keyfile_text(raw, source)
    kf = Keyfile.from_dict(d, source=source)
    kf.tagged = "tag" in d
    if d["version"] >= 3 and "tag" not in d:
        raise MeshError(f"{source}: field 'tag' is missing")
    if kf.key is None:
        if key is None:
            raise KeyRequired(f"{source} was written without the key (--no-store-key): give the key (--key)")
        from .keys import check_key
        key = check_key(key)
        verify_keyfile_tag(d, key, source)
        kf.key = key
    else:
        verify_keyfile_tag(d, kf.key, source)
    return kf
