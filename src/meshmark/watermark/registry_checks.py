"""Checks of a registry's fields (:mod:`.registry`): copy ids, row digests, the asset's setup."""
from __future__ import annotations

import hashlib
import hmac
import json
import math
import os
import re

from .._core import MeshError

MAX_ID_CHARS = 100
HEX64 = re.compile(r"[0-9a-f]{64}")


def shown(path) -> str:
    return os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def key_hash(key: str) -> str:
    return hashlib.sha256(key.encode()).hexdigest()


def check_copy_id(c, where: str = "copy id") -> str:
    """A copy id as stored: a non-empty string of at most 100 characters, usable in a file name (no
    path separator, control character or unpaired surrogate). MeshError naming ``where`` otherwise."""
    if not isinstance(c, (str, int)) or isinstance(c, bool):
        raise MeshError(f"{where} must be text, got {type(c).__name__}")
    c = str(c).strip()
    if not c:
        raise MeshError(f"{where} is empty")
    if len(c) > MAX_ID_CHARS:
        raise MeshError(f"{where} is longer than {MAX_ID_CHARS} characters")
    bad = [ch for ch in c if ch in "/\\" or ord(ch) < 32 or ord(ch) == 127 or 0xD800 <= ord(ch) <= 0xDFFF]
    if bad or c in (".", ".."):
        what = repr(bad[0]) if bad else repr(c)
        raise MeshError(f"{where} {c.encode('utf-8', 'backslashreplace').decode()!r} cannot be part of a file name "
                        f"(it contains {what})")
    return c


def _digest(kind: bytes, fields) -> str:
    body = json.dumps([f.hex() if isinstance(f, bytes) else f for f in fields], ensure_ascii=True,
                      separators=(",", ":")).encode()
    return hashlib.blake2b(body, digest_size=16, person=kind).hexdigest()


def asset_check(row) -> str:
    return _digest(b"meshmark-asset", row)


def copy_check(row) -> str:
    return _digest(b"meshmark-copy", row)


def _reject_constant(name):
    raise ValueError(f"{name}")


def _finite(text):
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(text[:40])
    return v


class Damaged(Exception):
    pass


def need(ok, why):
    if not ok:
        raise Damaged(why)


def text_or_null(v, what):
    need(v is None or isinstance(v, str), f"{what} is not text")


def validate_setup(setup_text, n_carriers: int, asset_id) -> dict:
    """An asset's ``setup`` JSON, checked field by field (through the keyfile schema for the method's
    parameters, side information and mesh counts). Raises Damaged naming the field."""
    from . import informed as _informed
    from .keyfile import FORMAT as KF_FORMAT, validate_keyfile_dict
    from .keys import check_key

    where = f"asset {asset_id}"
    need(isinstance(setup_text, str), f"{where}: setup is not text")
    try:
        s = json.loads(setup_text, parse_constant=_reject_constant, parse_float=_finite)
    except (ValueError, RecursionError):
        raise Damaged(f"{where}: setup is not valid JSON") from None
    need(isinstance(s, dict), f"{where}: setup is not a JSON object")
    need(isinstance(s.get("key_sha256"), str) and HEX64.fullmatch(s["key_sha256"]), f"{where}: setup.key_sha256")
    key = s.get("key")
    if key is not None:
        need(isinstance(key, str), f"{where}: setup.key is not text")
        try:
            check_key(key)
        except MeshError:
            raise Damaged(f"{where}: setup.key is not a valid key") from None
        need(hmac.compare_digest(key_hash(key), s["key_sha256"]), f"{where}: setup.key does not match its hash")
    for name, t in (("params", dict), ("side_info", dict), ("mesh", dict), ("weld", bool), ("method", str)):
        need(isinstance(s.get(name), t), f"{where}: setup.{name} is missing or not a {t.__name__}")
    need(s.get("choice") is None or isinstance(s["choice"], dict), f"{where}: setup.choice")
    carriers = s["side_info"].get("carriers")
    need(isinstance(carriers, list) and len(carriers) == n_carriers,
          f"{where}: setup.side_info.carriers does not list n_carriers ({n_carriers}) carriers")
    # the method's fields, through the keyfile schema (a keyfile-shaped view of the setup)
    kf = {"format": KF_FORMAT, "version": 3, "method": s["method"], "params": s["params"], "weld": s["weld"],
          "key": "registry", "payload": {"kind": "bits", "n_bits": 1, "bits": "0",
                                         "sha256": hashlib.sha256(b"0").hexdigest()},
          "coding": {"scheme": "repeat", "frame_bits": 17, "n_coded": n_carriers},
          "side_info": s["side_info"], "mesh": s["mesh"]}
    if s.get("choice") is not None:
        kf["choice"] = s["choice"]
    try:
        validate_keyfile_dict(kf, source=f"{where}: setup")
    except MeshError as exc:
        raise Damaged(str(exc)) from None
    except Exception as exc:  # a schema check that trips over a value it did not expect
        raise Damaged(f"{where}: setup ({type(exc).__name__})") from None
    need(isinstance(s["mesh"].get("n_vertices"), int), f"{where}: setup.mesh.n_vertices")
    if s.get("informed") is not None:
        try:
            _informed.check_params(s["informed"])
        except (MeshError, TypeError, ValueError):
            raise Damaged(f"{where}: setup.informed") from None
    return s
