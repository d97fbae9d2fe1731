"""Thesis ch. 8 protocol on the shared corpora: specific and universal detectors for every feature set
and classifier, 30 random cover-level splits, median accuracy / TPR / FPR / P_E, accuracy against the
number of PCA components (Figs. 8.3-8.5), and the ranking of meshmark's embedding methods by
detectability (docs/steganalysis.md §6).

    .venv/bin/python examples/steganalysis_protocol.py [--dataset out/steganalysis_dataset.npz]
        [--folders DIR ...] [--splits 30] [--out out/steganalysis_protocol]

The dataset (features of every cover and one stego version per cover and registered method) is built
once and cached; covers: ../shared/meshes/corpus-large, corpus and classic (research-only data: only
derived numbers are written, under out/). Thesis figures: specific > 80 % (LSB, Cho variance > 90 %),
universal about 75 %.
"""
from __future__ import annotations

import argparse
import csv
import pathlib
import time

import numpy as np

from meshmark.steganalysis import protocol as P

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"
RUNS = [("yang208", "qda", {}), ("yang208", "ensemble", {}), ("lfs76", "ensemble", {}), ("nvt36", "ensemble", {}),
        ("lfs76+nvt36", "ensemble", {}), ("yang208+lfs76+nvt36", "ensemble", {})]
PCA_K = [1, 2, 5, 10, 20, 40, 60, 100, 150, 208]
THESIS = "specific > 80 % (Figs. 8.3-8.4; LSB and Cho variance > 90 %), universal ~75 % (Fig. 8.5)"


def procedural_covers(n, seed=0):
    """Meshes that are not in ../shared: tori and capped tubes with random resolutions and proportions,
    smooth random bumps, and jittered vertices (valences stay 6 in the grid, like remeshed models)."""
    from meshmark import shapes
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n):
        if i % 2 == 0:
            m = shapes.torus(int(rng.integers(40, 140)), int(rng.integers(20, 70)), 1.0, float(rng.uniform(0.2, 0.5)))
        else:
            m = shapes.cylinder(int(rng.integers(30, 90)), int(rng.integers(40, 160)), float(rng.uniform(0.1, 0.4)),
                                float(rng.uniform(1, 3)))
        V = m.V.copy()
        c = V.mean(0)
        d = V - c
        r = np.linalg.norm(d, axis=1, keepdims=True)
        ang = np.arctan2(d[:, 1], d[:, 0])
        bump = sum(rng.uniform(0.005, 0.03) * np.sin(rng.integers(1, 7) * ang + rng.uniform(0, 6))
                   * np.cos(rng.uniform(1, 8) * d[:, 2] + rng.uniform(0, 6)) for _ in range(3))
        V = c + d * (1 + bump[:, None]) + rng.normal(scale=2e-4 * float(r.mean()), size=V.shape)
        out.append(m.with_vertices(V))
    return out


