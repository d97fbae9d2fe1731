"""The ch. 8 protocol: a dataset of cover and stego meshes, random cover-level splits, specific and
universal detectors, P_E per split and median, accuracy against PCA components (docs/steganalysis.md §6).

Stego methods are a registry, :data:`STEGO_METHODS`: ``name -> embed(mesh, rng) -> V'`` (marked
positions, one row per input vertex; raise MeshError if the mesh cannot carry the mark). Register
more with :func:`register_stego_method` (LSB and Chao plug in here with one line each).
"""
from __future__ import annotations

import math
import pathlib
import time

import numpy as np

from .._core import MeshError
from . import classifiers as clf
from .features import features as compute_features

STEGO_METHODS: dict = {}


def register_stego_method(name: str, embed, strength: str = "") -> None:
    """``embed(mesh: Mesh, rng: numpy Generator) -> (n, 3) marked vertices``."""
    STEGO_METHODS[name] = (embed, strength)


def _bits(rng, n=64):
    return rng.integers(0, 2, n)


def _cho(kind, lo, hi):
    def embed(mesh, rng):
        from ..watermark import cho
        alpha = float(rng.uniform(lo, hi))  # §8.2: alpha random in the range
        V, info = cho.embed_bits(mesh.V, mesh, _bits(rng), method=kind, alpha=alpha, delta_k=0.001)
        if info["failed_bins"]:
            raise MeshError(f"Cho {kind}: {len(info['failed_bins'])} bins failed")
        return V
    return embed


def _fitting(embed, n):
    """embed(n bits) with n reduced to what the framework's coding says fits ("at most N payload bits fit":
    the capacity counts carriers before the check bits and the convolutional code)."""
    import re
    try:
        return embed(n)
    except MeshError as exc:
        m = re.search(r"at most (\d+) payload bits fit", str(exc))
        if not m or not 0 < int(m.group(1)) < n:
            raise
        return embed(int(m.group(1)))


def _laplacian(thesis_exact):
    def embed(mesh, rng):
        from ..watermark import laplacian
        kw = dict(n_thr=46, n_robust=5, K=math.ceil(int(mesh.referenced().sum()) / 70)) if thesis_exact else {}
        cap = laplacian.capacity(mesh.V, mesh, thesis_exact=thesis_exact, **kw)
        if cap < 17:
            raise MeshError(f"laplacian: only {cap} carrier bits")
        bits = _bits(rng, min(32, cap - 16)).astype(np.uint8)  # the rest of the carriers: repetition
        key = f"k{rng.integers(1 << 30)}"
        return _fitting(lambda n: laplacian.embed(mesh.V, mesh, payload=bits[:n], key=key, thesis_exact=thesis_exact,
                                                  **kw).V, len(bits))
    return embed


def _framework(method):
    def embed(mesh, rng):
        from ..watermark import framework
        cap = framework.capacity(mesh.V, mesh, method=method)
        bits = _bits(rng, max(1, min(32, cap - 16))).astype(np.uint8)
        key = f"k{rng.integers(1 << 30)}"
        return _fitting(lambda n: framework.embed(mesh.V, mesh, payload=bits[:n], key=key, method=method).V, len(bits))
    return embed


def _radial(mesh, rng):
    from ..watermark import radial
    return radial.embed_bits(mesh.V, mesh, _bits(rng), K=400)[0]


# §8.2 strengths (thesis) ...
register_stego_method("cho-mean", _cho("mean", 0.02, 0.06), "alpha U[0.02, 0.06], 64 bins, delta_k 0.001")
register_stego_method("cho-variance", _cho("variance", 0.12, 0.20), "alpha U[0.12, 0.20], 64 bins, delta_k 0.001")
register_stego_method("laplacian-thesis", _laplacian(True), "n_thr 46, n_robust 5, K = ceil(V/70), thesis_exact")
register_stego_method("radial", _radial, "Yang ch. 6, K 400, 64 bits")
# ... and meshmark's own defaults (framework, key, full-capacity repetition coding)
register_stego_method("laplacian", _laplacian(False), "meshmark defaults")
register_stego_method("cho-mean:meshmark", _framework("cho-mean"), "meshmark defaults")
register_stego_method("cho-variance:meshmark", _framework("cho-variance"), "meshmark defaults")


