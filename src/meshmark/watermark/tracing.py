"""Copy tracing (fingerprinting): many marked copies of one asset, and which one leaked.

:func:`issue` marks N copies of a mesh, each with its own random codeword of C bits (one per carrier,
whitened and placed with the owner's key exactly as a payload is), all with the same parameters and
the original's side information, and records them in a registry (:class:`Registry`, one SQLite file).
:func:`trace` reads the carriers of a suspect mesh with their signed reliabilities s (the method's
soft read; Laplacian: a pair's count margin over its size) and correlates them with every codeword
issued: copy j scores T_j = sum_i (2 c_ji - 1) s_i (its matching bits m_j are reported too). For an
unmarked mesh (or another asset) each codeword's bits are fair coins independent of s, so T_j is
distributed as sum_i e_i |s_i| with fair signs e_i, whatever the mesh; the false-alarm probability,
corrected for the N codewords compared (Bonferroni), is::

    p_false_alarm = min(1, N * P(sum_i e_i |s_i| >= T_best))      (metrics.weighted_false_alarm_probability)

and a copy is named only when ``p_false_alarm < 1e-6`` (else ``copy`` is None: "none"). The same bound
holds for naming a *wrong* copy when the suspect is copy i (the other codewords are independent of
copy i's and of s). Weighting by reliability lets the many bits a pose flips with a small margin
count little (the posed Knight, docs/blender.md). A Laplacian read is also made at the recorded
histogram range (:func:`_reads`) and p multiplied by the number of distinct reads. With C carriers
read perfectly and none at a tie (s_i = 0), p is about N 2^-C as for the bit count: C >= 27 for
N = 100 (26 carriers rank the right copy first among 100 but certify only 100 * 2^-26 = 1.5e-6).

The registry (:class:`Registry`, :mod:`.registry`: schema, checks, locking) holds one row per
asset (the original's digest and its setup: method, parameters, carriers, side information, the
key's hash) and one per copy (its id, unique within the asset, and its codeword).

A second :func:`issue` of the same original into the same registry adds copies to its asset with
the asset's parameters and side information.

Every copy is kept within the distortion budget where the mesh allows (:mod:`.budget`: vertex RMSE
1e-4 and Hausdorff 5e-4 of the diagonal, 0.25 degrees of normal change): a new asset's trial copies
choose the blind mark's n_robust and the pattern's strength (``setup['budget']``), and a copy beyond
the budget is remade with a weaker pattern (:mod:`.copies`).

Informed tracing (:mod:`.informed`, docs/tracing.md): every copy also carries a keyed low-pass
pattern (settings in ``setup['informed']``; the field of copy j is derived from the key, the digest
and the copy id, nothing per copy is stored). When the original is available to :func:`trace`
(given, or found at the recorded path with the recorded digest) the pattern is correlated too and
the two tests are combined by Bonferroni: ``p = min(1, 2 min(p_blind, p_informed))``.
"""
from __future__ import annotations

import dataclasses
import hmac
import os

import numpy as np

from .._core import MeshError
from ..mesh import as_mesh, FacesLike, Mesh, MeshLike
from ..metrics import weighted_false_alarm_probability
from . import informed as _informed
from . import budget as _budget
from . import keys as _keys
from .copies import EXCLUDE_PASSES, LOST_SHARE, _NOT_TAKEN, _fit_budget, _mark_copies, _unwritable  # noqa: F401  (tracing.LOST_SHARE: API)
from .framework import DETECTION_THRESHOLD, MIN_CARRIERS, _weld
from .informed import source_digest  # noqa: F401  (tracing.source_digest: part of this module's API)
from .keyfile import Keyfile
from .methods import method_named
from .registry import MAX_COPIES, SCHEMA_VERSION, WAIT, Registry, check_copy_id, key_hash  # noqa: F401
from .._typing import PathLike, Progress
from typing import Iterable, Sequence
from typing import Any

# params="auto" for copies: the first rung of the ladder with at least 64 carriers (27 certify one
# copy among 100 only when every bit reads right; 64 still certify it with 10 of the 64 bits wrong
# among 100 copies, 7 among 10,000)
TRACE_CARRIERS = 64