def holdout(ds, meshes, feature_set, classifier):
    """Train every detector on the whole shared dataset, test on procedural covers and their stego."""
    from meshmark.steganalysis.features import features
    from meshmark.steganalysis.model import Model
    X = P.dataset_features(ds, feature_set)
    with P.one_thread():
        model = Model.train(X, ds["method"] != "cover", list(ds["method"]), feature_set, classifier)
        res = {}
        for j, mesh in enumerate(meshes):
            f = features(mesh, feature_set)
            res.setdefault("cover", []).append(model.detect_features(f))
            for k, (name, (fn, _)) in enumerate(P.STEGO_METHODS.items()):
                try:
                    Vm = fn(mesh, np.random.default_rng([99, j, k]))
                except Exception:
                    continue
                res.setdefault(name, []).append(model.detect_features(features(mesh.with_vertices(Vm), feature_set)))
    print(f"\nHoldout: {len(meshes)} procedural covers not in ../shared, {feature_set} + {classifier} trained on the shared dataset")
    print("| meshes | n | universal says marked | its own specific detector says marked |\n|---|---:|---:|---:|")
    for name, rs in res.items():
        own = "-" if name == "cover" else f"{np.mean([r['methods'][name] > 0.5 for r in rs]):.2f}"
        if name == "cover":
            own = f"{np.mean([max(r['methods'].values()) > 0.5 for r in rs]):.2f} (any)"
        print(f"| {name} | {len(rs)} | {np.mean([r['marked'] for r in rs]):.2f} | {own} |")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dataset", default="out/steganalysis_dataset.npz")
    ap.add_argument("--folders", nargs="+", default=[str(SHARED / f) for f in ("corpus-large", "corpus", "classic")])
    ap.add_argument("--splits", type=int, default=30)
    ap.add_argument("--out", default="out/steganalysis_protocol")
    ap.add_argument("--no-pca", action="store_true", help="skip the accuracy-vs-components curve")
    ap.add_argument("--subset", default=None, help="only covers whose path contains this (e.g. psb-seg)")
    ap.add_argument("--holdout", type=int, default=20, help="procedural covers (not in ../shared) to test on")
    ap.add_argument("--holdout-set", default="yang208+lfs76+nvt36")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    if pathlib.Path(a.dataset).is_file():
        ds = P.load_dataset(a.dataset)
    else:
        with P.one_thread():
            ds = P.build_dataset(P.mesh_files(a.folders), None, ("yang208", "lfs76", "nvt36"),
                                 log=lambda s: print(s, flush=True))
        P.save_dataset(ds, a.dataset)
    t_features = time.perf_counter() - t0
    if a.subset:
        ds = P.subset(ds, a.subset)
    counts = {m: int((ds["method"] == m).sum()) for m in sorted(set(ds["method"]))}
    print("dataset:", counts)
    rows, table = [], []
    t1 = time.perf_counter()
    for fs, c, kw in RUNS:
        t = time.perf_counter()
        r = P.evaluate(ds, fs, c, a.splits, **kw)
        for x in r:
            x.update(feature_set=fs, classifier=c)
        rows += r
        for m in P.median_table(r):
            table.append({"feature_set": fs, "classifier": c, **m})
        print(f"{fs} + {c}: {time.perf_counter() - t:.0f} s", flush=True)
    t_train = time.perf_counter() - t1
    curve = []
    if not a.no_pca:
        for k in PCA_K:
            r = P.evaluate(ds, "yang208", "qda", a.splits, n_components=k)
            for m in P.median_table(r):
                curve.append({"k": k, **m})
    with open(f"{out}_splits.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    with open(f"{out}_median.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(table[0]))
        w.writeheader()
        w.writerows(table)
    if curve:
        with open(f"{out}_pca.csv", "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(curve[0]))
            w.writeheader()
            w.writerows(curve)
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        dets = sorted({c["detector"] for c in curve})
        fig, ax = plt.subplots(figsize=(8, 5))
        for d in dets:
            cs = [c for c in curve if c["detector"] == d]
            ax.plot([c["k"] for c in cs], [c["median_accuracy"] for c in cs], "o-", label=d,
                    lw=2.5 if d == "universal" else 1)
        ax.set_xscale("log")
        ax.set_xlabel("PCA components kept (YANG208 + QDA)")
        ax.set_ylabel(f"median test accuracy over {a.splits} splits")
        ax.axhline(0.8, color="k", ls=":", lw=1)
        ax.set_title("Figs. 8.3-8.5 on the shared corpora")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(f"{out}_pca.png", dpi=120)

    print(f"\n| feature set | classifier | detector | accuracy | TPR | FPR | P_E |  (median of {a.splits} splits; thesis: {THESIS})")
    print("|---|---|---|---:|---:|---:|---:|")
    for r in table:
        print(f"| {r['feature_set']} | {r['classifier']} | {r['detector']} | {r['median_accuracy']:.3f} | "
              f"{r['median_tpr']:.3f} | {r['median_fpr']:.3f} | {r['median_pe']:.3f} |")
    # ranking: per method, the lowest median P_E any (set, classifier) reaches = how detectable it is
    best = {}
    for r in table:
        if r["detector"].startswith("specific:"):
            m = r["detector"].split(":", 1)[1]
            if m not in best or r["median_pe"] < best[m][0]:
                best[m] = (r["median_pe"], r["feature_set"], r["classifier"], r["median_accuracy"])
    print("\nRanking by detectability (hardest to detect first: highest best-case P_E)")
    print("| rank | method | best P_E | accuracy | by |\n|---:|---|---:|---:|---|")
    for i, (m, (pe, fs, c, acc)) in enumerate(sorted(best.items(), key=lambda kv: -kv[1][0])):
        print(f"| {i + 1} | {m} | {pe:.3f} | {acc:.3f} | {fs} + {c} |")
    if curve:
        print("\n| k | " + " | ".join(sorted({c['detector'] for c in curve})) + " |")
        for k in PCA_K:
            cs = sorted((c for c in curve if c["k"] == k), key=lambda c: c["detector"])
            print(f"| {k} | " + " | ".join(f"{c['median_accuracy']:.3f}" for c in cs) + " |")
    if a.holdout:
        holdout(ds, procedural_covers(a.holdout), a.holdout_set, "ensemble")
    print(f"\nfeatures/dataset {t_features:.0f} s, training+testing the {len(RUNS)} runs x {a.splits} splits {t_train:.0f} s"
          f"; wrote {out}_*.csv" + (f", {out}_pca.png" if curve else ""))


if __name__ == "__main__":
    main()