# LSB (§4.3.2) at eps = 1, 2, 5 degrees and Chao (n_layers 10, n_intervals 10000), both at full load,
# from meshmark.stego (the `stego` branch; written against its API as merged on main: lsb
# embed(mesh, message, key, tolerance) fills the carrier with the sealed frame plus random bytes,
# chao.embed(mesh, bits, fill=True, seed) pads with random bits). Not run on this branch, where
# meshmark.stego does not exist yet.
def _register_stego_module(register=None) -> bool:
    register = register or register_stego_method
    try:
        from .. import stego
    except ImportError:
        return False

    def lsb(tol):
        def embed(mesh, rng):
            return stego.embed(mesh, b"", key=f"k{int(rng.integers(1 << 30))}", tolerance=tol).V
        return embed

    for tol in (1, 2, 5):
        register(f"lsb-{tol}deg", lsb(float(tol)), f"§4.3.2, eps {tol} deg, full capacity")
    register("chao", lambda mesh, rng: stego.chao.embed(mesh, np.zeros(0, np.uint8), fill=True,
                                                        seed=int(rng.integers(1 << 31))).V,
             "n_layers 10, n_intervals 10000, full capacity")
    return True


_register_stego_module()

SUFFIXES = {".obj", ".off", ".ply", ".stl"}


def mesh_files(folders) -> list[pathlib.Path]:
    out = []
    for f in folders:
        f = pathlib.Path(f)
        if f.is_file():
            out.append(f)
        elif f.is_dir():
            out += sorted(p for p in f.rglob("*") if p.is_file() and p.suffix.lower() in SUFFIXES)
        else:
            raise MeshError(f"no such file or folder: {f}")
    return out


def build_dataset(paths, methods=None, feature_sets=("yang208",), seed: int = 0, log=None) -> dict:
    """Features of every cover and of one stego version per (cover, method).

    ``paths``: mesh files, or ``(name, Mesh)`` pairs for meshes made in memory (augmented covers).
    Returns ``{"cover": (N,) int cover index, "method": (N,) str ("cover" or method), "path": list of
    cover paths, "X": {set: (N, d)}, "failed": [(path, method, reason)]}``. Covers that cannot be read
    or are too small for the features are skipped (listed in failed)."""
    from ..io import read_mesh
    methods = list(STEGO_METHODS) if methods is None else list(methods)
    for m in methods:
        if m not in STEGO_METHODS:
            raise MeshError(f"unknown stego method {m!r}; registered: {', '.join(STEGO_METHODS)}")
    rows_c, rows_m, X, failed, kept = [], [], {s: [] for s in feature_sets}, [], []
    t0 = time.perf_counter()
    for i, p in enumerate(paths):
        try:
            p, mesh = p if isinstance(p, tuple) else (p, read_mesh(p))
            fc = {s: compute_features(mesh, s) for s in feature_sets}
        except MeshError as exc:
            failed.append((str(p), "cover", str(exc)))
            continue
        ci = len(kept)
        kept.append(str(p))
        rows_c.append(ci)
        rows_m.append("cover")
        for s in feature_sets:
            X[s].append(fc[s])
        for j, m in enumerate(methods):
            rng = np.random.default_rng([seed, i, j])
            try:
                Vm = np.asarray(STEGO_METHODS[m][0](mesh, rng))
                marked = mesh.with_vertices(Vm)
                fm = {s: compute_features(marked, s) for s in feature_sets}
            except MeshError as exc:
                failed.append((str(p), m, str(exc)))
                continue
            rows_c.append(ci)
            rows_m.append(m)
            for s in feature_sets:
                X[s].append(fm[s])
        if log:
            log(f"[{i + 1}/{len(paths)}] {pathlib.Path(p).name} {time.perf_counter() - t0:.0f} s")
    if not kept:
        why = f"; first: {failed[0][0]}: {failed[0][2]}" if failed else ""
        raise MeshError(f"empty training corpus: none of the {len(paths)} meshes could be read and featurised{why}")
    return {"cover": np.array(rows_c, int), "method": np.array(rows_m, dtype=object), "path": kept,
            "X": {s: np.array(v, float).reshape(len(rows_c), -1) for s, v in X.items()}, "failed": failed}


