"""Steganalysis models: a universal detector plus one specific detector per stego method, saved with
versioned metadata (docs/steganalysis.md §4).

File format (``.npz``, read with ``allow_pickle=False``): ``meta`` is a UTF-8 JSON document
``{"format": "meshmark-steganalysis-model", "format_version": 2, "feature_set", "n_features",
"classifier", "detectors": {name: {"kind", "params", "method"}}, "training": {"corpus_hash",
"n_covers", "n_stego", "methods", ...}, "meshmark_version"}``; every other entry is an array named
``<detector>/<array>``. The universal detector is called ``universal``; the specific ones ``specific:<method>``.

Format version 3 (features version 3: the stabilised sets, docs/steganalysis.md §2) adds ``"features_version"``
and the optional domain check ``"domain"`` = ``{"k", "threshold", "rate", ...}`` with arrays ``domain/centre``,
``domain/scale`` and ``domain/ref`` (the training covers, robustly standardised, float32): a mesh whose mean
distance to its ``k`` nearest training covers (standardised units / sqrt(d)) exceeds ``threshold`` is
reported ``verdict: "cannot judge"`` (the threshold is calibrated so that ``rate`` of the training covers,
each measured against the covers of the other groups, are beyond it). Every result carries ``verdict``
in {"marked", "no evidence", "cannot judge"} and ``reason`` (None for a verdict; why not otherwise; a
mesh too small for the features is "cannot judge").

Optional (files without them behave as before): ``"threshold"`` — the
universal decision is ``P(stego) > threshold`` (default 0.5); ``"guard"`` = ``{"max_outside", "margin",
...}`` with arrays ``guard/lo`` and ``guard/hi`` — the out-of-distribution guard: a mesh with more than
``max_outside`` of its features outside ``[lo - margin (hi - lo), hi + margin (hi - lo)]`` (the range
of the training rows) is reported ``in_distribution: false`` and ``marked: false`` with a warning
(docs/steganalysis.md, "Default model on unseen meshes").
"""
from __future__ import annotations

import hashlib
import io
import json
import pathlib

import numpy as np

from .._core import MeshError
from . import classifiers as clf
from .features import FEATURES_VERSION, feature_length, features as compute_features

FORMAT = "meshmark-steganalysis-model"
FORMAT_VERSION = 3  # 3: the stabilised feature sets (features version 3); 2: the 1e-7 log floor; older files read features that no longer exist
VERDICTS = ("marked", "no evidence", "cannot judge")
DEFAULT_MODEL = pathlib.Path(__file__).with_name("default_model.npz")


