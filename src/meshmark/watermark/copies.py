"""Writing the copies of :func:`.tracing.issue`: each copy's codeword on top of its informed pattern,
read back with the asset's shared side information; trial copies that find the carriers a copy
cannot write (:func:`_unwritable`) and the parameters that keep copies within the distortion budget
(:func:`_fit_budget`, :mod:`.budget`). The registry, the ids and the transaction stay in
:mod:`.tracing`."""
from __future__ import annotations

import secrets

import numpy as np

from .._core import MeshError
from . import budget as _budget
from . import informed as _informed
from . import keys as _keys
from .framework import MAX_ROUNDS, embed_channel

# A copy may leave at most C // LOST_SHARE of its C carrier bits unwritten (none below 64 carriers):
# on some meshes a few pairs hold vertices whose carrier value the solve cannot move (vtk_trumpet: closed
# 24-sided tubes of degree-3 vertices, all at one value), and whether their bit takes depends on the
# copy's informed pattern and codeword. The registry keeps the random codeword drawn, so the other
# copies' codewords stay fair coins independent of the suspect and the false-alarm bound is unchanged;
# the copy itself still reads C - C // 64 of C bits right: p <= 1e5 * P(Bin(C, 1/2) >= C - C // 64),
# below 1e-12 for C >= 64 (1e5 = MAX_COPIES).
LOST_SHARE = 64


_NOT_TAKEN = ("does not take", "do not read back")  # the messages of a copy whose carriers do not take
TRIALS = 16  # trial codewords written on the original before carriers are left out (_unwritable)
EXCLUDE_PASSES = 3  # rounds of trials; each leaves out more carriers if a copy still does not take


def _copy_steps(p: dict, tune_blind: bool, informed: bool) -> list:
    """(parameters, pattern scale) a copy tries in order until it is within the budget: the asset's,
    then a larger n_robust (``tune_blind``; n_robust only decides how many lengths the embedding moves,
    never how a carrier is read, so copies of one asset may differ in it), then a weaker pattern. The
    codeword is never redrawn: choosing it by its distortion would favour bits the original already reads."""
    steps = [(p, 1.0)]
    if tune_blind and "n_robust" in p:
        cap = int(p.get("n_thr", 2)) - 1
        for nr in _budget.COPY_N_ROBUST:
            v = min(nr, cap)
            if v > steps[-1][0]["n_robust"]:
                steps.append((dict(p, n_robust=v), 1.0))
    if informed:
        steps += [(steps[-1][0], s) for s in _budget.COPY_SCALES]
    return steps