def dataset_key(paths, methods, feature_sets, seed: int = 0) -> str:
    """What a cached dataset was built from: sha256 over the covers (file name and sha256 of its bytes, in
    order), the stego methods (None: every registered one, listed), the feature sets, the seed and
    features.FEATURES_VERSION. load_dataset refuses a cache whose key differs (issue 23)."""
    import hashlib
    import json
    from .features import FEATURES_VERSION
    h = hashlib.sha256()
    for p in paths:
        p = pathlib.Path(p)
        h.update(p.name.encode() + b"\0" + hashlib.sha256(p.read_bytes()).hexdigest().encode() + b"\n")
    ms = list(STEGO_METHODS) if methods is None else list(methods)
    h.update(json.dumps({"methods": ms, "sets": list(feature_sets), "seed": int(seed),
                         "features_version": FEATURES_VERSION}).encode())
    return h.hexdigest()


def save_dataset(ds, path, key: str | None = None):
    from .features import FEATURES_VERSION
    arrays = {"cover": ds["cover"], "method": ds["method"].astype(str), "path": np.array(ds["path"], dtype=str),
              "features_version": np.array(FEATURES_VERSION)}
    if key:
        arrays["key"] = np.array(key)
    for s, v in ds["X"].items():
        arrays["X_" + s] = v
    np.savez_compressed(path, **arrays)


def load_dataset(path, expect_key: str | None = None) -> dict:
    """A dataset saved by save_dataset. With ``expect_key`` (dataset_key of what the caller would build),
    MeshError unless the file was built for exactly those covers, methods, sets and features version."""
    from .features import FEATURES_VERSION
    try:
        z = np.load(path, allow_pickle=False)
        files = set(z.files)
    except Exception as exc:
        raise MeshError(f"{path} is not a steganalysis dataset ({exc})") from None
    if not {"cover", "method", "path"} <= files:
        raise MeshError(f"{path} is not a steganalysis dataset (no cover/method/path arrays)")
    fv = int(z["features_version"]) if "features_version" in files else 2
    if fv != FEATURES_VERSION:
        raise MeshError(f"dataset {path} holds features of version {fv}; this meshmark computes version "
                        f"{FEATURES_VERSION}: delete it (or name another --dataset) to rebuild")
    if expect_key is not None and ("key" not in files or str(z["key"]) != expect_key):
        raise MeshError(f"dataset {path} was built for other covers, stego methods or feature sets: delete it "
                        f"(or name another --dataset) to rebuild it for these")
    return {"cover": z["cover"], "method": z["method"].astype(object), "path": list(z["path"]),
            "X": {k[2:]: z[k] for k in z.files if k.startswith("X_")}, "failed": []}


def subset(ds, contains: str) -> dict:
    """The covers whose path contains ``contains`` (e.g. ``"psb-seg"``), with their stego rows."""
    keep = np.array([contains in p for p in ds["path"]])
    if keep.sum() == 0:
        raise MeshError(f"no cover path contains {contains!r}")
    rows = keep[ds["cover"]]
    remap = -np.ones(len(keep), int)
    remap[keep] = np.arange(int(keep.sum()))
    return {"cover": remap[ds["cover"][rows]], "method": ds["method"][rows],
            "path": [p for p, k in zip(ds["path"], keep) if k], "X": {k: v[rows] for k, v in ds["X"].items()},
            "failed": []}


