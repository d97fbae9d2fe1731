"""Embed, extract and detect for any watermark method.

A method (``meshmark.watermark.laplacian.METHOD`` and, later, the radial methods) provides::

    resolve(mesh, params) -> dict                  # parameters with defaults filled in
    carriers(mesh, params) -> (ids, side_info)     # the carriers the mesh offers (capacity = len(ids))
    embed(mesh, params, side_info, ids, bits) -> (V, side_info, stats)
    extract(mesh, params, side_info, ids) -> (bits, soft)

and this module does the rest, identically for every method:

0. weld (``weld=True``, the default): vertices at exactly equal positions are merged
   (:func:`meshmark.weld_vertices`), the method runs on the welded mesh, and the marked positions
   are scattered back to every copy, so copies stay coincident and the model does not crack open.
   Exporters split vertices at UV seams and sharp edges, and non-indexed glTF/STL keep every corner
   apart: without welding the edge graph of such a mesh is a set of loose pieces. The choice is
   stored in the keyfile and extraction welds the same way;
1. choose the parameters (``params="auto"``, the default: :mod:`.auto`; ``"thesis"``: the published
   defaults) and code the payload (:mod:`.coding`: up to 24 bits a keyed random code decoded by
   maximum likelihood, beyond a 20-bit keyed check and a tail-biting convolutional code, rate-matched
   to all carriers; older keyfiles name the K = 7 convolutional code or the repetition code of
   :mod:`.payload`, still read);
2. whiten the coded bits and assign them to carriers in a key-dependent order (:mod:`.keys`);
3. embed, then re-extract and re-embed the carriers that did not take (at most 4 rounds);
4. write the keyfile (:mod:`.keyfile`).

Extraction un-permutes and un-whitens with the keyfile's key (or a key given), compares the raw bits
with the expected ones (matches, NC, CDR), computes the false-alarm probability P(X >= matches),
X ~ Bin(n, 1/2), and decides ``detected = p_false_alarm < 1e-6`` (:data:`DETECTION_THRESHOLD`): a
random or unmarked mesh, or a wrong key, is called marked with probability below one in a million.
The message is decoded from the methods' signed reliabilities (maximum likelihood over the keyed
codebook, or soft Viterbi) and accepted only if the decoder certifies it (a wrong message below 1e-6
per attempt: the keyed code's threshold or the keyed check) *and* the mark is detected: no message is
returned without a detection.
"""
from __future__ import annotations

import hashlib
from dataclasses import dataclass, field

import numpy as np

from .. import __version__
from .._core import MeshError
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike
from ..topology import Welded, weld_vertices
from ..metrics import cdr as _cdr, false_alarm_probability, normalized_correlation
from . import keys as _keys
from .keyfile import Keyfile, load_keyfile
from . import coding as _coding
from .payload import Payload, decode as _decode_repeat, repeat_to
from .methods import METHODS, register, method_named as _method  # noqa: F401  (re-exported)
from .._typing import PathLike, Progress
from typing import Any

DETECTION_THRESHOLD = 1e-6
MIN_CARRIERS = 8
MAX_ROUNDS = 4

def merge_params(method_name: str, defaults: dict, params: dict) -> dict:
    """``defaults`` overridden by the non-None ``params``; MeshError naming any unknown parameter."""
    unknown = set(params) - set(defaults)
    if unknown:
        raise MeshError(f"unknown parameter(s) for the {method_name} method: {', '.join(sorted(unknown))} "
                        f"(known: {', '.join(defaults)})")
    return {**defaults, **{k: v for k, v in params.items() if v is not None}}


def min_detectable_carriers() -> int:
    """The fewest carriers for which a perfect read-back is a detection: P(X >= n) = 2^-n for
    X ~ Bin(n, 1/2) must fall below DETECTION_THRESHOLD (20 carriers for 1e-6)."""
    n = MIN_CARRIERS
    while false_alarm_probability(n, n) >= DETECTION_THRESHOLD:
        n += 1
    return n


def check_detectable(cap: int, what: str) -> None:
    """Refuse an embedding that could never be detected: with ``cap`` carriers even every bit read
    back correctly gives P(false alarm) = 2^-cap, which must be below the threshold."""
    need = min_detectable_carriers()
    if cap < need:
        raise MeshError(f"the mesh offers only {cap} carrier bits to {what}; at least {need} are needed: a mark "
                        f"that small can never be detected (all {cap} bits matching still has P(false alarm) = "
                        f"{false_alarm_probability(cap, cap):.2g}, not below {DETECTION_THRESHOLD:g}). Nothing was "
                        "written.")


