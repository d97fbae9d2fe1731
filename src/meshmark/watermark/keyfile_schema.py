"""The keyfile schema: every field a keyfile holds is checked here before anything uses it.

:func:`validate` is the one validation layer (``keyfile.validate_keyfile_dict`` calls it): a keyfile
that passes it can be read by the framework and by its method without a ``KeyError``, ``TypeError``
or ``UnicodeEncodeError``; every refusal is a :class:`~meshmark.MeshError` naming the field
(``params.thesis_exact is missing``, ``side_info.lo (2.5) must be below side_info.hi (1.0)``).

What is checked, for every readable version (1, 2, 3) and every method:

* the whole object: nesting at most :data:`MAX_DEPTH`, every string and object key valid UTF-8 (a
  ``\\udcff`` escape in the JSON is a lone surrogate, refused with its field's path);
* the top-level fields of :data:`FIELDS` (type, choices, the version that requires them); ``tag``
  is 64 lowercase hex digits; ``key`` a non-empty string, or absent with ``key_stored: false``
  (version 3);
* ``params``: exactly the method's parameters (:data:`METHOD_PARAMS`: the ones ``resolve`` writes;
  unknown ones are refused, since they would change how the mark is read), each in its documented
  range (:mod:`meshmark.ranges`), and the method's own rules (Laplacian ``thesis_exact`` uses the
  thesis carrier; Cho's ``alpha`` below 1/2 or 1/3, ``thesis_exact`` without guard and centring);
* ``side_info``: the method's fields (:data:`METHOD_SIDE`; Laplacian ``lo < hi``, finite, with a
  range float64 can split into K bins), ``carriers`` distinct integers below the method's number of
  bins or bin pairs;
* ``payload`` (kind, bit string, length, digest; a text payload is whole bytes), ``coding``
  (a known scheme and sizes consistent with the payload; ``n_coded`` = number of carriers),
  ``mesh`` (counts), ``choice`` (its mode).

Top-level fields outside :data:`FIELDS` are allowed (a newer meshmark may add some) but must be
plain JSON within the nesting limit; inside ``params``, ``side_info``, ``payload`` and ``coding``
unknown fields are refused.
"""
from __future__ import annotations

import hashlib
import math
import re

from .._core import MeshError
from .. import ranges as _ranges

FORMAT = "meshmark-keyfile"
VERSION = 3
READABLE_VERSIONS = (1, 2, 3)  # 1: no "weld" field, read as weld=False; 1-2: no tag
MAX_DEPTH = 8          # the keyfile's own nesting is 3; deeper is refused before use
MAX_CARRIER_ID = 1 << 31
MAX_PAYLOAD_BITS = 255  # payload.MAX_DATA_BITS: the longest message embed accepts
TAG_RE = re.compile(r"[0-9a-f]{64}")


# --- checks: each returns None (fine) or why the value is refused --------------------------------
def _int(lo, hi):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, int):
            return f"must be an integer, got {_short(v)}"
        if not lo <= v <= hi:
            return f"must be in {lo}..{hi}, got {_short(v)}"
    return check


