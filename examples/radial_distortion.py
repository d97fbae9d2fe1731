"""Embedding distortion of Yang's radial method for K = 200, 300, 400 (thesis Fig. 6.2), with Cho's
methods beside it.

    .venv/bin/python examples/radial_distortion.py [--out out/radial_distortion] [--messages 5] [--quick]

``--quick``: the Cow only, one message.

64 random bits (5 messages, averaged), the thesis' use (bit i in the i-th embeddable pair; n_thr from
Table 6.1 / the docs/radial.md rule, scaled by 400/K). Measures, relative to the bounding-box diagonal:
vertex RMSE, and the symmetric surface Hausdorff distance and surface RMS distance sampled by
pymeshlab's Metro-like ``get_hausdorff_distance`` (the thesis used Metro). Writes CSV + PNG.
"""
from __future__ import annotations

import argparse
import csv
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _radial_common import diag, load  # noqa: E402
from meshmark.watermark import cho, radial  # noqa: E402

MESHES = ["classic/bunny.obj", "classic/cow.obj", "classic/horse.ply", "classic/elephant.off", "classic/hand.obj"]


def surface_distances(V0, V1, F):
    """(Hausdorff, RMS) of the two surfaces, symmetric, sampled as Metro does (pymeshlab)."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(V0, F))
    ms.add_mesh(pymeshlab.Mesh(V1, F))
    n = 10 * len(V0)
    h = []
    for a, b in ((0, 1), (1, 0)):
        r = ms.get_hausdorff_distance(sampledmesh=a, targetmesh=b, samplevert=True, sampleface=True,
                                      sampleedge=True, samplenum=n)
        h.append((r["max"], r["RMS"]))
    return max(h[0][0], h[1][0]), float(np.sqrt(0.5 * (h[0][1] ** 2 + h[1][1] ** 2)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="out/radial_distortion")
    ap.add_argument("--messages", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="the Cow only, one message (tested)")
    a = ap.parse_args()
    meshes = ["classic/cow.obj"] if a.quick else MESHES
    if a.quick:
        a.messages = 1
    out = pathlib.Path(a.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    configs = [(f"Yang K={K}", (lambda K: lambda V, F, b: radial.embed_bits(V, F, b, K=K)[0])(K)) for K in (200, 300, 400)]
    configs += [("Cho mean a=0.04", lambda V, F, b: cho.embed_bits(V, F, b, method="mean")[0]),
                ("Cho variance a=0.16", lambda V, F, b: cho.embed_bits(V, F, b, method="variance")[0])]
    rows = []
    for rel in meshes:
        V, F = load(rel)
        d = diag(V)
        name = pathlib.Path(rel).stem
        for cname, emb in configs:
            vals = []
            for s in range(a.messages):
                bits = np.random.default_rng(s).integers(0, 2, 64)
                Vm = emb(V, F, bits)
                rmse = float(np.sqrt(((Vm - V) ** 2).sum(1).mean()))
                haus, srms = surface_distances(V, Vm, F)
                vals.append((rmse / d, srms / d, haus / d))
            r = dict(zip(["vertex_rmse_rel", "surface_rms_rel", "hausdorff_rel"], np.mean(vals, 0)))
            rows.append({"mesh": name, "method": cname, **r})
            print(f"{name:<10} {cname:<20} RMSE {r['vertex_rmse_rel']:.2e}  surface RMS {r['surface_rms_rel']:.2e}  "
                  f"Hausdorff {r['hausdorff_rel']:.2e}", flush=True)
    with open(out.with_suffix(".csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("\n| mesh | method | vertex RMSE / diag | surface RMS / diag | Hausdorff / diag |\n|---|---|---:|---:|---:|")
    for r in rows:
        print(f"| {r['mesh']} | {r['method']} | {r['vertex_rmse_rel']:.2e} | {r['surface_rms_rel']:.2e} | "
              f"{r['hausdorff_rel']:.2e} |")
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for rel in meshes:
        name = pathlib.Path(rel).stem
        ys = [r for r in rows if r["mesh"] == name and r["method"].startswith("Yang")]
        Ks = [int(r["method"].split("=")[1]) for r in ys]
        axes[0].plot(Ks, [r["surface_rms_rel"] for r in ys], "-o", label=name)
        axes[1].plot(Ks, [r["hausdorff_rel"] for r in ys], "-o", label=name)
    for ax, t in zip(axes, ["surface RMS / bbox diagonal", "Hausdorff / bbox diagonal"]):
        ax.set_xlabel("K")
        ax.set_ylabel(t)
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle("Yang's radial method, 64 bits: distortion vs K (thesis Fig. 6.2)")
    fig.tight_layout()
    fig.savefig(out.with_suffix(".png"), dpi=120)
    print(f"wrote {out.with_suffix('.csv')} and {out.with_suffix('.png')}")


if __name__ == "__main__":
    main()