@dataclass
class EmbedResult:
    """``V``: (n, 3) float64 marked vertices; ``keyfile``: what extract needs; iterable as (V, keyfile)."""
    V: np.ndarray
    keyfile: Keyfile
    capacity: int
    stats: dict = field(default_factory=dict)

    def __iter__(self):
        return iter((self.V, self.keyfile))

    def to_dict(self) -> dict:
        """The JSON-ready summary (method, capacity, coding, parameters and their choice,
        weld, the method's stats); no vertex array."""
        c = self.keyfile.coding
        return {"method": self.keyfile.method, "capacity": self.capacity, "n_coded": c["n_coded"],
                "coding": c["scheme"], "info_bits": c.get("info_bits", c.get("frame_bits")),
                "payload_bits": self.keyfile.payload["n_bits"], "params": self.keyfile.params,
                "params_choice": self.keyfile.choice, "weld": self.keyfile.weld,
                "welded_vertices": self.keyfile.mesh["n_vertices"], **self.stats}


@dataclass
class ExtractResult:
    detected: bool
    nc: float
    cdr: float
    matches: int
    n_bits: int
    p_false_alarm: float
    message: object          # str (text payload), bit string, or None when not recovered
    message_ok: bool
    reason: str = ""         # why the message was not recovered
    warnings: list = field(default_factory=list)
    bits: np.ndarray = None  # (n_coded,) extracted coded bits (0/1), after un-whitening
    n_vertices: int = 0      # vertices the method saw (after welding, if the keyfile welds)
    n_merged: int = 0        # input vertices merged into a coincident copy by welding
    expected_vertices: int | None = None  # the keyfile's count (None if it has none)

    @property
    def same_vertex_count(self) -> bool:
        """Whether the (welded) mesh has the vertex count the keyfile was made for."""
        return self.expected_vertices is None or self.n_vertices == self.expected_vertices

    def to_dict(self) -> dict:
        """The JSON-ready verdict (detected, nc, cdr, matches, bits, p_false_alarm, message,
        reason, warnings, vertex counts); no arrays."""
        return {"detected": self.detected, "nc": self.nc, "cdr": self.cdr, "matches": self.matches,
                "bits": self.n_bits, "p_false_alarm": self.p_false_alarm, "message": self.message,
                "message_ok": self.message_ok, "reason": self.reason, "warnings": list(self.warnings),
                "n_vertices": self.n_vertices, "n_merged": self.n_merged,
                "expected_vertices": self.expected_vertices}


def _weld(mesh: Mesh, weld) -> Welded | None:
    """The welded mesh (None when ``weld`` is off)."""
    if not isinstance(weld, (bool, np.bool_)):
        raise MeshError(f"weld must be True or False, got {weld!r}")
    return weld_vertices(mesh) if weld else None


def capacity(V: MeshLike, F: FacesLike = None, method: str = "laplacian", weld: bool = True,
             params: str | dict[str, Any] = "auto", n_data: int | None = None, key: str | int | None = None,
             key_bins: bool = False, **method_params: Any) -> int:
    """Number of carrier bits the mesh offers to ``method`` (before coding), on the welded mesh unless
    ``weld=False``: with the parameters ``params="auto"`` (the default) chooses for a payload of
    ``n_data`` bits (:mod:`.auto`; without ``n_data``, its first rung: the published numbers with the
    method's default carrier), or with the published parameters and carrier (``params="thesis"``).
    With ``key_bins=True`` the bins are the ones :func:`embed` uses with that ``key`` (required).

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    mesh = as_mesh(V, F)
    w = _weld(mesh, weld)
    mesh = w.mesh if w is not None else mesh
    from .auto import choose
    m = _method(method)
    move_K, method_params = moved_bins(mesh, m, params, method_params, key, key_bins, n_data)
    _, ids, _, _ = choose(mesh, m, params, method_params, n_data, move_K=move_K)
    return int(len(ids))


def moved_bins(mesh: Mesh, m, params, method_params: dict, key, key_bins, n_data=None):
    """(move_K, method_params) for key-dependent bins (:func:`.keys.key_bins`, docs/security.md §5):
    with ``params="auto"`` a function moving every rung's K; otherwise the published (or given
    parameters') K moved, in ``method_params``. (None, method_params) when ``key_bins`` is off."""
    from ..ranges import check_bool
    if not check_bool("key_bins", key_bins):
        return None, method_params
    key = _keys.check_key(key)
    if method_params.get("K") is not None or (isinstance(params, dict) and params.get("K") is not None):
        raise MeshError("key_bins chooses the bin count K from the key: do not give K as well")
    if params == "auto":  # every rung of the automatic ladder gets its K moved, then first fit
        return (lambda K: _keys.key_bins(key, m.name, int(K))), method_params
    from .auto import choose
    p0, _, _, _ = choose(mesh, m, params, method_params, n_data)  # published (or given) parameters
    return None, {**method_params, "K": _keys.key_bins(key, m.name, int(p0["K"]))}


