"""Steganalysis models: a universal detector plus one specific detector per stego method, saved with
versioned metadata (docs/steganalysis.md §4).

File format (``.npz``, read with ``allow_pickle=False``): ``meta`` is a UTF-8 JSON document
``{"format": "meshmark-steganalysis-model", "format_version": 2, "feature_set", "n_features",
"classifier", "detectors": {name: {"kind", "params", "method"}}, "training": {"corpus_hash",
"n_covers", "n_stego", "methods", ...}, "meshmark_version"}``; every other entry is an array named
``<detector>/<array>``. The universal detector is called ``universal``; the specific ones ``specific:<method>``.

Optional (format version 2 still; files without them behave as before): ``"threshold"`` — the
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
import os
import pathlib
import tempfile

import numpy as np

from .._core import MeshError
from . import classifiers as clf
from .features import feature_length, features as compute_features

FORMAT = "meshmark-steganalysis-model"
FORMAT_VERSION = 2  # 2: features with the 1e-7 log floor and the extended-precision frame (version-1 models read features that no longer exist)
DEFAULT_MODEL = pathlib.Path(__file__).with_name("default_model.npz")


class Model:
    def __init__(self, feature_set: str, classifier: str, detectors: dict, methods: dict, training: dict,
                 threshold: float = 0.5, guard: dict | None = None):
        self.threshold = float(threshold)
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
               "feature_set": self.feature_set, "classifier": self.classifier}
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
        return out

    def detect(self, mesh) -> dict:
        return self.detect_features(compute_features(mesh, self.feature_set))

    # --- files --------------------------------------------------------------------------------
    def save(self, path) -> None:
        from .. import __version__
        meta = {"format": FORMAT, "format_version": FORMAT_VERSION, "feature_set": self.feature_set,
                "n_features": feature_length(self.feature_set), "classifier": self.classifier,
                "detectors": {k: {"kind": d.kind, "params": d.params(), "method": self.methods[k]}
                              for k, d in self.detectors.items()},
                "training": self.training, "meshmark_version": __version__, "threshold": self.threshold}
        arrays = {"meta": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8)}
        if self.guard:
            meta["guard"] = {k: v for k, v in self.guard.items() if k not in ("lo", "hi")}
            arrays = {"meta": np.frombuffer(json.dumps(meta).encode(), dtype=np.uint8),
                      "guard/lo": np.asarray(self.guard["lo"]), "guard/hi": np.asarray(self.guard["hi"])}
        for k, d in self.detectors.items():
            for a, v in d.arrays().items():
                arrays[f"{k}/{a}"] = np.asarray(v)
        path = pathlib.Path(path)
        buf = io.BytesIO()
        np.savez_compressed(buf, **arrays)
        fd, tmp = tempfile.mkstemp(dir=path.parent if str(path.parent) else ".", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                f.write(buf.getvalue())
            os.replace(tmp, path)  # atomic: a failed save leaves no file
        except BaseException:
            if os.path.exists(tmp):
                os.unlink(tmp)
            raise

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
        guard = None
        if "guard" in meta:
            guard = {**meta["guard"], "lo": z["guard/lo"], "hi": z["guard/hi"]}
            if guard["lo"].shape != (feature_length(fs),):
                raise MeshError(f"model file {path}: the guard has {guard['lo'].size} features, {fs} has {feature_length(fs)}")
        return cls(fs, meta["classifier"], dets, methods, meta.get("training", {}),
                   threshold=float(meta.get("threshold", 0.5)), guard=guard)


def corpus_hash(paths) -> str:
    """sha256 over the sorted (file name, sha256 of its bytes) of the training covers."""
    h = hashlib.sha256()
    for p in sorted(pathlib.Path(p) for p in paths):
        h.update(p.name.encode() + b"\0" + hashlib.sha256(p.read_bytes()).hexdigest().encode() + b"\n")
    return h.hexdigest()
