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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dataset", default="out/steganalysis_dataset.npz")
    ap.add_argument("--folders", nargs="+", default=[str(SHARED / f) for f in ("corpus-large", "corpus", "classic")])
    ap.add_argument("--splits", type=int, default=30)
    ap.add_argument("--out", default="out/steganalysis_protocol")
    ap.add_argument("--no-pca", action="store_true", help="skip the accuracy-vs-components curve")
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
    print(f"\nfeatures/dataset {t_features:.0f} s, training+testing the {len(RUNS)} runs x {a.splits} splits {t_train:.0f} s"
          f"; wrote {out}_*.csv" + (f", {out}_pca.png" if curve else ""))


if __name__ == "__main__":
    main()