def _coded(payload: Payload, key: str, method: str, n: int, scheme: str) -> np.ndarray:
    """(n,) coded bits of the payload under ``scheme`` (before whitening)."""
    if scheme == "repeat":  # keyfiles before the convolutional code
        return repeat_to(payload.frame(), n)
    return _coding.encode(payload.data, payload.kind, key, method, n, scheme)


def _expected(payload: Payload, key: str, method: str, n: int, scheme: str):
    coded = _coded(payload, key, method, n, scheme)
    white = _keys.whitening(key, method, n)
    order = _keys.permutation(key, method, n)
    return coded, white, order


def embed_channel(mesh: Mesh, m, p: dict, side: dict, ids, channel: np.ndarray, report=None, allow_lost: int = 0):
    """Write the channel bits ``channel[i]`` into carrier ``ids[i]`` (steps 3 of the module doc):
    embed, re-read, re-embed what did not take (at most MAX_ROUNDS). Returns (V, side, stats);
    MeshError if more than ``allow_lost`` carriers (default 0: any) still read wrong."""
    report = report or (lambda f, t: None)
    carriers = np.asarray(ids)
    cap = carriers.size
    Vm = mesh.V
    stats = {}
    todo = np.arange(cap)
    for rnd in range(MAX_ROUNDS):
        report(0.1 + 0.8 * rnd / MAX_ROUNDS, f"embedding round {rnd + 1}")
        Vm, side, st = m.embed(mesh.with_vertices(Vm) if rnd else mesh, p, side, carriers[todo], channel[todo])
        for k, v in st.items():
            stats[k] = stats.get(k, 0) + v if isinstance(v, (int, float)) and k.startswith("n_") else v
        got, _ = m.extract(mesh.with_vertices(Vm), p, side, carriers)
        todo = np.flatnonzero(got != channel)
        if todo.size == 0:
            break
    stats["rounds"] = rnd + 1
    if todo.size > allow_lost:
        raise MeshError(f"the {m.name} mark does not take on this mesh: {todo.size} of {cap} carrier bits still read "
                        f"wrong after {MAX_ROUNDS} rounds ({m.describe(p)}); nothing was changed. Try other parameters.")
    return Vm, side, stats


