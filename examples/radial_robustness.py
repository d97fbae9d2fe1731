"""Robustness of Yang's radial method vs Cho's mean (and variance) method, thesis Figs. 6.6-6.8, 6.11.

    .venv/bin/python examples/radial_robustness.py [--out out/radial_robustness] [--study-out DIR]
                                                   [--workers N] [--quick]

``--quick``: the same methods and attacks on the Cow only, seed 0.

The study is examples/studies/radial_robustness.toml (meshmark.study; rerunning resumes from
--study-out): the thesis' own use of each method (raw bits, no key: the ``radial-bits`` and
``cho-*-bits`` method kinds). Yang K = 400, n_thr from Table 6.1 or the docs/radial.md rule, one bit in
*every* embeddable pair as §6.1.2 says ("hide a watermark bit w_i into each embeddable pair": 199 bits
on the Bunny), and, for comparison with the earlier runs, 64 bits in the first 64 embeddable pairs;
Cho alpha = 0.04 (mean) / 0.16 (variance), 64 bins = 64 bits, delta_k = 0.001, as published (no
guard, no re-synchronisation). Random messages, one per seed (``default_rng(seed)``). Attacks of
meshmark.attacks: additive noise A = 0.05/0.10/0.25/0.50 % of the mean distance to the centroid
(eq. 6.3.12, seeded by the task's seed), Laplacian smoothing lambda = 0.02 for 10/30/50 iterations,
quantization to 10/9/8 bits. Metric: correlation C (eq. 6.3.11) and CDR, mean of the seeds; the
embedding distortion (vertex RMSE / bbox diagonal) of each method is reported beside them. Models:
Bunny and Cow of Table 6.1 (Rabbit, Venus and Dragon are not in ../shared/meshes), and Horse,
Elephant and Hand. Writes <out>.csv and <out>.png and prints the tables.
"""
from __future__ import annotations

import argparse
import csv
import pathlib

import numpy as np

from meshmark.study import load_results, load_spec, run

SPEC = pathlib.Path(__file__).resolve().parent / "studies" / "radial_robustness.toml"
FIG_YANG, FIG_CHO = "Yang K=400 all pairs", "Cho mean a=0.04"


def table_rows(study_out, sp=None):
    """One row per (mesh, method, attack): the means over the seeds, in the spec's order."""
    sp = sp or load_spec(SPEC)
    by: dict = {}
    for r in sorted(load_results(study_out).to_pylist(), key=lambda r: r["seed"]):
        if r["status"] != "ok":
            raise SystemExit(f"{r['mesh']} {r['method']} {r['attack']} seed {r['seed']}: {r['status']}: {r['error']}")
        by.setdefault((r["mesh"], r["method"], r["attack"]), []).append(r)
    rows = []
    for mesh, _ in sp.meshes:
        name = pathlib.Path(mesh).stem
        for mv in sp.methods:
            rmse = float(np.mean([r["embed_rmse_rel"] for r in by[(mesh, mv.label, "none")]]))
            for av in sp.attacks:
                rs = by[(mesh, mv.label, av.label)]
                c, d = np.mean([(r["correlation"], r["cdr"]) for r in rs], axis=0)
                level = 0 if av.level is None else av.level
                if av.label.startswith("noise"):
                    level = round(level * 100, 10)  # in percent, as the thesis writes A
                rows.append({"mesh": name, "method": mv.label, "bits": rs[0]["payload_bits"], "rmse_diag": rmse,
                             "attack": av.label, "level": int(level) if float(level).is_integer() and level >= 1 else level,
                             "C": float(c), "CDR": float(d)})
    return rows, [m.label for m in sp.methods], [a.label for a in sp.attacks]


def print_tables(rows, methods, atts):
    meshes = list(dict.fromkeys(r["mesh"] for r in rows))
    get = {(r["mesh"], r["method"], r["attack"]): r for r in rows}
    print("| mesh | method | bits | RMSE/diag | " + " | ".join(atts) + " |\n|---|---|---:|---:|" + "---:|" * len(atts))
    for name in meshes:
        for mname in methods:
            cells = [get[(name, mname, att)] for att in atts]
            print(f"| {name} | {mname} | {cells[0]['bits']} | {cells[0]['rmse_diag']:.2e} | "
                  + " | ".join(f"{c['C']:.2f}" for c in cells) + " |")
    # Fig. 6.11: is Yang (every embeddable pair, as §6.1.2) more robust than Cho's mean method?
    print("\nFig. 6.11 (noise, smoothing): C(Yang all pairs) - C(Cho mean); + = Yang more robust")
    fig_atts = [att for att in atts if att.startswith(("noise", "smooth"))]
    print("| mesh | " + " | ".join(fig_atts) + " |\n|---|" + "---:|" * len(fig_atts))
    wins = 0
    for name in meshes:
        diffs = []
        for att in fig_atts:
            cy, cc = get[(name, FIG_YANG, att)]["C"], get[(name, FIG_CHO, att)]["C"]
            diffs.append(cy - cc)
            wins += cy > cc
        print(f"| {name} | " + " | ".join(f"{d:+.2f}" for d in diffs) + " |")
    print(f"Yang ahead in {wins} of {len(fig_atts) * len(meshes)} (mesh, attack) cells")


def plot(rows, methods, path, n_seeds):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    groups = [("noise", "noise A (%)"), ("smooth", "smoothing iterations (lambda 0.02)"), ("quantize", "quantisation bits")]
    styles = dict(zip(methods, ["-o", "-.x", "--s", ":^", "-v", "--d"]))
    for ax, (g, label) in zip(axes, groups):
        for name in dict.fromkeys(r["mesh"] for r in rows):
            for mname in methods:
                pts = sorted((r["level"], r["C"]) for r in rows if r["mesh"] == name and r["method"] == mname
                             and r["attack"].startswith(g))
                ax.plot(*zip(*pts), styles[mname], label=f"{name} {mname}", alpha=0.8)
        ax.set_xlabel(label)
        ax.set_ylabel("correlation C")
        ax.set_ylim(-0.2, 1.05)
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=6, ncol=2)
    fig.suptitle("Robustness, mean of %d seeds (thesis Figs. 6.6-6.8, 6.11)" % n_seeds)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="out/radial_robustness", help="CSV / PNG prefix")
    ap.add_argument("--study-out", default="out/radial_robustness_study", help="study results (resumed if present)")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--quick", action="store_true", help="the Cow only, seed 0 (the test suite runs it)")
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from _common import quick_spec
    sp = quick_spec(SPEC, ["../../../shared/meshes/classic/cow.obj"]) if a.quick else load_spec(SPEC)
    run(sp, a.study_out, workers=0 if a.quick and a.workers is None else a.workers, progress=False)
    rows, methods, atts = table_rows(a.study_out, sp)
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print_tables(rows, methods, atts)
    plot(rows, methods, out.with_suffix(".png"), len(sp.seeds))
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
