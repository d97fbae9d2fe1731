"""The default steganalysis model on meshes that are NOT in ../shared (docs/steganalysis.md, "Default
model on unseen meshes"):

    .venv/bin/python examples/steganalysis_unseen.py [--models default other.npz] [--n 60] [--blender out/holdout_blender]
        [--dataset out/unseen_holdout.npz] [--shared out/ds_v2_filled.npz] [--json F] [--quick]

``--models default`` (the default) is the shipped model. ``--quick``: 4 generated hold-out covers, no Blender
meshes, no shared dataset, a fresh cache.

Hold-out covers: ``--n`` meshes of the generated hold-out families (meshmark.steganalysis.generated:
torus-tube, superquadric, hull-blob; never trained on) plus the Blender-made OBJ files in ``--blender``
(examples/steganalysis_blender_holdout.py), each marked once by every registered stego method (seeded).
Their features are cached in ``--dataset``. ``--shared``: a cached protocol dataset of the shared
corpora (protocol.save_dataset); its covers not used by the default model (not in the model's
``training.covers``) are the second test set. For each model: FPR on the clean meshes, TPR per stego
method and overall, accuracy on covers + stego and the universal detector's ROC AUC, at the model's
threshold and at 0.5 (with and without an out-of-distribution guard when the model has one).
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "examples"))


def holdout_dataset(n, blender, seed, feature_sets):
    from meshmark.io import read_mesh
    from meshmark.steganalysis import generated as G, protocol as P
    covers = G.holdout_covers(n, seed=seed)
    if blender:
        covers += [(str(p), read_mesh(p)) for p in sorted(pathlib.Path(blender).glob("*.obj"))]
    with P.one_thread():
        return P.build_dataset(covers, None, feature_sets, seed=1000 + seed,
                               log=lambda s: print(s, file=sys.stderr, flush=True))


def family(path):
    p = str(path)
    if "#" in p and not p.startswith("/"):
        return p.split("#")[0]
    if "blender_" in p:
        return "blender"
    return "shared"


def score(model, X, method, fam, guard=True):
    """Rows of (set, FPR, TPR per method, overall TPR, accuracy, out-of-distribution fraction)."""
    res = [model.detect_features(x, guard=guard) for x in X]
    marked = np.array([r["marked"] for r in res])
    ind = np.array([r.get("in_distribution", True) for r in res])
    y = method != "cover"
    out = {"n_covers": int((~y).sum()), "n_stego": int(y.sum()),
           "fpr": float(marked[~y].mean()), "tpr": float(marked[y].mean()) if y.any() else float("nan"),
           "accuracy": float((marked == y).mean()), "ood_covers": float((~ind[~y]).mean()),
           "ood_stego": float((~ind[y]).mean()) if y.any() else float("nan")}
    out["balanced_accuracy"] = 0.5 * (1 - out["fpr"] + out["tpr"])
    from sklearn.metrics import roc_auc_score
    out["auc"] = float(roc_auc_score(y, [r["probability"] for r in res])) if y.any() else float("nan")
    out["tpr_by_method"] = {m: float(marked[method == m].mean()) for m in sorted(set(method) - {"cover"})}
    out["fpr_by_family"] = {f: float(marked[(~y) & (fam == f)].mean()) for f in sorted(set(fam[~y]))}
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--models", nargs="+", default=["default"], help='model files; "default": the shipped model')
    ap.add_argument("--n", type=int, default=60)
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--blender", default=str(ROOT / "out" / "holdout_blender"))
    ap.add_argument("--dataset", default=str(ROOT / "out" / "unseen_holdout.npz"))
    ap.add_argument("--shared", default=str(ROOT / "out" / "ds_v2_filled.npz"))
    ap.add_argument("--json", default=None, help="write every figure here")
    ap.add_argument("--quick", action="store_true", help="4 generated hold-out covers only, no cache (tested)")
    a = ap.parse_args()
    if a.quick:
        import tempfile
        a.n, a.blender, a.shared = 4, "", ""
        if a.dataset == ap.get_default("dataset"):
            a.dataset = str(pathlib.Path(tempfile.mkdtemp()) / "unseen_quick.npz")
    from meshmark.steganalysis import protocol as P
    from meshmark.steganalysis.model import Model
    models = {mp: Model.load() if mp == "default" else Model.load(mp) for mp in a.models}
    fsets = tuple(dict.fromkeys(s for m in models.values() for s in m.feature_set.split("+")))  # the models' sets
    if pathlib.Path(a.dataset).is_file():
        ds = P.load_dataset(a.dataset)
    else:
        ds = holdout_dataset(a.n, a.blender if a.blender and pathlib.Path(a.blender).is_dir() else None, a.seed, fsets)
        P.save_dataset(ds, a.dataset)
    sets = {"unseen": ds}
    if a.shared and pathlib.Path(a.shared).is_file():
        sets["shared-heldout"] = P.load_dataset(a.shared)
    report = {}
    for mp, model in models.items():
        train_files = {pathlib.Path(p).name for p in model.training.get("covers", {})}
        for name, d in sets.items():
            X = P.dataset_features(d, model.feature_set)
            cov_path = np.array([d["path"][c] for c in d["cover"]], dtype=object)
            keep = np.array([pathlib.Path(p).name not in train_files for p in cov_path])
            fam = np.array([family(p) for p in cov_path], dtype=object)
            shipped = model.threshold
            for t in dict.fromkeys((shipped, 0.5)):  # the model's operating point, and 0.5 for comparison
                for guard in ((False, True) if model.guard else (False,)):
                    model.threshold = t
                    r = score(model, X[keep], d["method"][keep], fam[keep], guard=guard)
                    key = f"{mp} | {name} | threshold={t:.3f} | guard={guard}"
                    report[key] = r
                    print(f"{key}: covers {r['n_covers']} stego {r['n_stego']} FPR {r['fpr']:.3f} TPR {r['tpr']:.3f} "
                          f"acc {r['accuracy']:.3f} bal {r['balanced_accuracy']:.3f} AUC {r['auc']:.3f} "
                          f"OOD covers {r['ood_covers']:.2f} stego {r['ood_stego']:.2f}")
                    print("   TPR:", " ".join(f"{m} {v:.2f}" for m, v in r["tpr_by_method"].items()))
                    print("   FPR:", " ".join(f"{m} {v:.2f}" for m, v in r["fpr_by_family"].items()))
            model.threshold = shipped
    if a.json:
        pathlib.Path(a.json).write_text(json.dumps(report, indent=1))


if __name__ == "__main__":
    main()