def _float(lo, hi, lo_open=False, hi_open=False):
    def check(v):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            return f"must be a number, got {_short(v)}"
        ok = math.isfinite(v) and (v > lo if lo_open else v >= lo) and (v < hi if hi_open else v <= hi)
        if not ok:
            return f"must be a finite number in {'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}, got {_short(v)}"
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
    r = r if len(r) <= 60 else r[:60] + "..."
    return r.encode("ascii", "backslashreplace").decode("ascii")


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
    "choice": (_optional(_type(dict)), None),
    "meshmark_version": (_type(str), None),
    "created": (_type(str), None),
    "tag": (_type(str), None),  # required in a version-3 file (load_keyfile); to_dict() has none
}
_R = _ranges.RANGES
_K = _int(*_R["K"])
# Generic parameter checks (a method without an entry in METHOD_PARAMS gets these).
PARAM_CHECKS = {
    "K": _K, "n_thr": _optional(_int(*_R["n_thr"])), "n_robust": _int(*_R["n_robust"]),
    "center_iters": _int(*_R["center_iters"]), "origin_iters": _int(*_R["origin_iters"]),
    "eps": _float(0.0, 1.0, lo_open=True), "alpha": _float(0.0, 0.5, lo_open=True, hi_open=True),
    "delta_k": _float(0.0, 1.0, lo_open=True, hi_open=True), "guard": _float(0.0, 0.25, hi_open=True),
    "thesis_exact": _type(bool), "solver": _type(str, ("iterative", "direct")),
    "origin_mode": _type(str, ("axis", "vertices")), "carrier": _type(str),
}
SIDE_CHECKS = {
    "lo": _float(-1e300, 1e300), "hi": _float(-1e300, 1e300), "scale": _type(str, ("none", "mean_edge_length", "local")),
    "range_search": _type(bool),
}
MESH_CHECKS = {
    "n_vertices": _int(0, 2**31 - 1), "n_faces": _int(0, 2**31 - 1), "n_input_vertices": _int(0, 2**31 - 1),
    "n_input_faces": _int(0, 2**31 - 1), "bbox_diagonal": _float(0.0, 1e300),
}
REQUIRED = {"params": ("K",), "mesh": ("n_vertices",), "side_info": ("carriers",)}

_REQ, _OPT = True, False
_P = PARAM_CHECKS
_CHO = {"K": (_K, _REQ), "alpha": (_P["alpha"], _REQ), "delta_k": (_P["delta_k"], _REQ),
        "guard": (_P["guard"], _REQ), "center_iters": (_P["center_iters"], _REQ), "thesis_exact": (_P["thesis_exact"], _REQ)}
# method -> {parameter: (check, required)}: the parameters each method's resolve() writes, in every
# keyfile version (Laplacian's solver and carrier came later: a keyfile without carrier reads 'thesis').
METHOD_PARAMS = {
    "laplacian": {"K": (_K, _REQ), "n_thr": (_int(*_R["n_thr"]), _REQ), "n_robust": (_P["n_robust"], _REQ),
                  "eps": (_P["eps"], _REQ), "thesis_exact": (_P["thesis_exact"], _REQ),
                  "solver": (_P["solver"], _OPT), "carrier": (None, _OPT)},  # carrier: laplacian.CARRIERS
    "radial": {"K": (_K, _REQ), "n_thr": (_int(*_R["n_thr"]), _REQ), "origin_mode": (_P["origin_mode"], _REQ),
               "origin_iters": (_P["origin_iters"], _REQ)},
    "cho-mean": _CHO,
    "cho-variance": {**_CHO, "alpha": (_float(0.0, 1.0 / 3.0, lo_open=True, hi_open=True), _REQ)},
}
# method -> {side_info field: (check, required)} besides "carriers"; and the carrier ids' bound:
# "pairs" (bin pairs (B2,B3), ...: (K - 2) // 2, eq. 7.1.6 / 6.1.4) or "bins" (K, Cho).
METHOD_SIDE = {
    "laplacian": {"lo": (SIDE_CHECKS["lo"], _REQ), "hi": (SIDE_CHECKS["hi"], _REQ),
                  "scale": (SIDE_CHECKS["scale"], _OPT), "range_search": (SIDE_CHECKS["range_search"], _OPT)},
    "radial": {}, "cho-mean": {}, "cho-variance": {},
}
CARRIER_BOUND = {"laplacian": "pairs", "radial": "pairs", "cho-mean": "bins", "cho-variance": "bins"}
PAYLOAD_FIELDS = ("kind", "n_bits", "bits", "sha256")
CODING_FIELDS = {"repeat": ("scheme", "frame_bits", "n_coded")}  # the others: scheme, info_bits, check_bits, n_coded
MIN_SPREAD = 1e-9  # Laplacian hi - lo relative to max(|lo|, |hi|): narrower bins are not float64-distinct


