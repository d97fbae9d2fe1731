"""Train the default steganalysis model shipped with meshmark (``meshmark steganalysis detect`` without
``--model``) on the openly licensed meshes of ../shared/meshes only (SOURCES.md):

    .venv/bin/python examples/steganalysis_default_model.py [--out src/meshmark/steganalysis/default_model.npz] [--quick --out F]

``--quick`` (the test suite): a small model from 3 open files and 6 generated meshes, the same training code;
it needs ``--out`` and never replaces the shipped model.

Covers: CC0 / public-domain / CC-BY files (CC-BY-SA, GPL, non-commercial, "no licence stated" and
everything in corpus-large are left out; attribution is in the model's metadata and
docs/steganalysis.md §4). Each cover is marked by every registered stego method with ``--versions``
independent messages and strengths. Cover variety (``--augment``, default on): besides each file, two
patches (the mesh cropped by 35 % along its first and third principal axes: open sub-meshes) and one
level of Loop subdivision (meshes under 20k vertices) are further covers. Since the unseen-mesh
measurement (docs/steganalysis.md, "Default model on unseen meshes"), also (``--variants``, default on)
three re-meshings of each file (quadric simplification, Gaussian noise, midpoint subdivision + noise:
``generated.open_variants``) and ``--generated`` meshes of the training-only families (``generated.
training_covers``: icospheres, Loop-subdivided solids, open height fields). None of the hold-out families
(``generated.HOLDOUT_FAMILIES``, the Blender meshes) is used.

Operating point: the universal decision threshold is the smallest vote fraction whose false-positive
rate on the covers is at most ``--fpr`` (default 5 %) in a grouped ``--folds``-fold cross-validation
over the training covers (a file and all its variants, or one generated mesh, form a group; the
hold-out sets are not used). The out-of-distribution guard (``--guard``) stores the training range;
its ``max_outside`` is set the same way (at most ``--ood-fpr`` of the out-of-fold training covers flagged);
off by default: measured, it flags no generated hold-out mesh and 13 % of the real held-out covers.
Models trained on research-only data are made with ``meshmark steganalysis train`` and stay out of the
repository.
"""
from __future__ import annotations

import argparse
import pathlib
import sys

import numpy as np

import meshmark
from meshmark import attacks
from meshmark.steganalysis import classifiers as clf, generated as G, protocol as P
from meshmark.steganalysis.features import PROTOCOL_SET
from meshmark.steganalysis.model import Model, corpus_hash

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"
OPEN = {  # file -> licence as stated in SOURCES.md
    "classic/spot.obj": "public domain (Keenan Crane)",
    "classic/hand.obj": "CC-BY 4.0 (SMPL woman mesh, Max Planck Society; odedstein/meshes)",
    "corpus/odedstein_boot.obj": "CC-BY 4.0 (inciprocal / Oded Stein)",
    "corpus/odedstein_cat-low-resolution.obj": "CC-BY 4.0 (billyd, Thingiverse 1565405)",
    "corpus/odedstein_demosthenes-low-res.obj": "CC-BY 4.0 (ryanfb)",
    "corpus/odedstein_fish_low_resolution.obj": "public domain (Keenan Crane)",
    "corpus/odedstein_goathead.obj": "CC-BY 3.0 (hugoelec, Thingiverse 42256)",
    "corpus/odedstein_koala_low_resolution.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182225)",
    "corpus/odedstein_penguin.obj": "CC-BY 4.0 (odedstein/meshes)",
    "corpus/odedstein_plane.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182252)",
    "corpus/odedstein_skull_low_resolution.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182365)",
    "corpus/odedstein_torus.obj": "CC-BY 4.0 (odedstein/meshes)",
    "corpus/vtk_Vase.stl": "CC-BY (Alzibiff, Victorian Goblet face illusion)",
    "corpus/thingi10k_59758.stl": "CC-BY (DigitalBytes, Thingiverse 18471)",
    "corpus/thingi10k_63448.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_63451.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_63452.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_65583.stl": "CC-BY (pmoews, Thingiverse 20976)",
    "corpus/thingi10k_68435.stl": "CC-BY (EdinKali, Thingiverse 22236)",
    "corpus/thingi10k_73338.stl": "CC-BY (anneyfresh, Thingiverse 24228)",
    "corpus/thingi10k_73342.stl": "CC-BY (anneyfresh, Thingiverse 24228)",
    "corpus/thingi10k_50736.stl": "public domain (chris, Thingiverse 15346)",
    "corpus/thingi10k_97171.stl": "public domain (chris, Thingiverse 33696)",
}


