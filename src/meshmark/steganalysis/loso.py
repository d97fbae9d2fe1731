"""The headline protocol: leave one source out (docs/steganalysis.md §6).

Random cover-level splits (protocol.evaluate, the thesis' §8.2 protocol) put meshes of one collection
on both sides, so a detector can learn what a collection looks like rather than what a mark does. Here
each source (sources.source_of: the collection a file was taken from) is held out in turn: every
detector is trained on the covers of the other sources and their stego versions and tested on the
held-out source's covers and stego versions. The universal detector is trained on every stego version
(protocol.UNIVERSAL "all"); its operating point is calibrated on the training side only, by an inner
cross-validation grouped by source (at most ``fpr`` of the out-of-fold covers called marked).

Rows per held-out source (``detector``):
  ``universal``           thesis-style test (each cover + one random stego version) at 0.5;
  ``universal@fpr``       the same at the calibrated threshold;
  ``detects:<method>``    share of the source's <method> stego meshes the universal detector calls marked
                          at the calibrated threshold (``fpr`` = that of the source's covers);
  ``specific:<method>``   the specific detector (covers vs <method>) at 0.5.
"""
from __future__ import annotations

import numpy as np

from .._core import MeshError
from . import classifiers as clf
from .protocol import _rates, dataset_features, one_thread
from .sources import source_of


def cover_sources(ds) -> np.ndarray:
    """The source of every cover of a dataset (protocol.build_dataset), from its path."""
    return np.array([source_of(p) for p in ds["path"]], dtype=object)


def calibrated_threshold(X, y, groups, fpr, classifier, params, n_folds=5, seed=0):
    """Smallest threshold t (decision p > t) whose out-of-fold cover FPR is <= fpr, folds grouped by
    ``groups``; also the out-of-fold rates at t."""
    ug = np.array(sorted(set(groups)))
    k = max(2, min(n_folds, len(ug)))
    fold_of = dict(zip(ug, np.random.default_rng(seed).permutation(len(ug)) % k))
    fold = np.array([fold_of[g] for g in groups])
    p = np.full(len(y), np.nan)
    for f in range(k):
        tr, te = fold != f, fold == f
        if not te.any() or y[tr].all() or not y[tr].any():
            continue
        p[te] = clf.fit(clf.make(classifier, **params), X[tr], y[tr]).predict_proba(X[te])
    ok = ~np.isnan(p)
    c = ok & ~y
    if not c.any() or not (ok & y).any():
        return 0.5, float("nan"), float("nan")
    grid = np.unique(np.r_[p[ok], 0.0, 1.0])
    t = next((t for t in grid if (p[c] > t).mean() <= fpr), 1.0)
    return float(t), float((p[c] > t).mean()), float((p[ok & y] > t).mean())


def evaluate_by_source(ds, feature_set: str, classifier: str = "ensemble", fpr: float = 0.05, seed: int = 0,
                       methods=None, sources=None, **params) -> list[dict]:
    """One row per (held-out source, detector); see the module docstring. ``sources``: per-cover source
    labels (default cover_sources(ds)). MeshError with fewer than two sources."""
    with one_thread():
        return _evaluate(ds, feature_set, classifier, fpr, seed, methods, sources, **params)


def _evaluate(ds, feature_set, classifier, fpr, seed, methods, sources, **params):
    X = dataset_features(ds, feature_set)
    meth, cov = ds["method"], ds["cover"]
    src = cover_sources(ds) if sources is None else np.asarray(sources, dtype=object)
    names = sorted(set(src))
    if len(names) < 2:
        raise MeshError(f"leave-one-source-out needs at least two sources, got {names}")
    methods = sorted({m for m in meth if m != "cover"}) if methods is None else list(methods)
    row_src = src[cov]
    y = meth != "cover"
    rows = []
    for k, s in enumerate(names):
        tr, te = row_src != s, row_src == s
        n_cov = int((te & ~y).sum())
        base = {"source": s, "n_covers": n_cov}
        if y[tr].all() or not y[tr].any():
            continue
        t, oof_fpr, oof_tpr = calibrated_threshold(X[tr], y[tr], row_src[tr], fpr, classifier, params, seed=seed)
        uni = clf.fit(clf.make(classifier, **params), X[tr], y[tr])
        p = uni.predict_proba(X[te])
        yt, mt, ct = y[te], meth[te], cov[te]
        rng = np.random.default_rng([seed, k])
        pick = []  # thesis-style test side: every cover + one random stego version of it
        for c in np.unique(ct):
            idx = np.flatnonzero(ct == c)
            pick += list(idx[~yt[idx]])
            st = idx[yt[idx]]
            if len(st):
                pick.append(int(rng.choice(st)))
        pick = np.array(pick, int)
        rows.append({**base, "detector": "universal", "threshold": 0.5, **_rates(yt[pick], p[pick] > 0.5),
                     "n_test": len(pick)})
        rows.append({**base, "detector": "universal@fpr", "threshold": t, **_rates(yt[pick], p[pick] > t),
                     "n_test": len(pick), "oof_fpr": oof_fpr, "oof_tpr": oof_tpr})
        cover_fpr = float((p[~yt] > t).mean()) if (~yt).any() else float("nan")
        for m in methods:
            sel = mt == m
            if sel.any():
                rows.append({**base, "detector": f"detects:{m}", "threshold": t, "accuracy": float("nan"),
                             "tpr": float((p[sel] > t).mean()), "fpr": cover_fpr, "pe": float("nan"),
                             "n_test": int(sel.sum())})
            a = tr & ((meth == "cover") | (meth == m))
            b = te & ((meth == "cover") | (meth == m))
            if not (y[a].any() and (~y[a]).any() and (y[b]).any()):
                continue
            det = clf.fit(clf.make(classifier, **params), X[a], y[a])
            rows.append({**base, "detector": f"specific:{m}", "threshold": 0.5,
                         **_rates(y[b], det.predict_proba(X[b]) > 0.5), "n_test": int(b.sum())})
    return rows


def source_table(rows) -> list[dict]:
    """Per source: universal accuracy (0.5 and calibrated), cover FPR and TPR at the calibrated threshold,
    and the accuracy of every specific detector; plus an 'all' row of cover-weighted means."""
    out = []
    for s in sorted({r["source"] for r in rows}):
        rs = {r["detector"]: r for r in rows if r["source"] == s}
        if "universal" not in rs:
            continue
        d = {"source": s, "n_covers": rs["universal"]["n_covers"], "universal": rs["universal"]["accuracy"],
             "universal@fpr": rs["universal@fpr"]["accuracy"], "fpr": rs["universal@fpr"]["fpr"],
             "tpr": rs["universal@fpr"]["tpr"], "threshold": rs["universal@fpr"]["threshold"]}
        for k, r in rs.items():
            if k.startswith("specific:"):
                d[k] = r["accuracy"]
            elif k.startswith("detects:"):
                d[k] = r["tpr"]
        out.append(d)
    if out:
        w = np.array([d["n_covers"] for d in out], float)
        keys = sorted({k for d in out for k in d if k not in ("source", "n_covers")})
        tot = {"source": "all (cover-weighted)", "n_covers": int(w.sum())}
        for k in keys:
            v = np.array([d.get(k, np.nan) for d in out], float)
            ok = ~np.isnan(v)
            tot[k] = float((v[ok] * w[ok]).sum() / w[ok].sum()) if ok.any() else float("nan")
        out.append(tot)
    return out