def embed(V: MeshLike, F: FacesLike = None, payload: str | bytes | None = None, key: str | int | None = None,
          method: str = "laplacian", progress: Progress = None, weld: bool = True,
          params: str | dict[str, Any] = "auto", store_key: bool = True, key_bins: bool = False,
          **method_params: Any) -> EmbedResult:
    """Embed ``payload`` (text, bit string or Payload) under ``key`` with ``method``.

    ``params="auto"`` (default) chooses the method's parameters for this mesh and payload
    (:mod:`.auto`, deterministic, recorded in the keyfile); ``"thesis"`` uses the published defaults.
    Parameters given as keywords (``K=...``) are kept as given in both modes.

    Returns an :class:`EmbedResult` with the marked vertices (one row per input vertex, in input
    order) and the keyfile; the input arrays are never modified. With ``weld=True`` (default) the
    method runs on the mesh with coincident vertices merged and every copy gets the same marked
    position (copies that were bit-identical stay bit-identical). Raises MeshError (nothing
    changed) when the mesh is invalid, offers fewer than 8 carriers, or the coded message does not
    fit (the message states the capacity in bits).
    ``progress(fraction, text)`` is called as the work advances, if given. With ``store_key=False``
    the written keyfile leaves the key out (extraction then needs ``key=``). With ``key_bins=True``
    (and no ``K`` given) the bin count is moved by a key-derived 3-12 % (:func:`.keys.key_bins`):
    with ``params="auto"`` every rung of the ladder's K, then the first rung that fits is chosen;
    with ``"thesis"`` (or a dict) the published K. A second embedder with another key then uses
    misaligned bins and the first mark survives overmarking in most cases (docs/security.md §5); the
    K used is in the keyfile (auto: also ``choice["key_bins"]``), so extraction is unchanged. Off by
    default (docs/security.md §5 says why).
    """
    report = progress or (lambda f, t: None)
    mesh_in = as_mesh(V, F)
    from ..ranges import check_bool
    store_key = check_bool("store_key", store_key)
    key_bins = check_bool("key_bins", key_bins)
    m = _method(method)
    key = _keys.check_key(key)
    pl = Payload.coerce(payload)
    w = _weld(mesh_in, weld)
    mesh = w.mesh if w is not None else mesh_in
    report(0.05, "finding carriers")
    from .auto import choose
    move_K, method_params = moved_bins(mesh, m, params, method_params, key, key_bins, pl.data.size)
    p, ids, side, choice = choose(mesh, m, params, method_params, pl.data.size, move_K=move_K)
    cap = int(len(ids))
    if cap < MIN_CARRIERS:
        raise MeshError(f"the mesh offers only {cap} carrier bits to the {method} method with {m.describe(p)}; "
                        f"at least {MIN_CARRIERS} are needed")
    check_detectable(cap, f"the {method} method with {m.describe(p)}")
    need = _coding.min_carriers(pl.data.size)
    if need > cap:
        raise MeshError(f"the message needs {need} carrier bits ({pl.data.size} data + {_coding.CHECK_BITS} check "
                        f"bits at code rate 2/3) but the mesh offers {cap} with the {method} method ({m.describe(p)}); "
                        f"at most {_coding.max_data_bits(cap)} payload bits fit")
    from .auto import fallbacks
    later = fallbacks(mesh, m, method_params, choice, move_K)
    while True:
        coded, white, order = _expected(pl, key, method, cap, _coding.scheme_for(pl.data.size))
        channel = coded ^ white
        carriers = np.asarray(ids)[order]  # carrier of coded bit i
        try:
            Vm, side, stats = embed_channel(mesh, m, p, side, carriers, channel, report)
            break
        except MeshError as exc:
            # automatic parameters: a rung whose mark does not take gives way to the next that fits
            nxt = next(later, None) if "does not take" in str(exc) else None
            if nxt is None:
                raise
            p, ids, side, choice = nxt
            cap = int(len(ids))
    if key_bins:
        stats["key_bins"] = True
    report(0.95, "writing keyfile")
    kf = _make_keyfile(m, p, key, weld, pl, side, ids, mesh, mesh_in, Vm, choice,
                       _coding.coding_field(pl.data.size, cap), store_key=store_key)
    if w is not None:
        Vm = w.scatter(Vm)
        stats["n_merged"] = w.n_merged
    report(1.0, "done")
    return EmbedResult(V=Vm, keyfile=kf, capacity=cap, stats=stats)


def _make_keyfile(m, p, key, weld, pl: Payload, side, ids, mesh, mesh_in, Vm, choice, coding,
                  store_key: bool = True) -> Keyfile:
    bits = pl.bitstring()
    return Keyfile(method=m.name, params=p, key=key, weld=bool(weld), store_key=store_key,
                   payload={"kind": pl.kind, "n_bits": pl.data.size, "bits": bits,
                            "sha256": hashlib.sha256(bits.encode()).hexdigest()},
                   coding=coding, side_info={**side, "carriers": [int(c) for c in ids]},
                   mesh={"n_vertices": mesh.n_vertices, "n_faces": mesh.n_faces,
                         "n_input_vertices": mesh_in.n_vertices, "n_input_faces": mesh_in.n_faces,
                         "bbox_diagonal": float(np.linalg.norm(Vm.max(0) - Vm.min(0)))},
                   choice=choice, meshmark_version=__version__)