def augmented(paths):
    """(name, mesh) covers: each open file, two patches of it and its Loop subdivision (docs/steganalysis.md §4)."""
    out = []
    for p in paths:
        m = meshmark.read_mesh(p)
        out.append((str(p), m))
        used = np.zeros(m.n_vertices, bool)
        used[m.face_indices] = True
        Vc = m.V[used] - m.V[used].mean(0)
        axes = np.linalg.svd(Vc, full_matrices=False)[2]
        for k in (0, 2):
            try:
                c = attacks.crop(m, fraction=0.35, normal=axes[k])
                if c.n_vertices >= 50:
                    out.append((f"{p}#crop{k}", c))
            except meshmark.MeshError:
                pass
        if m.n_vertices < 20000:
            try:
                out.append((f"{p}#loop1", attacks.subdivide(m, scheme="loop", levels=1)))
            except meshmark.MeshError:
                pass
    return out


def group_of(name):
    """Cross-validation group of a training cover: its source file (with every variant) or the generated mesh."""
    return name if name.split("#")[0] in G.FAMILIES else name.split("#")[0]


QUICK_COVERS = ["classic/spot.obj", "corpus/odedstein_fish_low_resolution.obj", "corpus/odedstein_torus.obj"]


def training_set(a):
    paths = [SHARED / p for p in (QUICK_COVERS if a.quick else OPEN)]
    covers = [(str(p), meshmark.read_mesh(p)) for p in paths] if a.no_augment else augmented(paths)
    if a.variants:
        covers += [v for k, p in enumerate(paths) for v in G.open_variants(str(p), meshmark.read_mesh(p), seed=k)]
    covers += G.training_covers(a.generated, seed=a.seed)
    Xs, meth, cov = [], [], []
    names = None
    for v in range(a.versions):
        ds = P.build_dataset(covers, None, tuple(a.feature_set.split("+")), seed=v,
                             log=lambda s: print(s, file=sys.stderr, flush=True) if a.verbose else None)
        keep = np.ones(len(ds["method"]), bool) if v == 0 else ds["method"] != "cover"
        names = ds["path"] if names is None else names
        assert names == ds["path"]
        Xs.append(P.dataset_features(ds, a.feature_set)[keep])
        meth += list(ds["method"][keep])
        cov += list(ds["cover"][keep])
    return {"X": np.vstack(Xs), "method": np.array(meth, dtype=object), "cover": np.array(cov), "path": names}


def calibrate(X, y, groups, n_folds, seed, learners, fpr_target, ood_target, margin, fs):
    """Out-of-fold universal probabilities and guard fractions (grouped k-fold), the threshold with OOF
    cover FPR <= fpr_target and the guard's max_outside with <= ood_target of the OOF covers flagged."""
    ug = np.array(sorted(set(groups)))
    fold_of = dict(zip(ug, np.random.default_rng(seed).permutation(len(ug)) % n_folds))
    fold = np.array([fold_of[g] for g in groups])
    p, out = np.zeros(len(y)), np.zeros(len(y))
    for k in range(n_folds):
        tr, te = fold != k, fold == k
        det = clf.make("ensemble", n_learners=learners).fit(X[tr], y[tr])
        p[te] = det.predict_proba(X[te])
        m = Model(fs, "ensemble", {}, {}, {})
        m.set_guard(X[tr], margin, 1.0)
        out[te] = m.outside_fraction(X[te])
    c = ~y
    grid = np.unique(np.r_[p, 0.0])
    # smallest threshold t (decision p > t) with OOF FPR <= target
    t = next(t for t in grid if (p[c] > t).mean() <= fpr_target)
    q = float(np.quantile(out[c], 1 - ood_target))
    return {"threshold": float(t), "oof_fpr": float((p[c] > t).mean()), "oof_tpr": float((p[y] > t).mean()),
            "oof_fpr_at_0.5": float((p[c] > 0.5).mean()), "oof_tpr_at_0.5": float((p[y] > 0.5).mean()),
            "max_outside": q, "oof_flagged_covers": float((out[c] > q).mean()),
            "oof_flagged_stego": float((out[y] > q).mean()), "folds": n_folds}, p, out


