"""The steganalysis task kind of ``meshmark study run`` (a spec with ``kind = "steganalysis"``).

One spec reproduces every table of docs/steganalysis.md from scratch (``examples/studies/steganalysis.toml``)::

    kind = "steganalysis"
    [study]
    name = "steganalysis"
    [steganalysis]
    parts = ["protocol", "cho_table"]          # the ch. 8 protocol; thesis Table 6.2 (§6.4)
    folders = ["../../../shared/meshes/corpus-large", ...]   # covers (relative to the spec)
    subset = ""                                 # only covers whose path contains this (e.g. "psb-seg")
    feature_sets = ["yang208", "lfs76s", "nvt36s"]
    runs = [{ set = "yang208", classifier = "qda" }, { set = "yang208", classifier = "ensemble" }, ...]
    splits = 30
    test_fraction = 0.3
    pca_k = [1, 2, 5, ...]                      # accuracy vs PCA components, YANG208 + QDA (Figs. 8.3-8.5); [] = skip
    universal = ["pick"]                        # universal training variants (protocol.UNIVERSAL)
    holdout = 20                                # procedural covers not in ../shared
    holdout_set = "yang208+lfs76s+nvt36s"
    by_source = [["yang208+lfs76s+nvt36s", "ensemble"]]   # leave one source out (loso.py); [] = skip
    dedup = true                                # drop covers with the geometry of another (sources.deduplicate)
    [steganalysis.cho_table]
    folders = ["../../../shared/meshes/corpus", "../../../shared/meshes/corpus-large"]
    variants = true
    limit = 0

Tasks: (1) generate — the features of every cover and of one stego version per (cover, registered
method), cached in ``OUT/dataset.npz`` (a rerun reuses it: resume); (2) the protocol — cover-level
splits, training and testing of every detector, ``OUT/protocol_splits.csv`` (every split),
``protocol_median.csv``, ``protocol_ranking.csv``, ``protocol_pca.csv`` and the figures
``protocol_pca.png`` (Figs. 8.3-8.5 style: accuracy against the number of PCA components per detector)
and ``protocol_accuracy.png`` (median accuracy per detector and run); (3) Table 6.2 — ``cho_table*.csv/png``.
``OUT/tables.md`` has every table as printed in docs/steganalysis.md.
"""
from __future__ import annotations

import csv
import json
import pathlib
import time

import numpy as np

from .._core import MeshError
from . import protocol as P

KIND = "steganalysis"
KEYS = {"parts", "folders", "subset", "feature_sets", "runs", "splits", "test_fraction", "pca_k", "holdout",
        "holdout_set", "cho_table", "methods", "universal", "seed", "limit", "by_source"}
PARTS = {"protocol", "cho_table"}
DEFAULT_RUNS = [("yang208", "qda"), ("yang208", "ensemble"), ("lfs76s", "ensemble"), ("nvt36s", "ensemble"),
                ("lfs76s+nvt36s", "ensemble"), ("yang208+lfs76s+nvt36s", "ensemble")]
THESIS = "specific > 80 % (Figs. 8.3-8.4; LSB and Cho variance > 90 %), universal ~75 % (Fig. 8.5)"


def _write_csv(path, rows):
    if not rows:
        return
    fields = list(dict.fromkeys(k for r in rows for k in r))
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields, restval="")
        w.writeheader()
        w.writerows(rows)


def _paths(base, xs, what):
    if not isinstance(xs, list) or not xs:
        raise MeshError(f"steganalysis spec: {what} must be a non-empty list of folders")
    out = [(base / x).resolve() for x in xs]
    for p in out:
        if not p.is_dir():
            raise MeshError(f"steganalysis spec: {what}: no such folder {p}")
    return out


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