def read_soft(mesh: Mesh, kf: Keyfile, key: str):
    """(raw bits (n,), signed reliabilities (n,)) of the keyfile's carriers, in coded-bit order and
    un-whitened: bit i = 1 and soft i > 0 both mean coded bit i reads 1; |soft| <= 1 is the
    method's reliability (Laplacian: the pair's count margin relative to its size)."""
    m = _method(kf.method)
    n = int(kf.coding["n_coded"])
    ids = np.asarray(kf.side_info["carriers"], dtype=np.int64)
    if ids.size != n:
        raise MeshError(f"keyfile: {ids.size} carriers listed but {n} coded bits")
    white = _keys.whitening(key, kf.method, n)
    order = _keys.permutation(key, kf.method, n)
    got, soft = m.extract(mesh, kf.params, kf.side_info, ids[order])
    bits = (np.asarray(got, np.uint8) ^ white).astype(np.uint8)
    soft = np.clip(np.asarray(soft, np.float64), -1.0, 1.0) * (1.0 - 2.0 * white)
    return bits, soft


def _prepare(mesh: Mesh, kf: Keyfile):
    """(mesh as the method sees it, n_merged, warnings, expected vertex count)."""
    w = _weld(mesh, kf.weld)
    n_merged = 0
    if w is not None:
        mesh, n_merged = w.mesh, w.n_merged
    warnings = []
    expected = kf.mesh.get("n_vertices")
    if mesh.n_vertices != expected:
        welded = f" ({mesh.n_vertices + n_merged} before welding)" if n_merged else ""
        warnings.append(f"the mesh has {mesh.n_vertices} vertices{welded} but the keyfile was made for "
                        f"{expected} (simplified, cropped or remeshed?); extracting blindly")
    return mesh, n_merged, warnings, expected


def extract(V: MeshLike, F: FacesLike = None, keyfile: Keyfile | PathLike | None = None,
            key: str | int | None = None, progress: Progress = None) -> ExtractResult:
    """Extract and detect the watermark described by ``keyfile`` (a path or Keyfile).

    ``key`` overrides the keyfile's key (to test a key), and is required when the keyfile was written
    without it (``store_key=False``); the keyfile's HMAC tag is checked first (a changed keyfile, or a
    wrong key for a key-less keyfile, is a MeshError). The mesh may differ from the marked one
    (attacked, deformed, re-exported): extraction is blind and never needs the original mesh. If the
    keyfile says so (``weld``), coincident vertices are welded first, exactly as at embedding. The
    message is decoded only when the mark is detected.
    """
    report = progress or (lambda f, t: None)
    mesh = as_mesh(V, F)
    if keyfile is None:
        raise MeshError("a keyfile is required to extract")
    kf = load_keyfile(keyfile, key=key)  # schema, then the HMAC tag (with the given key if none is stored)
    _method(kf.method)
    key = _keys.check_key(kf.key if key is None else key)
    mesh, n_merged, warnings, expected = _prepare(mesh, kf)
    if not kf.tagged:  # a version 1-2 file, or a tag stripped and the version lowered: say so
        warnings.append("the keyfile carries no integrity tag (an old version, or the tag was removed): "
                        "changes to it cannot be detected")
    n = int(kf.coding["n_coded"])
    pl = Payload.from_bits(kf.payload["bits"])
    pl = Payload(kf.payload["kind"], pl.data)
    scheme = kf.coding["scheme"]
    report(0.2, "extracting")
    bits, soft = read_soft(mesh, kf, key)
    coded = _coded(pl, key, kf.method, n, scheme)
    matches = int((bits == coded).sum())
    p_fa = false_alarm_probability(matches, n)
    detected = bool(p_fa < DETECTION_THRESHOLD)
    found, reason = None, ""
    if not detected:
        reason = "no watermark detected (a message is only read from a detected mark)"
    elif scheme == "repeat":
        found, _, reason = _decode_repeat(bits, np.abs(soft), int(kf.coding["frame_bits"]), pl.kind)
    else:
        data, reason = _coding.decode(soft, pl.data.size, pl.kind, key, kf.method, scheme)
        if data is not None:
            found = Payload(pl.kind, data)
            try:
                found.message()
            except UnicodeDecodeError:
                found, reason = None, "the recovered bytes are not valid UTF-8"
    message = found.message() if found is not None else None
    report(1.0, "done")
    return ExtractResult(detected=detected, nc=normalized_correlation(coded, bits),
                         cdr=_cdr(coded, bits), matches=matches, n_bits=n, p_false_alarm=p_fa,
                         message=message, message_ok=found is not None, reason=reason, warnings=warnings, bits=bits,
                         n_vertices=mesh.n_vertices, n_merged=n_merged,
                         expected_vertices=None if expected is None else int(expected))