def _mark_copies(mesh, w, m, p, trace_side, side, cids, ids, key, sha, orig, sink, staged, report,
                 tune_blind: bool = False, remake: bool = True):
    """(out, rows, trace_side, shares): every copy marked with its random codeword over the carriers ``cids``
    (with ``sink``: written to temporaries, appended to ``staged``). ``trace_side`` None: the first
    copy's side information serves every copy. A copy beyond the distortion budget is remade along
    :func:`_copy_steps` until it is within (if none is, the first step that takes is kept: a
    weaker mark would not make the copy invisible); ``shares``: each copy's largest share of the
    budget (budget.measure); ``remake`` False: no copy is remade (the asset's gentlest trial copies are
    beyond budget.HOPELESS, _fit_budget). MeshError if a copy leaves more than
    C // LOST_SHARE carrier bits unwritten."""
    C = int(len(cids))
    lost = C // LOST_SHARE  # carrier bits a copy may leave unwritten (see LOST_SHARE)
    white = _keys.whitening(key, m.name, C)
    order = _keys.permutation(key, m.name, C)
    carriers = np.asarray(cids)[order]
    ref = _budget.Reference(mesh) if orig is None else orig
    steps = _copy_steps(p, tune_blind, orig is not None) if remake else [(p, 1.0)]
    out, rows, shares = [], [], []
    pats = None
    for j, cid in enumerate(ids):
        report(j / len(ids), f"copy {cid}")
        cw = np.unpackbits(np.frombuffer(secrets.token_bytes((C + 7) // 8), np.uint8))[:C]
        ch = cw ^ white
        if orig is not None and j % _informed._BATCH == 0:
            pats = orig.patterns([_informed.copy_seed(key, sha, c) for c in ids[j:j + _informed._BATCH]])
        best, err = None, None
        for pc, s in steps:  # the pattern's scale changes z, never the null (informed.detect)
            # the keyed pattern first, the blind mark on top
            base = mesh if orig is None else mesh.with_vertices(orig.marked(s * pats[:, j % _informed._BATCH]))
            try:
                Vs, ts = _write_copy(mesh, base, m, pc, trace_side, side, carriers, ch, lost, cid)
            except MeshError as exc:  # does not read back with the shared side information
                err = exc
                continue
            share = _budget.worst(_budget.measure(ref.V, ref.T, Vs, ref.diag))
            if best is None:
                best = (Vs, ts, share)  # kept if no step is within: the most robust mark that takes
            if share <= 1.0:
                best = (Vs, ts, share)
                break
        if best is None:
            raise err
        Vm, trace_side, share = best
        shares.append(share)
        Vout = w.scatter(Vm) if w is not None else Vm
        path = None
        if sink is not None:
            files = list(sink.write(cid, Vout))
            staged.extend(files)
            path = files[0][1] if files else None
            out.append((cid, path))
        else:
            out.append((cid, Vout))
        rows.append((cid, np.packbits(cw).tobytes(), path))
    return out, rows, trace_side, shares


def _write_copy(mesh, base, m, p, trace_side, side, carriers, ch, lost, cid):
    """(V, trace_side): the channel word ``ch`` written on ``base`` (the original, or the original
    moved by the copy's pattern) so that it reads back with the asset's one side information
    (``trace_side``; None: this copy's becomes it). MeshError if more than ``lost`` bits do not."""
    C = len(carriers)
    Vm, s_j, _ = embed_channel(base, m, p, dict(trace_side or side), carriers, ch, allow_lost=lost)
    if trace_side is None:
        trace_side = s_j  # the first copy's side information serves every copy
    # every copy must read back with the one side information kept for the asset, at its recorded
    # histogram range (trace reads there too, _reads; the range search may settle elsewhere on a copy
    # whose margins are small): re-embed the carriers that do not (the marked mesh's scale differs
    # slightly from copy to copy)
    fixed = {**trace_side, "range_search": False}
    for _ in range(MAX_ROUNDS):
        got, _ = m.extract(mesh.with_vertices(Vm), p, fixed, carriers)
        bad = np.flatnonzero(got != ch)
        if bad.size == 0:
            break
        Vm, _, _ = m.embed(mesh.with_vertices(Vm), p, dict(trace_side), carriers[bad], ch[bad])
    else:
        got, _ = m.extract(mesh.with_vertices(Vm), p, fixed, carriers)
        bad = np.flatnonzero(got != ch)
    if bad.size > lost:
        raise MeshError(f"copy {cid}: {bad.size} of {C} carrier bits do not read back with the shared side "
                        f"information (at most {lost} may); nothing was recorded")
    return Vm, trace_side


def _trial(mesh, m, p, side, cids, base, seed):
    """(V, channel, read): a trial copy: a random channel word (from ``seed``) over ``cids`` written on
    ``base`` (the original, or the original moved by a trial pattern) as a copy is (embed_channel,
    every bit allowed to fail), and how it reads back."""
    C = int(len(cids))
    ch = np.random.default_rng(seed).integers(0, 2, C).astype(np.uint8)
    Vm, s_t, _ = embed_channel(base, m, p, dict(side), cids, ch, allow_lost=C)
    got, _ = m.extract(mesh.with_vertices(Vm), p, s_t, cids)
    return Vm, ch, got


def _unwritable(mesh, m, p, side, cids, key, sha, orig, attempt: int = 0) -> list:
    """The carriers whose bit does not take in at least one of TRIALS trial copies of the original:
    a keyed random channel word over ``cids``, on top of a trial informed pattern (seeds of ids no copy
    can have), written as a copy is (embed_channel). On vtk_trumpet these are the pairs that hold
    closed 24-sided tubes of degree-3 vertices, all at one carrier value, which the solve cannot move;
    left in, their bit depends on the neighbouring carriers' bits and the copy's pattern."""
    cids = np.asarray(cids, np.int64)
    tag = "" if attempt == 0 else f"{attempt}-"  # fresh trials on each pass
    seeds = [_informed.copy_seed(key, sha, f"\0trial-{tag}{t}") for t in range(TRIALS)]
    pats = orig.patterns(seeds) if orig is not None else None
    failed = set()
    for t, seed in enumerate(seeds):
        base = mesh if pats is None else mesh.with_vertices(orig.marked(pats[:, t]))
        _, ch, got = _trial(mesh, m, p, side, cids, base, seed)
        failed.update(int(c) for c in cids[got != ch])
    return sorted(failed)


def _fit_budget(mesh, m, p, side, cids, key, sha, orig, tune_blind: bool):
    """(p, pattern scale, record): the first step of budget.LADDER whose trial copies (budget.TRIALS:
    pattern and a random channel word, written as copies are, with the first trial's side information
    serving the others) all take and fit budget.MARGIN of the distortion budget; if none does, the
    first within the budget itself, else the first step that takes (the automatic parameters).
    When the automatic parameters do not fit, the gentlest step is tried next: if even its best trial
    copy is beyond budget.HOPELESS times the budget, no step can bring copies within and the automatic
    parameters are kept at once (``record['remake']`` False: copies are not remade either;
    ``record['gentlest_share']``: that best trial's share).
    ``tune_blind``: the blind parameters may change (n_robust; automatic Laplacian parameters only).
    The choice depends on the original and the key alone, never on a copy's codeword (choosing
    codewords by their distortion would favour bits the original already reads)."""
    cids = np.asarray(cids, np.int64)
    ref = _budget.Reference(mesh) if orig is None else orig
    seeds = [_informed.copy_seed(key, sha, f"\0budget-{t}") for t in range(_budget.TRIALS)]
    pats = orig.patterns(seeds) if orig is not None else None
    lost = len(cids) // LOST_SHARE

    def step(nr, scale):
        pp = dict(p)
        if nr is not None and tune_blind and "n_robust" in pp:  # never beyond n_thr - 1: a margin of one vertex
            pp["n_robust"] = max(int(pp["n_robust"]), min(nr, int(pp.get("n_thr", nr + 1)) - 1))
        return pp, (scale if orig is not None else 1.0)

    def trials(pp, scale):  # the trial copies' shares of the budget; None: they do not take
        shares, ts = [], None
        try:
            for t, seed in enumerate(seeds):
                base = mesh if pats is None else mesh.with_vertices(orig.marked(scale * pats[:, t]))
                ch = np.random.default_rng(seed).integers(0, 2, len(cids)).astype(np.uint8)
                Vm, ts = _write_copy(mesh, base, m, pp, ts, side, cids, ch, lost, f"trial {t + 1}")
                shares.append(_budget.worst(_budget.measure(ref.V, ref.T, Vm, ref.diag)))
        except MeshError:
            return None
        return shares

    best = first = near = None
    done: dict = {}
    remake, gentlest = True, None
    for i, (nr, scale) in enumerate(_budget.LADDER):
        pp, scale = step(nr, scale)
        k = (pp.get("n_robust"), scale)
        if k not in done:
            done[k] = trials(pp, scale)
        if done[k] is None:  # this step's copies do not take
            continue
        share = max(done[k])
        if first is None:
            first = (share, pp, scale)
        if near is None and share <= 1.0:
            near = (share, pp, scale)
        if share <= _budget.MARGIN:
            best = (share, pp, scale)
            break
        if i == 0 and len(_budget.LADDER) > 1:  # the gentlest step: can any step bring copies within?
            gp, gs = step(*_budget.LADDER[-1])
            gk = (gp.get("n_robust"), gs)
            done[gk] = trials(gp, gs)
            gentlest = None if done[gk] is None else min(done[gk])
            if gentlest is not None and gentlest > _budget.HOPELESS:
                remake = False
                break
    # no step fits the margin: the first whose trials are within the budget itself; else the automatic
    # parameters, whose blind mark is the most robust (a weaker one would not buy invisibility);
    # setup['budget'] records the share
    best = best or near or first
    if best is None:  # no step takes: the automatic parameters, as before (issue reports what fails)
        return p, 1.0, None
    share, pp, scale = best
    rec = {"fits": bool(share <= 1.0), "worst_share": round(float(share), 4), "pattern_scale": scale,
           "trials": _budget.TRIALS}
    if "n_robust" in pp:
        rec["n_robust"] = int(pp["n_robust"])
    if gentlest is not None:
        rec["gentlest_share"] = round(float(gentlest), 4)
    if not remake:
        rec["remake"] = False
    return pp, scale, rec