def holdout(ds, meshes, feature_set, classifier="ensemble") -> list[dict]:
    """Train every detector on the whole dataset, test on covers not in it and their stego versions."""
    from .features import features
    from .model import Model
    X = P.dataset_features(ds, feature_set)
    with P.one_thread():
        model = Model.train(X, ds["method"] != "cover", list(ds["method"]), feature_set, classifier)
        res = {}
        for j, mesh in enumerate(meshes):
            res.setdefault("cover", []).append(model.detect_features(features(mesh, feature_set)))
            for k, (name, (fn, _)) in enumerate(P.STEGO_METHODS.items()):
                if f"specific:{name}" not in model.detectors:  # a method the dataset does not have
                    continue
                try:
                    Vm = fn(mesh, np.random.default_rng([99, j, k]))
                except Exception:  # noqa: BLE001 - a cover that cannot carry this mark
                    continue
                res.setdefault(name, []).append(model.detect_features(features(mesh.with_vertices(Vm), feature_set)))
    rows = []
    for name, rs in res.items():  # covers: does ANY specific detector fire; stego: does its own one
        rows.append({"meshes": name, "n": len(rs), "universal_marked": float(np.mean([r["marked"] for r in rs])),
                     "specific_marked": float(np.mean([(max(r["methods"].values()) if name == "cover"
                                                        else r["methods"][name]) > 0.5 for r in rs])),
                     "specific_is": "any" if name == "cover" else "own"})
    return rows


