"""The keyfile: a versioned JSON file holding everything ``extract`` needs.

It is written by ``embed`` and kept by the owner; the marked mesh can be shared without it. Fields:

``format`` ("meshmark-keyfile"), ``version`` (2), ``method``, ``params`` (the method's parameters
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
Every keyfile is checked against a schema (:data:`FIELDS`, :data:`PARAM_CHECKS`, :data:`SIDE_CHECKS`,
:data:`MESH_CHECKS`: types, ranges, required fields, no NaN, no negative ids, bounded nesting, UTF-8)
before anything in it is used (``validate_keyfile_dict``). Fields not in the schema are allowed (a
newer meshmark may add some) but must be plain JSON within the nesting limit.

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
from .. import ranges as _ranges

FORMAT = "meshmark-keyfile"
VERSION = 3
READABLE_VERSIONS = (1, 2, 3)  # 1: no "weld" field, read as weld=False; 1-2: no tag
MAX_BYTES = 256 << 20  # a keyfile holds one id per carrier: far below this even for huge meshes
MAX_DEPTH = 8          # the keyfile's own nesting is 3; deeper is refused before use
MAX_CARRIER_ID = 1 << 31


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
    def from_dict(cls, d, source: str = "keyfile") -> "Keyfile":
        """A Keyfile from its parsed JSON, after :func:`validate_keyfile_dict` (the tag is checked by
        :func:`load_keyfile`, which knows the key)."""
        validate_keyfile_dict(d, source)
        stored = "key" in d
        def bad(msg):
            raise MeshError(f"{source}: {msg}")
        choice = _read_choice(d, bad)
        return cls(method=d["method"], params=d["params"], key=d.get("key"), payload=d["payload"], coding=d["coding"],
                   weld=d["weld"] if d["version"] >= 2 else False, store_key=stored, choice=choice,
                   side_info=d["side_info"], mesh=d["mesh"],
                   meshmark_version=str(d.get("meshmark_version", "")), created=str(d.get("created", "")))


# --- schema ---------------------------------------------------------------------------------------
def _int(lo, hi):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, int):
            return f"must be an integer, got {_short(v)}"
        if not lo <= v <= hi:
            return f"must be in {lo}..{hi}, got {v}"
    return check


def _float(lo, hi, lo_open=False, hi_open=False):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            return f"must be a number, got {_short(v)}"
        ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
        if not ok:
            return f"must be a finite number in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}, got {v!r}"
    return check


def _type(t, choices=None):
    def check(v):
        if not isinstance(v, t) or (t is int and isinstance(v, bool)):
            return f"must be a {t.__name__}, got {_short(v)}"
        if choices is not None and v not in choices:
            return f"must be one of {', '.join(map(repr, choices))}, got {_short(v)}"
    return check


def _optional(check):
    return lambda v: None if v is None else check(v)


def _short(v) -> str:
    r = repr(v)
    return r if len(r) <= 60 else r[:60] + "..."


# Top-level fields: name -> (check, first version that requires it; None = optional). Other helpers
# extend these tables (e.g. FIELDS["code"] = (_type(dict), None)).
FIELDS = {
    "format": (_type(str, (FORMAT,)), 1),
    "version": (_type(int, READABLE_VERSIONS), 1),
    "method": (_type(str), 1),
    "params": (_type(dict), 1),
    "weld": (_type(bool), 2),
    "key": (_type(str), None),
    "key_stored": (_type(bool), None),
    "payload": (_type(dict), 1),
    "coding": (_type(dict), 1),
    "side_info": (_type(dict), 1),
    "mesh": (_type(dict), 1),
    "meshmark_version": (_type(str), None),
    "created": (_type(str), None),
    "tag": (_type(str), None),  # required in a version-3 file (load_keyfile); to_dict() has none
}
# Method parameters (the ranges of meshmark.ranges); absent ones are not required here (each method
# reads its own), unknown ones are left to the method.
_R = _ranges.RANGES
PARAM_CHECKS = {
    "K": _int(*_R["K"]), "n_thr": _optional(_int(*_R["n_thr"])), "n_robust": _int(*_R["n_robust"]),
    "center_iters": _int(*_R["center_iters"]), "origin_iters": _int(*_R["origin_iters"]),
    "eps": _float(0.0, 1.0, lo_open=True), "alpha": _float(0.0, 0.5, lo_open=True, hi_open=True),
    "delta_k": _float(0.0, 1.0, lo_open=True, hi_open=True), "guard": _float(0.0, 0.25, hi_open=True),
    "thesis_exact": _type(bool), "solver": _type(str, ("iterative", "direct")),
    "origin_mode": _type(str, ("axis", "vertices")), "carrier": _type(str),
}
SIDE_CHECKS = {
    "lo": _float(-1e300, 1e300), "hi": _float(-1e300, 1e300), "scale": _type(str), "range_search": _type(bool),
}
MESH_CHECKS = {
    "n_vertices": _int(0, 2**31 - 1), "n_faces": _int(0, 2**31 - 1), "n_input_vertices": _int(0, 2**31 - 1),
    "n_input_faces": _int(0, 2**31 - 1), "bbox_diagonal": _float(0.0, 1e300),
}

REQUIRED = {"params": ("K",), "mesh": ("n_vertices",), "side_info": ("carriers",)}


def _depth_ok(d, limit: int) -> bool:
    stack = [(d, 1)]
    while stack:
        v, depth = stack.pop()
        if isinstance(v, (dict, list)):
            if depth > limit:
                return False
            items = v.values() if isinstance(v, dict) else v
            stack.extend((x, depth + 1) for x in items if isinstance(x, (dict, list)))
    return True


def validate_keyfile_dict(d, source: str = "keyfile") -> None:
    """Check a parsed keyfile against the schema before anything in it is used: MeshError naming
    the field. Does not check the tag (see :func:`verify_keyfile_tag`)."""
    def bad(msg):
        raise MeshError(f"{source}: {msg}")
    if not isinstance(d, dict):
        bad("not a JSON object")
    if not _depth_ok(d, MAX_DEPTH):
        bad(f"nested deeper than {MAX_DEPTH} levels (corrupt or not a meshmark keyfile)")
    if d.get("format") != FORMAT:
        bad(f"not a meshmark keyfile (format is {_short(d.get('format'))}, expected {FORMAT!r})")
    version = d.get("version")
    if isinstance(version, bool) or version not in READABLE_VERSIONS:
        bad(f"keyfile version {_short(version)} is not supported (this meshmark reads versions "
            f"{', '.join(map(str, READABLE_VERSIONS))})")
    for name, (check, since) in FIELDS.items():
        if name not in d:
            if since is not None and version >= since:
                bad(f"field {name!r} is missing")
            continue
        why = check(d[name])
        if why:
            bad(f"field {name!r} {why}")
    if "key" not in d and version < 3:
        bad("field 'key' is missing")
    if "key" in d and not d["key"]:
        bad("field 'key' is empty")
    if d.get("key_stored") is False and "key" in d:
        bad("field 'key_stored' is false but the keyfile holds a key")
    from .framework import METHODS
    if d["method"] not in METHODS:
        bad(f"unknown method {_short(d['method'])} (known: {', '.join(METHODS)})")
    for table, name in ((PARAM_CHECKS, "params"), (SIDE_CHECKS, "side_info"), (MESH_CHECKS, "mesh")):
        for k, check in table.items():
            if k in d[name]:
                why = check(d[name][k])
                if why:
                    bad(f"{name}.{k} {why}")
    for name, keys in REQUIRED.items():
        for k in keys:
            if k not in d[name]:
                bad(f"{name}.{k} is missing")
    p = d["payload"]
    bits = p.get("bits")
    if p.get("kind") not in ("text", "bits") or not isinstance(bits, str) or set(bits) - {"0", "1"} or not bits:
        bad("payload must have kind 'text' or 'bits' and a non-empty 0/1 bit string")
    if isinstance(p.get("n_bits"), bool) or p.get("n_bits") != len(bits):
        bad(f"payload n_bits ({_short(p.get('n_bits'))}) does not match its bit string ({len(bits)} bits)")
    if p.get("sha256") != hashlib.sha256(bits.encode()).hexdigest():
        bad("payload digest does not match its bits (the keyfile was edited or corrupted)")
    c = d["coding"]
    _check_coding(c, len(bits), bad)
    if not c["n_coded"] <= MAX_CARRIER_ID:
        bad("coding.n_coded is out of range")
    ids = d["side_info"]["carriers"]
    if not isinstance(ids, list):
        bad("side_info.carriers is not a list")
    if len(ids) != c["n_coded"]:
        bad(f"side_info.carriers lists {len(ids)} carriers but coding.n_coded is {c['n_coded']}")
    K = d["params"].get("K")
    high = K if isinstance(K, int) and not isinstance(K, bool) else MAX_CARRIER_ID
    for i, v in enumerate(ids):
        if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < high:
            bad(f"side_info.carriers[{i}] must be an integer in 0..{high - 1}, got {_short(v)}")
    if len(set(ids)) != len(ids):
        bad("side_info.carriers lists a carrier twice")


# --- integrity tag ------------------------------------------------------------------------------
def _canonical(d: dict) -> bytes:
    body = {k: v for k, v in d.items() if k != "tag"}
    return json.dumps(body, sort_keys=True, separators=(",", ":"), ensure_ascii=True, allow_nan=False).encode()


def keyfile_tag(d: dict, key: str) -> str:
    """HMAC-SHA256 keyed by the key (UTF-8) of the canonical JSON of every field but ``tag``."""
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
    if not hmac.compare_digest(tag, keyfile_tag(d, key)):
        if "key" in d:
            raise MeshError(f"{source} was changed after it was written: its HMAC-SHA256 tag does not match "
                            "its content (edited, corrupted, or tampered with)")
        raise MeshError(f"{source}: the key is wrong, or the keyfile was changed after it was written "
                        "(its HMAC-SHA256 tag does not match)")
    return True


def _check_coding(c: dict, n_bits: int, bad) -> None:
    """The ``coding`` field: the keyed code or the convolutional scheme (:mod:`.coding`), or the older
    repetition code."""
    from . import coding
    if not isinstance(c.get("n_coded"), int) or isinstance(c.get("n_coded"), bool):
        bad("coding must have an integer n_coded")
    if c.get("scheme") == coding.KEYED:
        if not 1 <= n_bits <= coding.keyed_code.MAX_DATA_BITS:
            bad(f"coding scheme {coding.KEYED!r} takes 1 to {coding.keyed_code.MAX_DATA_BITS} payload bits, "
                f"the payload has {n_bits}")
        if c.get("info_bits") != n_bits or c.get("check_bits") != 0:
            bad(f"coding sizes are inconsistent with the payload (info_bits must be {n_bits}, check_bits 0)")
        if c["n_coded"] < coding.min_carriers(n_bits):
            bad(f"coding: {c['n_coded']} coded bits cannot carry {n_bits} payload bits")
    elif c.get("scheme") in coding.CONVOLUTIONAL:
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
        bad(f"coding scheme must be one of {', '.join(map(repr, coding.SCHEMES))} or 'repeat', "
            f"got {c.get('scheme')!r}")


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


def load_keyfile(path_or_keyfile, key: str | None = None) -> Keyfile:
    """Read, validate and check a keyfile (a path, or a Keyfile which is returned as is).

    The tag is checked with the keyfile's own key, or with ``key`` when the keyfile holds none
    (written with ``store_key=False``); such a keyfile without ``key`` raises :class:`KeyRequired`.
    """
    if isinstance(path_or_keyfile, Keyfile):
        kf = path_or_keyfile
        if kf.key is None and key is not None:
            import dataclasses
            kf = dataclasses.replace(kf, key=key)
        return kf
    path = os.fspath(path_or_keyfile)
    shown = os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    source = f"keyfile '{shown}'"
    try:
        with open(path, "rb") as f:
            raw = f.read(MAX_BYTES + 1)
    except OSError as exc:
        raise MeshError(f"cannot read keyfile '{shown}': {exc.strerror or exc}") from None
    if len(raw) > MAX_BYTES:
        raise MeshError(f"{source} is larger than {MAX_BYTES >> 20} MB (not a meshmark keyfile)")
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