class IssuedCopies(list):
    """What :func:`issue` returns: the list of ``(copy_id, V)`` (or ``(copy_id, path)``), with
    ``distortion``: ``{"limits": budget.BUDGET, "n_copies", "copies_beyond": copies beyond the
    budget, "largest_share": the largest of a copy's RMSE, Hausdorff and normal change over its
    limit}`` (:mod:`.budget`; 1 = at a limit)."""

    def __init__(self, items: Iterable[tuple[str, Any]], distortion: dict) -> None:
        super().__init__(items)
        self.distortion = distortion


def _setup_keyfile(setup: dict, key: str) -> Keyfile:
    """A Keyfile-shaped view of an asset's setup (for the framework's carrier reading)."""
    return Keyfile(method=setup["method"], params=setup["params"], key=key, payload={}, weld=setup["weld"],
                   coding={"scheme": "trace", "n_coded": len(setup["side_info"]["carriers"])},
                   side_info=setup["side_info"], mesh=setup["mesh"], choice=setup.get("choice"))


def _plan_ids(n_copies, ids) -> list | None:
    """The ids asked for, checked before any work (None: numbered under the registry's lock)."""
    if (n_copies is None) == (ids is None):
        raise MeshError("give either the number of copies or their ids")
    if ids is None:
        if isinstance(n_copies, bool) or not isinstance(n_copies, (int, np.integer)) or not 1 <= n_copies <= MAX_COPIES:
            raise MeshError(f"the number of copies must be an integer in 1..{MAX_COPIES:,}, got {n_copies!r}")
        return None
    ids = [check_copy_id(c, f"copy id {i + 1}") for i, c in enumerate(ids)]
    if not ids:
        raise MeshError("copy ids must be non-empty")
    if len(ids) > MAX_COPIES:
        raise MeshError(f"{len(ids):,} copy ids given; one issue makes at most {MAX_COPIES:,} copies")
    seen, dup = set(), []
    for c in ids:
        (dup.append(c) if c in seen else seen.add(c))
    if dup:
        raise MeshError(f"copy id(s) listed twice: {', '.join(sorted(set(dup))[:5])}")
    return ids