def protocol(cfg: dict, base: pathlib.Path, out: pathlib.Path, log) -> list[str]:
    L = []
    t0 = time.perf_counter()
    cache = out / "dataset.npz"
    fsets = tuple(cfg.get("feature_sets", ("yang208", "lfs76s", "nvt36s")))
    files = P.mesh_files(_paths(base, cfg.get("folders"), "folders"))
    if cfg.get("limit"):
        files = files[: int(cfg["limit"])]
    if cfg.get("dedup", True):
        from .sources import deduplicate
        files = [g[0] for g in deduplicate(files)]
    key = P.dataset_key(files, cfg.get("methods"), fsets, seed=int(cfg.get("seed", 0)))
    ds = None
    if cache.is_file():
        try:
            ds = P.load_dataset(cache, expect_key=key)
            log(f"[steganalysis] reusing {cache}")
        except MeshError as exc:  # the study's own cache, built for another spec: rebuilt
            log(f"[steganalysis] not reusing {cache}: {exc}")
    if ds is None:
        with P.one_thread():
            ds = P.build_dataset(files, cfg.get("methods"), fsets, seed=int(cfg.get("seed", 0)), log=log)
        P.save_dataset(ds, cache, key=key)
    t_data = time.perf_counter() - t0
    if cfg.get("subset"):
        ds = P.subset(ds, cfg["subset"])
    counts = {m: int((ds["method"] == m).sum()) for m in sorted(set(ds["method"]))}
    L.append(f"dataset: {json.dumps(counts)}")
    splits, frac = int(cfg.get("splits", 30)), float(cfg.get("test_fraction", 0.3))
    runs = [(r["set"], r.get("classifier", "ensemble"), r.get("universal", "pick"), r.get("params", {}))
            for r in cfg["runs"]] if "runs" in cfg else [(s, c, "pick", {}) for s, c in DEFAULT_RUNS]
    for u in cfg.get("universal", []):
        if u != "pick":
            runs.append(("yang208+lfs76s+nvt36s", "ensemble", u, {}))
    rows, table = [], []
    t1 = time.perf_counter()
    for fs, c, uni, params in runs:
        t = time.perf_counter()
        r = P.evaluate(ds, fs, c, splits, frac, universal=uni, **params)
        ptext = json.dumps(params, sort_keys=True) if params else ""
        for x in r:
            x.update(feature_set=fs, classifier=c, universal_training=uni, params=ptext)
        rows += r
        table += [{"feature_set": fs, "classifier": c, "universal_training": uni, "params": ptext, **m}
                  for m in P.median_table(r)]
        log(f"[steganalysis] {fs} + {c} ({uni}): {time.perf_counter() - t:.0f} s")
    for fs, c in [tuple(x) for x in cfg.get("by_source", [])]:  # the headline protocol: leave one source out
        from .loso import evaluate_by_source, source_table
        t = time.perf_counter()
        lr = evaluate_by_source(ds, fs, c)
        for x in lr:
            x.update(feature_set=fs, classifier=c)
        st = source_table(lr)
        _write_csv(out / f"sources_{fs}_{c}.csv", lr)
        _write_csv(out / f"sources_table_{fs}_{c}.csv", st)
        log(f"[steganalysis] leave-one-source-out {fs} + {c}: {time.perf_counter() - t:.0f} s")
        meths = sorted({k.split(":", 1)[1] for d in st for k in d if k.startswith("specific:")})
        L.append(f"\nLeave one source out, {fs} + {c} (universal: accuracy at 0.5 and at the threshold calibrated to "
                 f"5 % FPR on the training sources; FPR / TPR at that threshold; specific detectors' accuracy)")
        L.append("| source | covers | universal | universal@5% | FPR | TPR | " + " | ".join(meths) + " |")
        L.append("|---|---:|---:|---:|---:|---:|" + "---:|" * len(meths))
        for d in st:
            L.append(f"| {d['source']} | {d['n_covers']} | {d['universal']:.3f} | {d['universal@fpr']:.3f} | {d['fpr']:.3f} | "
                     f"{d['tpr']:.3f} | " + " | ".join(f"{d.get('specific:' + m, float('nan')):.3f}" for m in meths) + " |")
    t_train = time.perf_counter() - t1
    _write_csv(out / "protocol_splits.csv", rows)
    _write_csv(out / "protocol_median.csv", table)
    curve = []
    for k in cfg.get("pca_k", []):
        for m in P.median_table(P.evaluate(ds, "yang208", "qda", splits, frac, n_components=int(k))):
            curve.append({"k": int(k), **m})
    _write_csv(out / "protocol_pca.csv", curve)

    L.append(f"\n| feature set | classifier | universal training | params | detector | accuracy | TPR | FPR | P_E |  "
             f"(median of {splits} splits; thesis: {THESIS})")
    L.append("|---|---|---|---|---|---:|---:|---:|---:|")
    for r in table:
        L.append(f"| {r['feature_set']} | {r['classifier']} | {r['universal_training']} | {r['params']} | {r['detector']} | "
                 f"{r['median_accuracy']:.3f} | {r['median_tpr']:.3f} | {r['median_fpr']:.3f} | {r['median_pe']:.3f} |")
    best = {}
    for r in table:
        if r["detector"].startswith("specific:"):
            m = r["detector"].split(":", 1)[1]
            if m not in best or r["median_pe"] < best[m][0]:
                best[m] = (r["median_pe"], r["feature_set"], r["classifier"] + (f" {r['params']}" if r["params"] else ""),
                           r["median_accuracy"])
    ranking = [{"rank": i + 1, "method": m, "best_pe": pe, "accuracy": acc, "by": f"{fs} + {c}"}
               for i, (m, (pe, fs, c, acc)) in enumerate(sorted(best.items(), key=lambda kv: -kv[1][0]))]
    _write_csv(out / "protocol_ranking.csv", ranking)
    L.append("\nRanking by detectability (hardest to detect first: highest best-case P_E)")
    L.append("| rank | method | best P_E | accuracy | by |\n|---:|---|---:|---:|---|")
    L += [f"| {r['rank']} | {r['method']} | {r['best_pe']:.3f} | {r['accuracy']:.3f} | {r['by']} |" for r in ranking]
    if curve:
        dets = sorted({c["detector"] for c in curve})
        L.append("\n| k | " + " | ".join(dets) + " |\n|---:|" + "---:|" * len(dets))
        for k in sorted({c["k"] for c in curve}):
            cs = {c["detector"]: c for c in curve if c["k"] == k}
            L.append(f"| {k} | " + " | ".join(f"{cs[d]['median_accuracy']:.3f}" for d in dets) + " |")
    _plots(out, table, curve, splits)
    if int(cfg.get("holdout", 0)):
        hs = cfg.get("holdout_set", "yang208+lfs76s+nvt36s")
        hr = holdout(ds, procedural_covers(int(cfg["holdout"])), hs)
        _write_csv(out / "protocol_holdout.csv", hr)
        L.append(f"\nHoldout: {cfg['holdout']} procedural covers not in ../shared, {hs} + ensemble trained on the whole dataset")
        L.append("| meshes | n | universal says marked | specific says marked |\n|---|---:|---:|---:|")
        L += [f"| {r['meshes']} | {r['n']} | {r['universal_marked']:.2f} | {r['specific_marked']:.2f} ({r['specific_is']}) |"
              for r in hr]
    L.append(f"\nfeatures/dataset {t_data:.0f} s, training+testing {len(runs)} runs x {splits} splits {t_train:.0f} s")
    return L