class Model:
    def __init__(self, feature_set: str, classifier: str, detectors: dict, methods: dict, training: dict,
                 threshold: float = 0.5, guard: dict | None = None, domain: dict | None = None):
        self.threshold = float(threshold)
        self.domain = domain  # None or {"centre", "scale", "ref" (arrays), "k", "threshold", "rate", ...}
        self.guard = guard  # None or {"lo", "hi" (arrays), "max_outside", "margin", ...}
        self.feature_set = feature_set
        self.classifier = classifier
        self.detectors = detectors  # name -> fitted classifier
        self.methods = methods      # name -> stego method (None for universal)
        self.training = training

    # --- training ---------------------------------------------------------------------------
    @classmethod
    def train(cls, X, y, method_labels, feature_set: str, classifier: str = "ensemble",
              training: dict | None = None, **params) -> "Model":
        """Fit the universal detector on all of (X, y) and one specific detector per method on the
        covers plus that method's stego meshes. ``method_labels`` names the method of each stego row
        (ignored for covers). MeshError for an empty set or a single class."""
        X = np.asarray(X, float)
        y = np.asarray(y, int)
        if X.ndim != 2 or len(X) == 0:
            raise MeshError("empty training corpus: no feature vectors")
        if X.shape[1] != feature_length(feature_set):
            raise MeshError(f"features have {X.shape[1]} columns, the {feature_set} set has {feature_length(feature_set)}")
        labels = np.asarray(method_labels, dtype=object)
        dets, methods = {}, {}
        dets["universal"] = clf.make(classifier, **params).fit(X, y)
        methods["universal"] = None
        for m in sorted({str(l) for l, t in zip(labels, y) if t == 1}):
            sel = (y == 0) | (labels == m)
            dets[f"specific:{m}"] = clf.make(classifier, **params).fit(X[sel], y[sel])
            methods[f"specific:{m}"] = m
        return cls(feature_set, classifier, dets, methods, dict(training or {}))

    def set_guard(self, X, margin: float, max_outside: float, **info) -> None:
        """The out-of-distribution guard from training rows X: their per-feature range, widened by
        ``margin`` of its span on each side; more than ``max_outside`` of the features outside it means
        the model cannot judge the mesh."""
        X = np.asarray(X, float)
        self.guard = {"lo": X.min(0), "hi": X.max(0), "margin": float(margin), "max_outside": float(max_outside),
                      **info}

    # --- domain check ------------------------------------------------------------------------
    @staticmethod
    def _standardise(X, centre, scale):
        return np.clip((np.asarray(X, float) - centre) / scale, -50, 50)

    @staticmethod
    def _knn_distance(Z, ref, k, exclude=None):
        """Mean Euclidean distance / sqrt(d) of each row of Z to its k nearest rows of ref (rows of ref with
        exclude[i, j] True are not neighbours of Z[i])."""
        Z, ref = np.atleast_2d(Z).astype(float), np.asarray(ref, float)
        d2 = (Z ** 2).sum(1)[:, None] + (ref ** 2).sum(1)[None, :] - 2 * Z @ ref.T
        d2 = np.maximum(d2, 0)
        if exclude is not None:
            d2 = np.where(exclude, np.inf, d2)
        kk = min(k, ref.shape[0])
        part = np.sort(d2, axis=1)[:, :kk]
        return np.sqrt(part).mean(1) / np.sqrt(Z.shape[1])

    def set_domain(self, X_covers, groups, rate: float = 0.05, k: int = 3, **info) -> dict:
        """The domain check from the training covers X_covers (rows) and their groups (a source, or a file
        with its variants): robust standardisation (median, IQR), reference = the standardised covers;
        threshold = the (1 - rate) quantile of each cover's distance to the covers of the other groups."""
        X = np.asarray(X_covers, float)
        g = np.asarray(groups, dtype=object)
        centre = np.median(X, 0)
        q1, q3 = np.percentile(X, [25, 75], axis=0)
        scale = q3 - q1
        scale = np.where(scale > 0, scale, np.where(np.abs(centre) > 0, np.abs(centre), 1.0))
        Z = self._standardise(X, centre, scale)
        d = self._knn_distance(Z, Z, k, exclude=g[:, None] == g[None, :])
        t = float(np.quantile(d[np.isfinite(d)], 1 - rate))
        self.domain = {"centre": centre, "scale": scale, "ref": Z.astype(np.float32), "k": int(k), "threshold": t,
                       "rate": float(rate), "n_ref": int(len(Z)), **info}
        return {"threshold": t, "flagged": float((d > t).mean())}

    def domain_distance(self, F) -> np.ndarray:
        """Per row of F: the domain check's distance (0 without a domain)."""
        F = np.atleast_2d(np.asarray(F, float))
        if not self.domain:
            return np.zeros(len(F))
        d = self.domain
        return self._knn_distance(self._standardise(F, d["centre"], d["scale"]), d["ref"], d["k"])

    def outside_fraction(self, F) -> np.ndarray:
        """Per row of F: the fraction of features outside the guard's widened training range (0 without a guard)."""
        F = np.atleast_2d(np.asarray(F, float))
        if not self.guard:
            return np.zeros(len(F))
        lo, hi, m = self.guard["lo"], self.guard["hi"], self.guard["margin"]
        w = m * (hi - lo)
        return ((F < lo - w) | (F > hi + w)).mean(axis=1)

    # --- use ----------------------------------------------------------------------------------
    def detect_features(self, F, guard: bool = True) -> dict:
        """Universal decision (``P > threshold`` and, with the guard, in distribution), its probability,
        one probability per method. ``guard=False`` ignores the out-of-distribution guard."""
        F = np.asarray(F, float).reshape(1, -1)
        if F.shape[1] != feature_length(self.feature_set):
            raise MeshError(f"feature vector has {F.shape[1]} components, the model needs {self.feature_set}")
        p = float(self.detectors["universal"].predict_proba(F)[0])
        per = {self.methods[k]: float(d.predict_proba(F)[0]) for k, d in self.detectors.items() if k != "universal"}
        out = {"marked": p > self.threshold, "probability": p, "threshold": self.threshold, "methods": per,
               "feature_set": self.feature_set, "classifier": self.classifier, "reason": None}
        cal = self.training.get("calibration") if isinstance(self.training, dict) else None
        if cal and "oof_fpr" in cal:  # how much a verdict of this model is worth (cross-validated on its covers)
            out["operating_point"] = {"cv_fpr": cal["oof_fpr"], "cv_tpr": cal["oof_tpr"]}
        if self.guard:
            frac = float(self.outside_fraction(F)[0])
            out["in_distribution"] = frac <= self.guard["max_outside"]
            out["outside_fraction"] = frac
            if not out["in_distribution"]:
                out["warning"] = (f"{100 * frac:.0f} % of the features lie outside the range of this model's training "
                                  f"meshes: the detector cannot judge this kind of mesh (reported not marked); "
                                  f"train a model on covers like it (meshmark steganalysis train)")
                if guard:
                    out["marked"] = False
                    out["reason"] = out["warning"]
        if self.domain:
            dist = float(self.domain_distance(F)[0])
            out["domain_distance"], out["domain_threshold"] = dist, self.domain["threshold"]
            out["in_domain"] = dist <= self.domain["threshold"]
            if not out["in_domain"] and guard:
                out["marked"] = False
                out["reason"] = (f"the mesh lies outside this model's training covers (distance {dist:.2f} > "
                                 f"{self.domain['threshold']:.2f}, a distance only {100 * self.domain['rate']:.0f} % of "
                                 f"held-out training covers exceed): the detector cannot judge it; train a model on "
                                 f"covers like it (meshmark steganalysis train)")
        out["verdict"] = "cannot judge" if out["reason"] else ("marked" if out["marked"] else "no evidence")
        return out

    def detect(self, mesh) -> dict:
        """detect_features of the mesh's features; a mesh too small for the features is "cannot judge"."""
        try:
            F = compute_features(mesh, self.feature_set)
        except MeshError as exc:
            if "too small" not in str(exc):
                raise
            return {"verdict": "cannot judge", "reason": str(exc), "marked": False, "probability": None,
                    "threshold": self.threshold, "methods": {}, "feature_set": self.feature_set,
                    "classifier": self.classifier}
        return self.detect_features(F)

    # --- files --------------------------------------------------------------------------------
    def save(self, path, overwrite: bool = False) -> None:
        """Write the model (.npz) atomically; an existing file is replaced only with ``overwrite=True``."""
        from .. import __version__
        from ..atomic import write_bytes
        meta = {"format": FORMAT, "format_version": FORMAT_VERSION, "feature_set": self.feature_set,
                "n_features": feature_length(self.feature_set), "classifier": self.classifier,
                "detectors": {k: {"kind": d.kind, "params": d.params(), "method": self.methods[k]}
                              for k, d in self.detectors.items()},
                "training": self.training, "meshmark_version": __version__, "threshold": self.threshold,
                "features_version": FEATURES_VERSION}
        arrays = {}
        if self.guard:
            meta["guard"] = {k: v for k, v in self.guard.items() if k not in ("lo", "hi")}
            arrays.update({"guard/lo": np.asarray(self.guard["lo"]), "guard/hi": np.asarray(self.guard["hi"])})
        if self.domain:
            meta["domain"] = {k: v for k, v in self.domain.items() if k not in ("centre", "scale", "ref")}
            arrays.update({f"domain/{k}": np.asarray(self.domain[k]) for k in ("centre", "scale", "ref")})
        arrays["meta"] = np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)
        for k, d in self.detectors.items():
            for a, v in d.arrays().items():
                arrays[f"{k}/{a}"] = np.asarray(v)
        buf = io.BytesIO()
        np.savez_compressed(buf, **arrays)
        write_bytes(path, buf.getvalue(), what="model", overwrite=overwrite)  # a failed save leaves no file

    @classmethod
    def load(cls, path=None) -> "Model":
        path = pathlib.Path(path) if path is not None else DEFAULT_MODEL
        try:
            z = np.load(path, allow_pickle=False)
            meta = json.loads(bytes(z["meta"]).decode())
        except FileNotFoundError:
            raise MeshError(f"model file {path} does not exist") from None
        except Exception as exc:  # not an npz, or no meta
            raise MeshError(f"{path} is not a meshmark steganalysis model ({exc})") from None
        if meta.get("format") != FORMAT:
            raise MeshError(f"{path} is not a meshmark steganalysis model (format {meta.get('format')!r})")
        if meta.get("format_version") != FORMAT_VERSION:
            raise MeshError(f"model file {path} has format version {meta.get('format_version')}; this meshmark "
                            f"reads version {FORMAT_VERSION}: retrain it with `meshmark steganalysis train`")
        fs = meta["feature_set"]
        if feature_length(fs) != meta.get("n_features"):
            raise MeshError(f"model file {path}: feature set {fs} has {feature_length(fs)} features here, "
                            f"{meta.get('n_features')} in the model")
        dets, methods = {}, {}
        for k, d in meta["detectors"].items():
            a = {name.split("/", 1)[1]: z[name] for name in z.files if name.startswith(k + "/")}
            dets[k] = clf.CLASSIFIERS[d["kind"]].from_arrays(d["params"], a)
            methods[k] = d["method"]
        if meta.get("features_version", FEATURES_VERSION) != FEATURES_VERSION:
            raise MeshError(f"model file {path} was trained on features version {meta.get('features_version')}; this "
                            f"meshmark computes version {FEATURES_VERSION}: retrain it with `meshmark steganalysis train`")
        domain = None
        if "domain" in meta:
            domain = {**meta["domain"], **{k: z[f"domain/{k}"] for k in ("centre", "scale", "ref")}}
            if domain["centre"].shape != (feature_length(fs),):
                raise MeshError(f"model file {path}: the domain check has {domain['centre'].size} features, {fs} has {feature_length(fs)}")
        guard = None
        if "guard" in meta:
            guard = {**meta["guard"], "lo": z["guard/lo"], "hi": z["guard/hi"]}
            if guard["lo"].shape != (feature_length(fs),):
                raise MeshError(f"model file {path}: the guard has {guard['lo'].size} features, {fs} has {feature_length(fs)}")
        return cls(fs, meta["classifier"], dets, methods, meta.get("training", {}),
                   threshold=float(meta.get("threshold", 0.5)), guard=guard, domain=domain)


def corpus_hash(paths) -> str:
    """sha256 over the sorted (file name, sha256 of its bytes) of the training covers."""
    h = hashlib.sha256()
    for p in sorted(pathlib.Path(p) for p in paths):
        h.update(p.name.encode() + b"\0" + hashlib.sha256(p.read_bytes()).hexdigest().encode() + b"\n")
    return h.hexdigest()