def issue(V: MeshLike, F: FacesLike = None, *, key: str | int, registry: PathLike | Registry,
          n_copies: int | None = None, ids: Sequence[str] | None = None, method: str = "laplacian",
          params: str | dict[str, Any] = "auto", weld: bool = True, store_key: bool = True, source_name: str = "",
          progress: Progress = None, original: PathLike | None = None, informed: bool = True, sink: Any = None,
          wait: float = WAIT,
          **method_params: Any) -> IssuedCopies:
    """Mark copies of the mesh, each with its own random codeword; record them in ``registry`` (a
    path or :class:`Registry`). Give ``n_copies`` (1..MAX_COPIES; numbered after the asset's largest numeric id:
    ``0001``, ...) or ``ids`` (strings usable in a file name, unique within the asset; the same id
    may be used by another asset). Returns a list of ``(copy_id, V)`` with V the (n, 3) float64 marked
    vertices (input order), or with ``sink`` a list of ``(copy_id, path)``: an :class:`IssuedCopies`,
    whose ``distortion`` says how many copies are beyond the distortion budget.

    The whole issue is one write transaction of the registry (``BEGIN IMMEDIATE``): a second issue
    into the same registry waits up to ``wait`` seconds and then numbers its copies after this one's.
    Nothing is recorded unless every copy is marked (and, with ``sink``, written).

    ``sink``: streams the copies to disk: ``sink.check(ids)`` (optional) is called once the ids are
    known, before any marking, and ``sink.write(copy_id, V)`` writes one copy to temporary files and
    returns ``[(temporary, final path), ...]`` (the first final path is recorded). After the last copy
    the rows are inserted, the temporaries renamed onto their paths and the transaction committed;
    on any failure the transaction is rolled back and every file written is removed.

    ``informed`` (default on, for a new asset): each copy also carries its keyed low-pass pattern
    (:mod:`.informed`); ``original``: the path of the original file, recorded so that :func:`trace`
    can find it (optional; ``meshmark issue`` records IN)."""
    report = progress or (lambda f, t: None)
    mesh_in = as_mesh(V, F)
    key = _keys.check_key(key)
    m = method_named(method)
    ids = _plan_ids(n_copies, ids)
    w = _weld(mesh_in, weld)
    mesh = w.mesh if w is not None else mesh_in
    sha = source_digest(mesh)
    own = not isinstance(registry, Registry)
    reg = Registry(registry) if own else registry
    staged, placed = [], []
    try:
        reg.begin(wait)
        found = reg.asset(sha)
        existing = reg.copy_ids(found[0]) if found is not None else set()
        if ids is None:
            i = 1 + max((int(c) for c in existing if c.isascii() and c.isdigit()), default=0)
            ids = []
            while len(ids) < n_copies:
                if f"{i:04d}" not in existing:
                    ids.append(f"{i:04d}")
                i += 1
        dup = sorted(set(ids) & existing)
        if dup:
            raise MeshError(f"copy id(s) already used for this asset: {', '.join(dup[:5])}")
        if sink is not None and hasattr(sink, "check"):
            sink.check(ids)
        if found is None:
            from .auto import choose
            p, cids, side, choice = choose(mesh, m, params, method_params, None, need=TRACE_CARRIERS)
            side = dict(side)
            asset_id = None
            inf_params = _informed.default_params(mesh) if informed else None
        else:
            asset_id, setup = found
            if setup["method"] != method:
                raise MeshError(f"the registry holds this mesh with the {setup['method']} method, not {method}")
            if not hmac.compare_digest(setup["key_sha256"], key_hash(key)):
                raise MeshError("the registry holds this mesh under another key")
            p, choice = setup["params"], setup.get("choice")
            inf_params = setup.get("informed")
            cids = np.asarray(setup["side_info"]["carriers"], np.int64)
            side = {k: v for k, v in setup["side_info"].items() if k != "carriers"}
        orig = _informed.Original(mesh, inf_params) if inf_params else None
        budget = None
        tune = params == "auto" and "n_robust" not in method_params  # the blind mark's n_robust may change
        if found is None:  # the parameters that keep trial copies within the distortion budget
            p, scale, budget = _fit_budget(mesh, m, p, side, cids, key, sha, orig, tune_blind=tune)
            if orig is not None and scale != 1.0:
                inf_params["rmse"] = orig.params["rmse"] = inf_params["rmse"] * scale
        rec = budget if found is None else setup.get("budget")
        remake = (rec or {}).get("remake", True)  # False: the gentlest trial copies were far beyond the budget
        excluded: list = []
        passes = 0
        while True:
            C = int(len(cids))
            if C < MIN_CARRIERS:
                raise MeshError(f"the mesh offers only {C} carrier bits to the {method} method; at least {MIN_CARRIERS} are needed")
            try:
                out, rows, trace_side, shares = _mark_copies(mesh, w, m, p, side if found is not None else None, side,
                                                     cids, ids, key, sha, orig, sink, staged, report,
                                                     tune_blind=tune, remake=remake)
                break
            except MeshError as exc:
                # a new asset whose copies do not take: leave out the carriers that fail a trial (at most
                # EXCLUDE_PASSES passes, each with fresh trials on the carriers left)
                if found is not None or passes == EXCLUDE_PASSES or not any(t in str(exc) for t in _NOT_TAKEN):
                    raise
                more = _unwritable(mesh, m, p, side, cids, key, sha, orig, passes)
                passes += 1
                if not more:
                    raise
                excluded = sorted(set(excluded) | set(more))
                cids = np.asarray([c for c in cids if int(c) not in set(excluded)], np.int64)
                for tmp, _ in staged:
                    if os.path.lexists(tmp):
                        os.remove(tmp)
                staged.clear()
        if asset_id is None:
            setup = {"method": method, "params": p, "choice": choice, "weld": bool(weld),
                     "key": key if store_key else None, "key_sha256": key_hash(key),
                     "side_info": {**trace_side, "carriers": [int(c) for c in cids]},
                     "mesh": {"n_vertices": mesh.n_vertices, "n_faces": mesh.n_faces}}
            if inf_params:
                setup["informed"] = inf_params
            if budget is not None:
                setup["budget"] = budget
            if excluded:  # carriers left out because their bit did not take in a trial (_unwritable)
                setup["excluded_carriers"] = [int(c) for c in excluded]
            asset_id = reg.add_asset(sha, source_name, setup, C)
        if original is not None:
            reg.set_original(asset_id, os.fspath(original))
        reg.add_copies(asset_id, rows)
        for tmp, final in staged:
            existed = os.path.lexists(final)
            try:
                os.replace(tmp, final)
            except OSError as exc:
                raise MeshError(f"cannot write '{final}': {exc.strerror or exc}") from None
            placed.append((final, existed))
        reg.commit()
        placed = []
        report(1.0, "done")
        return IssuedCopies(out, _budget.summary(shares))
    except BaseException:
        reg.rollback()
        for final, existed in placed:
            if not existed and os.path.lexists(final):
                os.remove(final)
        raise
    finally:
        for tmp, _ in staged:
            if os.path.lexists(tmp):
                os.remove(tmp)
        if own:
            reg.close()