def _walk(d, bad) -> None:
    """Nesting at most MAX_DEPTH; every string and object key valid UTF-8 (named by its path)."""
    stack = [(d, 1, "")]
    while stack:
        v, depth, path = stack.pop()
        if depth > MAX_DEPTH:
            bad(f"nested deeper than {MAX_DEPTH} levels (corrupt or not a meshmark keyfile)")
        items = v.items() if isinstance(v, dict) else enumerate(v)
        for k, x in items:
            sub = f"{path}.{k}" if isinstance(k, str) else f"{path}[{k}]"
            if isinstance(k, str) and not _utf8(k):
                bad(f"field name {_short(k)} in {path.lstrip('.') or 'the keyfile'} is not valid UTF-8 "
                    "(a lone surrogate escape)")
            if isinstance(x, str):
                if not _utf8(x):
                    bad(f"field {sub.lstrip('.')!r} is not valid UTF-8 text (a lone surrogate escape such as "
                        f"\\udcff): {_short(x)}")
            elif isinstance(x, (dict, list)):
                stack.append((x, depth + 1, sub))


def _utf8(s: str) -> bool:
    try:
        s.encode("utf-8")
        return True
    except UnicodeEncodeError:
        return False


def _table(d: dict, name: str, spec: dict, method: str, bad, extra=()) -> None:
    """``d[name]`` against ``spec`` {field: (check, required)}: unknown fields, missing required
    ones, and values out of range refused."""
    obj = d[name]
    unknown = sorted(set(obj) - set(spec) - set(extra))
    if unknown:
        bad(f"{name}.{_short(unknown[0]).strip(chr(39))} is not a field of a {method} keyfile's {name} "
            f"(known: {', '.join(list(spec) + list(extra))})")
    for k, (check, required) in spec.items():
        if k not in obj:
            if required:
                bad(f"{name}.{k} is missing (the {method} method needs it)")
            continue
        why = check(obj[k]) if check is not None else None
        if why:
            bad(f"{name}.{k} {why}")


def validate(d, source: str, methods) -> None:
    """Check a parsed keyfile against the schema: MeshError naming the field. ``methods``: the
    registered watermark methods (``framework.METHODS``). Does not check the tag's value."""
    def bad(msg):
        raise MeshError(f"{source}: {msg}")
    if not isinstance(d, dict):
        bad("not a JSON object")
    _walk(d, bad)
    if d.get("format") != FORMAT:
        bad(f"not a meshmark keyfile (format is {_short(d.get('format'))}, expected {FORMAT!r})")
    version = d.get("version")
    if isinstance(version, bool) or not isinstance(version, int) or version not in READABLE_VERSIONS:
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
    _check_key(d, version, bad)
    method = d["method"]
    if method not in methods:
        bad(f"unknown method {_short(method)} (known: {', '.join(methods)})")
    _check_params(d, method, bad)
    _check_side(d, method, bad)
    for k, check in MESH_CHECKS.items():
        if k in d["mesh"]:
            why = check(d["mesh"][k])
            if why:
                bad(f"mesh.{k} {why}")
    for name, keys in REQUIRED.items():
        for k in keys:
            if k not in d[name]:
                bad(f"{name}.{k} is missing")
    bits = _check_payload(d["payload"], bad)
    _check_coding(d["coding"], len(bits), bad)
    _check_carriers(d, method, bad)
    choice = d.get("choice")
    if choice is not None and choice.get("mode") not in ("auto", "thesis", "given"):
        bad("field 'choice' must be an object with mode 'auto', 'thesis' or 'given'")