def splits(n_covers: int, n_splits: int = 30, test_fraction: float = 0.3, seed: int = 0):
    """Random cover-level splits: a cover and all its stego versions are on the same side."""
    rng = np.random.default_rng(seed)
    n_test = max(1, int(round(n_covers * test_fraction)))
    for _ in range(n_splits):
        perm = rng.permutation(n_covers)
        test = np.zeros(n_covers, bool)
        test[perm[:n_test]] = True
        yield ~test, test


def _rates(y, pred):
    y, pred = np.asarray(y, bool), np.asarray(pred, bool)
    tpr = float(pred[y].mean()) if y.any() else float("nan")
    fpr = float(pred[~y].mean()) if (~y).any() else float("nan")
    return {"accuracy": float((y == pred).mean()), "tpr": tpr, "fpr": fpr, "pe": 0.5 * (fpr + 1 - tpr)}


def _pick_universal(ds, covers_mask, rng):
    """Covers in the mask plus one stego version per cover of a randomly chosen method (§8.2.2)."""
    rows = []
    for c in np.flatnonzero(covers_mask):
        idx = np.flatnonzero(ds["cover"] == c)
        cov = idx[ds["method"][idx] == "cover"]
        st = idx[ds["method"][idx] != "cover"]
        rows += list(cov)
        if len(st):
            rows.append(int(rng.choice(st)))
    return np.array(rows, int)


def one_thread():
    """BLAS on one thread: the classifiers work on small matrices, where OpenBLAS threads on a shared
    machine cost 5-40x (measured: 34 s vs 6.7 s for 5 QDA splits)."""
    from threadpoolctl import threadpool_limits
    return threadpool_limits(1)


#: How the universal detector is trained (its test side is always §8.2.2's: every test cover plus one stego
#: version of a randomly chosen method). "pick": the thesis, one random stego version per training cover;
#: "all": every stego version of every training cover (the FLD ensemble's threshold minimises the balanced
#: P_E, so the 10:1 class ratio does not shift it); "stack": a class-balanced logistic regression (C by
#: cover-grouped CV) on the specific detectors' probabilities, learned on every training row with
#: out-of-fold probabilities (the specific detectors retrained on 2/3 of the training covers, 3 folds),
#: applied at test to the probabilities of the specific detectors trained on all training covers;
#: "max-specific": no universal model, the largest
#: probability of the specific detectors (each trained on the same training covers).
UNIVERSAL = ("pick", "all", "max-specific", "stack")


def evaluate(ds, feature_set: str, classifier: str = "ensemble", n_splits: int = 30, test_fraction: float = 0.3,
             seed: int = 0, methods=None, universal: str = "pick", **params) -> list[dict]:
    """Run the split protocol: one row per (split, detector) with accuracy, TPR, FPR and P_E on the
    test side. Detectors: ``specific:<method>`` for each method, and ``universal`` (trained as
    ``universal`` says: :data:`UNIVERSAL`)."""
    if universal not in UNIVERSAL:
        raise MeshError(f"universal must be one of {', '.join(UNIVERSAL)}, got {universal!r}")
    with one_thread():
        return _evaluate(ds, feature_set, classifier, n_splits, test_fraction, seed, methods, universal, **params)


def dataset_features(ds, feature_set: str) -> np.ndarray:
    """The (N, d) features of ``feature_set`` (a '+' combination is the columns side by side)."""
    parts = feature_set.split("+")
    for p in parts:
        if p not in ds["X"]:
            raise MeshError(f"the dataset has no {p} features (it has {', '.join(ds['X'])})")
    return np.hstack([ds["X"][p] for p in parts])