def set_paths(registry: PathLike | Registry, paths: dict, asset_id: int | None = None) -> None:
    """Record where copies were written (copy id -> path; without ``asset_id``: the copy of that id
    issued last)."""
    own = not isinstance(registry, Registry)
    reg = Registry(registry, create=False, readonly=False) if own else registry
    try:
        reg.begin()
        try:
            reg.set_paths(paths, asset_id)
        except BaseException:
            reg.rollback()
            raise
        reg.commit()
    finally:
        if own:
            reg.close()


def _reads(mesh: Mesh, kf: Keyfile, key: str, read_soft) -> list:
    """The distinct reads (bits, soft) of the carriers: as the method reads them (the Laplacian searches
    the histogram's range, undoing a uniform scale) and, when the asset's side information has that
    search on, also at the recorded range: a pose can fool the search (the Knight: t = 0.95 read 41 of
    83 bits, the recorded range 72). Each read is a function of the suspect alone, so the false alarm
    is bounded by Bonferroni over the distinct reads (1 when both agree, the usual case)."""
    reads = [read_soft(mesh, kf, key)]
    if kf.side_info.get("range_search", False):
        b, s = read_soft(mesh, dataclasses.replace(kf, side_info={**kf.side_info, "range_search": False}), key)
        if not (np.array_equal(b, reads[0][0]) and np.array_equal(s, reads[0][1])):
            reads.append((b, s))
    return reads