def _check_key(d: dict, version: int, bad) -> None:
    if "tag" in d and not TAG_RE.fullmatch(d["tag"]):
        bad(f"field 'tag' must be 64 lowercase hexadecimal digits (an HMAC-SHA256), got {_short(d['tag'])}")
    if "key" not in d:
        if version < 3:
            bad("field 'key' is missing")
        if d.get("key_stored") is not False:
            bad("field 'key' is missing (a keyfile written without its key says \"key_stored\": false)")
    elif not d["key"]:
        bad("field 'key' is empty")
    elif d.get("key_stored") is False:
        bad("field 'key_stored' is false but the keyfile holds a key")


def _generic(table: dict, name: str, checks: dict, bad) -> None:
    """The generic checks of ``table`` (``params`` or ``side_info``) for a method without a schema entry."""
    for k, check in checks.items():
        if k in table:
            why = check(table[k])
            if why:
                bad(f"{name}.{k} {why}")


def _check_params(d: dict, method: str, bad) -> None:
    p = d["params"]
    spec = METHOD_PARAMS.get(method)
    if spec is None:  # a method registered without a schema entry: the generic checks
        _generic(p, "params", PARAM_CHECKS, bad)
        return
    _table(d, "params", spec, method, bad)
    if method == "laplacian":
        CARRIERS = _ranges.LAPLACIAN_CARRIERS
        carrier = p.get("carrier")
        if "carrier" in p and (not isinstance(carrier, str) or carrier not in CARRIERS):
            bad(f"params.carrier must be one of {', '.join(map(repr, CARRIERS))}, got {_short(carrier)}")
        if p["thesis_exact"] and carrier not in (None, "thesis"):
            bad(f"params.thesis_exact is true but params.carrier is {carrier!r} (thesis_exact uses the thesis carrier)")
    elif method.startswith("cho-") and p["thesis_exact"] and (p["guard"] or p["center_iters"]):
        bad("params.thesis_exact is true but params.guard or params.center_iters is not 0 (the paper has neither)")


def _check_side(d: dict, method: str, bad) -> None:
    spec = METHOD_SIDE.get(method)
    s = d["side_info"]
    if spec is None:
        _generic(s, "side_info", SIDE_CHECKS, bad)
        return
    _table(d, "side_info", spec, method, bad, extra=("carriers",))
    if "lo" in spec:
        lo, hi = s["lo"], s["hi"]
        if not lo < hi:
            bad(f"side_info.lo ({lo!r}) must be below side_info.hi ({hi!r})")
        if not hi - lo > MIN_SPREAD * max(abs(lo), abs(hi)) or not (hi - lo) / d["params"]["K"] > 1e-300:
            bad(f"side_info.lo ({lo!r}) and side_info.hi ({hi!r}) are too close to split into "
                f"{d['params']['K']} bins")


def _check_payload(p: dict, bad) -> str:
    unknown = sorted(set(p) - set(PAYLOAD_FIELDS))
    if unknown:
        bad(f"payload.{_short(unknown[0]).strip(chr(39))} is not a payload field (known: {', '.join(PAYLOAD_FIELDS)})")
    bits = p.get("bits")
    if p.get("kind") not in ("text", "bits") or not isinstance(bits, str) or set(bits) - {"0", "1"} or not bits:
        bad("payload must have kind 'text' or 'bits' and a non-empty 0/1 bit string (payload.kind, payload.bits)")
    if len(bits) > MAX_PAYLOAD_BITS:
        bad(f"payload.bits holds {len(bits)} bits; a payload has at most {MAX_PAYLOAD_BITS}")
    if isinstance(p.get("n_bits"), bool) or p.get("n_bits") != len(bits):
        bad(f"payload n_bits ({_short(p.get('n_bits'))}) does not match its bit string ({len(bits)} bits)")
    if p.get("sha256") != hashlib.sha256(bits.encode()).hexdigest():
        bad("payload digest does not match its bits (the keyfile was edited or corrupted)")
    if p["kind"] == "text" and len(bits) % 8:  # (bytes that are not UTF-8: extraction says so)
        bad(f"payload.bits of a text payload must be whole bytes, got {len(bits)} bits")
    return bits