def _plots(out, table, curve, splits):
    from ..optional import pyplot
    plt = pyplot("the steganalysis study's plots")
    if curve:  # Figs. 8.3-8.5: accuracy against the number of principal components
        fig, ax = plt.subplots(figsize=(8, 5))
        for d in sorted({c["detector"] for c in curve}):
            cs = sorted((c for c in curve if c["detector"] == d), key=lambda c: c["k"])
            ax.plot([c["k"] for c in cs], [c["median_accuracy"] for c in cs], "o-", label=d,
                    lw=2.5 if d == "universal" else 1)
        ax.set_xscale("log")
        ax.set_xlabel("PCA components kept (YANG208 + QDA)")
        ax.set_ylabel(f"median test accuracy over {splits} splits")
        ax.axhline(0.8, color="k", ls=":", lw=1)
        ax.set_title("Figs. 8.3-8.5: accuracy against the number of principal components")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "protocol_pca.png", dpi=120)
        plt.close(fig)
    runs = list(dict.fromkeys((r["feature_set"], r["classifier"], r["universal_training"], r["params"]) for r in table))
    dets = sorted({r["detector"] for r in table}, key=lambda d: (d == "universal", d))
    fig, ax = plt.subplots(figsize=(max(8, len(dets) * 0.9), 5))
    w = 0.8 / max(1, len(runs))
    for j, run in enumerate(runs):
        acc = {r["detector"]: r["median_accuracy"] for r in table
               if (r["feature_set"], r["classifier"], r["universal_training"], r["params"]) == run}
        ax.bar(np.arange(len(dets)) + j * w, [acc.get(d, np.nan) for d in dets], w,
               label=f"{run[0]} + {run[1]}" + ("" if run[2] == "pick" else f" ({run[2]})") + (f" {run[3]}" if run[3] else ""))
    ax.set_xticks(np.arange(len(dets)) + 0.4 - w / 2)
    ax.set_xticklabels([d.replace("specific:", "") for d in dets], rotation=45, ha="right", fontsize=8)
    ax.set_ylim(0.4, 1.0)
    ax.axhline(0.8, color="k", ls=":", lw=1)
    ax.set_ylabel(f"median test accuracy ({splits} splits)")
    ax.set_title("Specific and universal detectors (ch. 8 protocol)")
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "protocol_accuracy.png", dpi=120)
    plt.close(fig)


def run_study(raw: dict, out, base, log=print):
    """Runner of the ``steganalysis`` kind (registered in meshmark.study.engine.TASK_KINDS)."""
    from ..study.engine import Summary
    t0 = time.perf_counter()
    unknown = set(raw) - {"kind", "study", "steganalysis"}
    if unknown:
        raise MeshError(f"steganalysis spec: unknown top-level keys {sorted(unknown)} (kind, study, steganalysis)")
    cfg = raw.get("steganalysis")
    if not isinstance(cfg, dict):
        raise MeshError("steganalysis spec: needs a [steganalysis] table")
    bad = set(cfg) - KEYS
    if bad:
        raise MeshError(f"steganalysis spec: unknown keys in [steganalysis]: {sorted(bad)} (known: {sorted(KEYS)})")
    parts = cfg.get("parts", ["protocol"])
    if not parts or set(parts) - PARTS:
        raise MeshError(f"steganalysis spec: parts must be a non-empty subset of {sorted(PARTS)}, got {parts}")
    out, base = pathlib.Path(out), pathlib.Path(base)
    out.mkdir(parents=True, exist_ok=True)
    (out / "spec.json").write_text(json.dumps({"kind": KIND, "spec": raw, "base": str(base)}, indent=1, default=str))
    S = Summary(planned=len(parts))
    L = [f"# {raw.get('study', {}).get('name', 'steganalysis')}"]
    if "protocol" in parts:
        L += ["\n## The ch. 8 protocol"] + protocol(cfg, base, out, log)
        S.ok += 1
    if "cho_table" in parts:
        from . import table62
        ct = cfg.get("cho_table", {})
        folders = _paths(base, ct.get("folders"), "cho_table.folders")
        L += ["\n## Table 6.2 (§6.4 detector)"] + table62.run(folders, out / "cho_table", int(ct.get("limit", 0)),
                                                            bool(ct.get("variants", True)), log)
        S.ok += 1
    S.ran = S.ok
    (out / "tables.md").write_text("\n".join(L) + "\n")
    log("\n".join(L))
    S.wall = time.perf_counter() - t0
    return S