def trace(V: MeshLike, F: FacesLike = None, *, registry: PathLike | Registry, key: str | int | None = None,
          original: Mesh | PathLike | None = None) -> dict:
    """Which issued copy is this mesh? Returns a dict with ``detected``, ``copy`` (id or None),
    ``p_false_alarm`` (corrected for every codeword compared and, when the original was used, for the
    two tests), ``evidence`` (``"informed+blind"`` or ``"blind"``), ``matches``, ``n_carriers``,
    ``n_copies``, ``asset_id``, ``second_matches`` (``copy``, ``matches``, ``n_carriers``, ``asset_id`` and
    ``second_matches`` are None when no copy is named), ``blind`` and ``informed`` (each test's best copy,
    its p and details; ``informed`` is None without an original) and ``originals`` (per asset: where
    the original was looked for and whether it was used).

    ``original``: the original (a path or a Mesh); without it the path recorded by :func:`issue` is
    tried, and an original whose digest differs from the registry's is not used (blind only). A given
    original that matches no asset of the registry is a MeshError.

    ``V``: a :class:`~meshmark.Mesh`, or (n, 3) float64 positions in mesh units with ``F`` (m, k) integer faces."""
    from ..io import read_mesh

    mesh0 = as_mesh(V, F)
    given = None
    if original is not None:
        given = read_mesh(os.fspath(original)) if isinstance(original, (str, os.PathLike)) else as_mesh(original)
    reg = registry if isinstance(registry, Registry) else Registry(registry, create=False)
    try:
        assets = reg.assets()
        if key is not None:  # the assets issued under this key (the registry keeps each key's hash)
            key = _keys.check_key(key)
            h = key_hash(key)
            mine = [a for a in assets if hmac.compare_digest(a[1]["key_sha256"], h)]
            if assets and not mine:
                raise MeshError("wrong key: no asset in the registry was issued under this key")
            assets = mine
        elif any(a[1].get("key") is None for a in assets):
            raise MeshError("the registry does not store the key: give --key")
        n_total = sum(reg.n_copies(a[0]) for a in assets)
        best, best_inf, originals, n_reads = None, None, [], 1
        for asset_id, setup, C in assets:
            k = key if key is not None else setup["key"]
            from .framework import _prepare, read_soft
            kf = _setup_keyfile(setup, k)
            mesh, _, _, _ = _prepare(mesh0, kf)
            cids, W = reg.codewords(asset_id, C)
            if not cids:
                continue
            reads = _reads(mesh, kf, k, read_soft)
            n_reads = max(n_reads, len(reads))
            Wi = W.astype(np.int32)
            for r, (bits, soft) in enumerate(reads):
                b = bits.astype(np.int32)
                matches = C - int(b.sum()) - Wi.sum(1) + 2 * (Wi @ b)
                score = (2.0 * W - 1.0) @ soft  # the soft correlation; matches break ties
                j = int(np.lexsort((-matches, -score))[0])
                second = int(np.partition(matches, -2)[-2]) if len(cids) > 1 else 0
                cand = {"asset_id": asset_id, "copy_id": cids[j], "matches": int(matches[j]), "n_carriers": int(C),
                        "second_matches": second, "score": float(score[j]), "read": ("searched", "recorded")[r],
                        "tail": weighted_false_alarm_probability(soft, float(score[j]))}
                if best is None or cand["tail"] < best["tail"]:
                    best = cand
            orig, info = _informed.find_original(reg, asset_id, setup, given)
            originals.append(info)
            if orig is not None:
                sha = reg.original(asset_id)[2]
                # the suspect as the blind test welded it (kf.weld is setup["weld"])
                det = _informed.detect(mesh, orig,
                                       [_informed.copy_seed(k, sha, c) for c in cids])
                z = det.pop("z")
                jz = int(np.argmax(z))
                zs = np.sort(z)
                inf = {"asset_id": asset_id, "copy_id": cids[jz], "z": float(z[jz]),
                       "second_z": float(zs[-2]) if len(zs) > 1 else 0.0, **det}
                if best_inf is None or inf["z"] > best_inf["z"]:
                    best_inf = inf
        if given is not None and not any(o["status"] == "given" for o in originals):
            raise MeshError("the original given is not the original of any asset in the registry (its digest differs)")
        if best is None:
            return {"detected": False, "copy": None, "p_false_alarm": 1.0, "evidence": "blind", "matches": None,
                    "n_carriers": None, "n_copies": n_total, "asset_id": None, "second_matches": None,
                    "blind": None, "informed": None, "originals": originals}
        p_blind = min(1.0, n_reads * n_total * best["tail"])  # Bonferroni over codewords and distinct reads
        blind = {"copy": best["copy_id"], "asset_id": best["asset_id"], "p_false_alarm": p_blind,
                 "matches": best["matches"], "n_carriers": best["n_carriers"], "score": best["score"],
                 "read": best["read"], "n_reads": n_reads}
        informed = None
        winner, p = blind, p_blind
        if best_inf is not None:
            p_inf = min(1.0, n_total * _informed.tail_probability(best_inf["z"]))
            informed = {"copy": best_inf.pop("copy_id"), "p_false_alarm": p_inf, **best_inf}
            p = min(1.0, 2.0 * min(p_blind, p_inf))  # Bonferroni over the two tests
            if p_inf < p_blind:
                winner = informed
        detected = bool(p < DETECTION_THRESHOLD)
        # the copy's asset, bits and carriers only for a named copy (null for "none"); "blind" and
        # "informed" keep each test's best candidate with its own asset_id
        named = (lambda v: v if detected else None)
        return {"detected": detected, "copy": named(winner["copy"]), "p_false_alarm": p,
                "evidence": "informed+blind" if informed is not None else "blind",
                "matches": named(best["matches"]), "n_carriers": named(best["n_carriers"]), "n_copies": n_total,
                "asset_id": named(winner["asset_id"]), "second_matches": named(best["second_matches"]),
                "blind": blind, "informed": informed, "originals": originals}
    finally:
        if not isinstance(registry, Registry):
            reg.close()