def _check_coding(c: dict, n_bits: int, bad) -> None:
    """The ``coding`` field: the keyed code or the convolutional scheme (:mod:`.coding`), or the older
    repetition code."""
    from . import coding
    scheme = c.get("scheme")
    if not isinstance(scheme, str) or (scheme not in coding.SCHEMES and scheme != "repeat"):
        bad(f"coding scheme must be one of {', '.join(map(repr, coding.SCHEMES))} or 'repeat', "
            f"got {_short(scheme)} (coding.scheme)")
    known = CODING_FIELDS.get(scheme, ("scheme", "info_bits", "check_bits", "n_coded"))
    unknown = sorted(set(c) - set(known))
    if unknown:
        bad(f"coding.{_short(unknown[0]).strip(chr(39))} is not a field of coding scheme {scheme!r} "
            f"(known: {', '.join(known)})")
    n = c.get("n_coded")
    if not isinstance(n, int) or isinstance(n, bool):
        bad(f"coding must have an integer n_coded, got {_short(n)} (coding.n_coded)")
    if not 1 <= n <= MAX_CARRIER_ID:
        bad(f"coding.n_coded is out of range (1..{MAX_CARRIER_ID}), got {n}")
    for k in known[1:-1]:
        if isinstance(c.get(k), bool) or not isinstance(c.get(k), int):
            bad(f"coding.{k} must be an integer, got {_short(c.get(k))}")
    if scheme == coding.KEYED:
        if not 1 <= n_bits <= coding.keyed_code.MAX_DATA_BITS:
            bad(f"coding scheme {coding.KEYED!r} takes 1 to {coding.keyed_code.MAX_DATA_BITS} payload bits, "
                f"the payload has {n_bits}")
        if c["info_bits"] != n_bits or c["check_bits"] != 0:
            bad(f"coding sizes are inconsistent with the payload (info_bits must be {n_bits}, check_bits 0)")
    elif scheme in coding.CONVOLUTIONAL:
        if c["info_bits"] != coding.info_bits(n_bits) or c["check_bits"] != coding.CHECK_BITS:
            bad(f"coding sizes are inconsistent with the payload (info_bits must be {coding.info_bits(n_bits)}, "
                f"check_bits {coding.CHECK_BITS})")
    else:  # repeat
        if c["frame_bits"] != n_bits + 16 or n < c["frame_bits"]:
            bad("coding sizes are inconsistent with the payload (coding.frame_bits must be the payload's bits + 16, "
                "at most coding.n_coded)")
    if scheme != "repeat" and n < coding.min_carriers(n_bits):
        bad(f"coding: {n} coded bits cannot carry {n_bits} payload bits (coding.n_coded)")


def _check_carriers(d: dict, method: str, bad) -> None:
    c = d["coding"]
    ids = d["side_info"]["carriers"]
    if not isinstance(ids, list):
        bad("side_info.carriers is not a list")
    if len(ids) != c["n_coded"]:
        bad(f"side_info.carriers lists {len(ids)} carriers but coding.n_coded is {c['n_coded']}")
    K = d["params"].get("K")
    bound = CARRIER_BOUND.get(method)
    if isinstance(K, int) and not isinstance(K, bool):
        high = (K - 2) // 2 if bound == "pairs" else K
        what = {"pairs": f"the {high} bin pairs of K = {K} bins", "bins": f"the K = {K} bins"}.get(bound, f"K = {K}")
    else:
        high, what = MAX_CARRIER_ID, "the carrier id limit"
    for i, v in enumerate(ids):
        if isinstance(v, bool) or not isinstance(v, int) or not 0 <= v < high:
            bad(f"side_info.carriers[{i}] must be an integer in 0..{high - 1}, got {_short(v)} ({what})")
    if len(set(ids)) != len(ids):
        bad("side_info.carriers lists a carrier twice")