def _evaluate(ds, feature_set, classifier, n_splits, test_fraction, seed, methods, universal="pick", **params):
    X = dataset_features(ds, feature_set)
    meth = ds["method"]
    n_cov = int(ds["cover"].max()) + 1 if len(ds["cover"]) else 0
    if n_cov < 4:
        raise MeshError(f"the split protocol needs at least 4 covers, got {n_cov}")
    if not 0 < test_fraction < 1 or n_splits < 1:
        raise MeshError(f"need 0 < test_fraction < 1 and n_splits >= 1, got {test_fraction} and {n_splits}")
    methods = sorted({m for m in meth if m != "cover"}) if methods is None else list(methods)
    rows = []
    for k, (tr, te) in enumerate(splits(n_cov, n_splits, test_fraction, seed)):
        trr, ter = tr[ds["cover"]], te[ds["cover"]]
        rng = np.random.default_rng([seed, k])
        a_u, b_u = _pick_universal(ds, tr, rng), _pick_universal(ds, te, rng)
        p_max = np.zeros(len(b_u))
        P_u = np.zeros((len(b_u), len(methods)))
        for m in methods:
            sel = (meth == "cover") | (meth == m)
            a, b = sel & trr, sel & ter
            model = clf.fit(clf.make(classifier, **params), X[a], meth[a] != "cover", ds["cover"][a])
            pred = model.predict_proba(X[b]) > 0.5
            rows.append({"split": k, "detector": f"specific:{m}", **_rates(meth[b] != "cover", pred),
                         "n_train": int(a.sum()), "n_test": int(b.sum())})
            if universal == "max-specific":
                p_max = np.maximum(p_max, model.predict_proba(X[b_u]))
            if universal == "stack":
                P_u[:, methods.index(m)] = model.predict_proba(X[b_u])
        if universal == "max-specific":
            pred, n_train = p_max > 0.5, int(trr.sum())
        elif universal == "stack":
            a = np.flatnonzero(trr)
            S = _stack_scores(ds, X, a, tr, methods, classifier, params, np.random.default_rng([seed, k, 7]))
            comb = clf.fit(clf.LogReg(), S, meth[a] != "cover", ds["cover"][a])
            pred, n_train = comb.predict_proba(P_u) > 0.5, int(len(a))
        else:
            a = np.flatnonzero(trr) if universal == "all" else a_u
            model = clf.fit(clf.make(classifier, **params), X[a], meth[a] != "cover", ds["cover"][a])
            pred, n_train = model.predict_proba(X[b_u]) > 0.5, int(len(a))
        rows.append({"split": k, "detector": "universal", **_rates(meth[b_u] != "cover", pred),
                     "n_train": n_train, "n_test": int(len(b_u))})
    return rows


def _stack_scores(ds, X, rows, tr, methods, classifier, params, rng, n_folds=3):
    """Out-of-fold probabilities of every specific detector for the training ``rows``: the training covers
    (mask ``tr``) fall in ``n_folds`` folds; each fold's rows are scored by specific detectors trained on the
    other folds' covers only (a cover and its stego versions stay together)."""
    meth, cov = ds["method"], ds["cover"]
    tr_cov = np.flatnonzero(tr)
    fold = np.empty(len(tr), int)
    fold[tr_cov] = rng.permutation(len(tr_cov)) % n_folds
    S = np.full((len(rows), len(methods)), 0.5)
    fr = fold[cov[rows]]
    for f in range(n_folds):
        inner = tr & (fold != f)
        held = rows[fr == f]
        for j, m in enumerate(methods):
            a = inner[cov] & ((meth == "cover") | (meth == m))
            y = meth[a] != "cover"
            if y.all() or not y.any():
                continue  # too few covers carry this method here: leave 1/2
            model = clf.fit(clf.make(classifier, **params), X[a], y, cov[a])
            S[fr == f, j] = model.predict_proba(X[held])
    return S


def median_table(rows) -> list[dict]:
    out = []
    for d in sorted({r["detector"] for r in rows}):
        rs = [r for r in rows if r["detector"] == d]
        out.append({"detector": d, "splits": len(rs),
                    **{f"median_{k}": float(np.median([r[k] for r in rs])) for k in ("accuracy", "tpr", "fpr", "pe")}})
    return out