def evaluate_on_sources(model_path, dataset, out_csv=None):
    """The model on a protocol dataset of the shared corpora (examples/steganalysis_sources.py), covers used
    for training (OPEN) left out: per source, the share of clean covers called marked (FPR), of stego meshes
    found (TPR, per method) and of meshes the domain check cannot judge; rates among the judged meshes."""
    from meshmark.steganalysis.loso import cover_sources
    model = Model.load(model_path)
    ds = P.load_dataset(dataset)
    X = P.dataset_features(ds, model.feature_set)
    train_names = {pathlib.Path(p).name for p in OPEN}
    keep_cov = np.array([pathlib.Path(p).name not in train_names for p in ds["path"]])
    rows = keep_cov[ds["cover"]]
    src = cover_sources(ds)[ds["cover"]]
    p = model.detectors["universal"].predict_proba(X)
    dist = model.domain_distance(X)
    judged = dist <= model.domain["threshold"] if model.domain else np.ones(len(X), bool)
    marked = (p > model.threshold) & judged
    meth = ds["method"]
    table = []
    for s in sorted(set(src[rows])) + ["all"]:
        sel = rows & ((src == s) if s != "all" else True)
        c, st = sel & (meth == "cover"), sel & (meth != "cover")
        d = {"source": s, "covers": int(c.sum()), "cannot_judge_covers": float(1 - judged[c].mean()),
             "cannot_judge_stego": float(1 - judged[st].mean()), "fpr": float(marked[c].mean()),
             "fpr_judged": float(marked[c & judged].mean()) if (c & judged).any() else float("nan"),
             "tpr": float(marked[st].mean()), "tpr_judged": float(marked[st & judged].mean()) if (st & judged).any() else float("nan")}
        for m in sorted(set(meth[st])):
            d[f"tpr:{m}"] = float(marked[st & (meth == m)].mean())
        table.append(d)
    if out_csv:
        import csv
        with open(out_csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=sorted({k for d in table for k in d}))
            w.writeheader()
            w.writerows(table)
    meths = sorted({k[4:] for d in table for k in d if k.startswith("tpr:")})
    print("| source | covers | cannot judge (covers / stego) | FPR | FPR judged | TPR | TPR judged | "
          + " | ".join(meths) + " |")
    print("|---|---:|---:|---:|---:|---:|---:|" + "---:|" * len(meths))
    for d in table:
        print(f"| {d['source']} | {d['covers']} | {d['cannot_judge_covers']:.2f} / {d['cannot_judge_stego']:.2f} | "
              f"{d['fpr']:.3f} | {d['fpr_judged']:.3f} | {d['tpr']:.3f} | {d['tpr_judged']:.3f} | "
              + " | ".join(f"{d.get('tpr:' + m, float('nan')):.2f}" for m in meths) + " |")
    return table


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--evaluate", default=None, metavar="DATASET",
                    help="only evaluate --out (an existing model) on a protocol dataset of the shared corpora, per source")
    ap.add_argument("--out", default=str(ROOT / "src" / "meshmark" / "steganalysis" / "default_model.npz"))
    ap.add_argument("--set", dest="feature_set", default=PROTOCOL_SET)
    ap.add_argument("--versions", type=int, default=2, help="stego versions per (cover, method)")
    ap.add_argument("--learners", type=int, default=31, help="FLD learners of each specific detector")
    ap.add_argument("--universal-learners", type=int, default=101,
                    help="FLD learners of the universal detector (finer vote fractions at the low-FPR threshold)")
    ap.add_argument("--no-augment", action="store_true", help="no crops and Loop subdivisions of the files")
    ap.add_argument("--variants", type=int, default=1, help="1: add generated.open_variants of each file")
    ap.add_argument("--generated", type=int, default=90, help="meshes of the training-only generated families")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--fpr", type=float, default=0.05, help="target cross-validated FPR on the covers")
    ap.add_argument("--guard", type=int, default=0,
                    help="1: store the out-of-distribution guard (measured not to help the default model: docs)")
    ap.add_argument("--ood-fpr", type=float, default=0.02, help="OOF training covers the guard may flag")
    ap.add_argument("--margin", type=float, default=0.1, help="guard: widen the training range by this share of its span")
    ap.add_argument("--folds", type=int, default=5)
    ap.add_argument("--domain-rate", type=float, default=0.05,
                    help="domain check: share of the training covers (each against the other groups) beyond its threshold; 0 = none")
    ap.add_argument("--threshold", type=float, default=None, help="fix the threshold instead of calibrating it")
    ap.add_argument("--dataset", default=None, help="cache of the training features (.npz): read if present, else written")
    ap.add_argument("--no-diversity", action="store_true",
                    help="ablation: drop the open-file variants and the generated covers (the previous recipe)")
    ap.add_argument("--verbose", action="store_true")
    ap.add_argument("--quick", action="store_true",
                    help="3 open files, no crops or variants, 6 generated, few learners (tested; needs --out)")
    a = ap.parse_args()
    if a.quick:
        if a.out == ap.get_default("out"):
            raise SystemExit("--quick makes a small test model: give --out (the shipped model is never replaced by it)")
        a.no_augment, a.variants, a.generated, a.versions = True, 0, 6, 1
        a.learners, a.universal_learners, a.folds = 5, 11, 3
    if a.evaluate:
        evaluate_on_sources(a.out, a.evaluate, pathlib.Path(a.out).with_suffix(".sources.csv"))
        return
    paths = [SHARED / p for p in (QUICK_COVERS if a.quick else OPEN)]
    with P.one_thread():
        if a.dataset and pathlib.Path(a.dataset).is_file():
            z = np.load(a.dataset, allow_pickle=False)
            ds = {"X": z["X"], "method": z["method"].astype(object), "cover": z["cover"], "path": list(z["path"])}
        else:
            ds = training_set(a)
            if a.dataset:
                np.savez_compressed(a.dataset, X=ds["X"], method=ds["method"].astype(str), cover=ds["cover"],
                                    path=np.array(ds["path"], dtype=str))
        if a.no_diversity:
            tags = ("#simplify", "#noise", "#midpoint+noise")
            ok = np.array([not (p.split("#")[0] in G.FAMILIES or p.endswith(tags)) for p in ds["path"]])
            rows = ok[ds["cover"]]
            new = -np.ones(len(ok), int)
            new[ok] = np.arange(int(ok.sum()))
            ds = {"X": ds["X"][rows], "method": ds["method"][rows], "cover": new[ds["cover"][rows]],
                  "path": [p for p, k in zip(ds["path"], ok) if k]}
            a.variants, a.generated = 0, 0
        X, labs = ds["X"], list(ds["method"])
        y = ds["method"] != "cover"
        groups = np.array([group_of(ds["path"][c]) for c in ds["cover"]], dtype=object)
        cal, _, _ = calibrate(X, y, groups, a.folds, a.seed, a.universal_learners, a.fpr, a.ood_fpr, a.margin, a.feature_set)
        threshold = cal["threshold"] if a.threshold is None else a.threshold
        fam = {}
        for pth in ds["path"]:
            f = pth.split("#")[0] if pth.split("#")[0] in G.FAMILIES else ("open file" if "#" not in pth else
                                                                          "open " + pth.split("#")[1].rstrip("0123456789"))
            fam[f] = fam.get(f, 0) + 1
        training = {"corpus_hash": corpus_hash(paths), "n_covers": int((~y).sum()), "n_stego": int(y.sum()),
                    "methods": sorted({l for l in labs if l != "cover"}), "versions": a.versions,
                    "augmentation": None if a.no_augment else "each file + 2 patches (35 % crops along principal axes 1, 3) + Loop subdivision (< 20k vertices)",
                    "variants": "generated.open_variants: simplify, noise, midpoint+noise" if a.variants else None,
                    "generated": {"n": a.generated, "seed": a.seed, "families": list(G.TRAINING_FAMILIES)},
                    "cover_kinds": fam, "calibration": cal, "fpr_target": a.fpr,
                    "learners": {"universal": a.universal_learners, "specific": a.learners},
                    "covers": {p: lic for p, lic in OPEN.items() if not a.quick or p in QUICK_COVERS},
                    "note": "openly licensed meshes of ../shared/meshes plus generated meshes only; see docs/steganalysis.md"}
        model = Model.train(X, y, labs, a.feature_set, "ensemble", training, n_learners=a.learners)
        model.detectors["universal"] = clf.make("ensemble", n_learners=a.universal_learners).fit(X, y)
        model.threshold = threshold
        if a.guard:
            model.set_guard(X, a.margin, cal["max_outside"], ood_target=a.ood_fpr)
        if a.domain_rate > 0:
            c = ~y
            dom = model.set_domain(X[c], groups[c], rate=a.domain_rate, group_kind="a file with its variants, or one generated mesh")
            model.training["domain"] = dom
    model.save(a.out, overwrite=True)  # regenerates the shipped model
    print(f"wrote {a.out} ({pathlib.Path(a.out).stat().st_size / 1024:.0f} KB): {training['n_covers']} covers "
          f"({fam}), {training['n_stego']} stego; threshold {threshold:.3f}; calibration {cal}")


if __name__ == "__main__":
    main()
