"""Figures 3.2, 4.2, 4.3, 5.4 and 5.5 of the thesis for any mesh (PNG + CSV per figure).

    .venv/bin/python examples/analysis_figures.py [MESH ...] [--out out/analysis_figures] [--seed 0]

Default mesh: ../shared/meshes/classic/bunny.obj. Per mesh (file stem as prefix):
* fig3_2: dis(M, M^t) for t = 0..64 (IEEE-754 double pattern, 3 dithers per level) with the logistic
  model fitted at t = 12..28, for the mean, area and dihedral weightings (the variances, Fig. 3.3, are
  in the CSV);
* fig4_3: E_mesh by E_min, E_appr, E_max (linear and exact E(theta)) against the measured mean
  normal change under centered uniform cubic noise of half-width l = 2^-(i+1) L and under the
  dithered quantizer at level i;
* fig5_4: the mean curvature change of the interior vertices for displacements of mean strength 2^-t L
  in the normal, tangential and random directions, with the eq. 5.2.4 line fitted over t >= 12.
Once: fig4_2 (E(theta) and its tangent l/2h) and fig5_5 (the hexagonal pyramid).
"""
from __future__ import annotations

import argparse
import math
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import SHARED, write_csv  # noqa: E402

import meshmark  # noqa: E402
from meshmark import analysis as A  # noqa: E402
from meshmark.attacks import mean_centroid_distance, noise  # noqa: E402
from meshmark.metrics import normal_degradation  # noqa: E402


def _plt():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def fig3_2(mesh, name, out, seed):
    plt = _plt()
    c = A.degradation_curve(mesh, range(65), seed=seed, repeats=3)
    model = A.degradation_model(mesh, seed=seed)
    t = c["t"]
    rows = []
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for ax, w in zip(axes, A.WEIGHTINGS):
        f = model[w]
        pred = A.logistic(t, f["a"], f["b"], f["C"])
        ax.plot(t, c[w], "b.-", label="dis (measured)")
        ax.plot(t, pred, "r-", label=f"D(t): a={f['a']:.2f} b={f['b']:.3f} C={f['C']:.3f}")
        ax.plot(A.FIT_LEVELS, f["samples"], "ko", mfc="none", label="fitted samples")
        ax.set_title(f"{name}: {w}")
        ax.set_xlabel("t (bits of the double kept)")
        ax.set_ylabel("radians")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / f"{name}_fig3_2.png", dpi=120)
    plt.close(fig)
    for j, tt in enumerate(t):
        rows.append({"t": int(tt), **{f"dis_{w}": c[w][j] for w in A.WEIGHTINGS},
                     **{f"var_{w}": c["variance"][w][j] for w in A.WEIGHTINGS},
                     **{f"model_{w}": float(A.logistic(tt, model[w]["a"], model[w]["b"], model[w]["C"]))
                        for w in A.WEIGHTINGS}})
    write_csv(rows, out / f"{name}_fig3_2.csv")


def fig4_2(out):
    plt = _plt()
    r = np.linspace(0, 2, 401)
    E = A.expected_normal_angle(r)
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8))
    for ax, lim in zip(axes, (2.0, 0.5)):
        sel = r <= lim
        ax.plot(r[sel], E[sel], "b-", label="E(theta), eq. 4.1.7/4.1.8")
        ax.plot(r[sel], r[sel] / 2, "r--", label="tangent l/2h")
        ax.set_xlabel("l/h")
        ax.set_ylabel("radians")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig4_2.png", dpi=120)
    plt.close(fig)
    write_csv([{"l_over_h": float(a), "E": float(b), "tangent": float(a / 2)} for a, b in zip(r, E)], out / "fig4_2.csv")


def fig4_3(mesh, name, out, seed, levels=range(6, 23)):
    plt = _plt()
    L = float(np.ptp(mesh.V, axis=0).max())
    d = mean_centroid_distance(mesh)
    i = np.array(list(levels))
    l = L * 2.0 ** -(i + 1.0)
    est = {f"{b}_{'exact' if ex else 'linear'}": A.mesh_expectation(mesh, l, b, exact=ex)
           for b in ("min", "appr", "max") for ex in (False, True)}
    uni = np.array([normal_degradation(mesh, noise(mesh, strength=float(x / d), seed=seed + k).V)
                    for k, x in enumerate(l)])
    dit = np.array([math.radians(A.psi(mesh, int(k), seed=seed)) for k in i])
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for key, style in (("min_linear", "g--"), ("appr_linear", "r--"), ("max_linear", "m--"),
                       ("min_exact", "g-"), ("appr_exact", "r-"), ("max_exact", "m-")):
        ax.semilogy(i, est[key], style, label=key.replace("_", " "))
    ax.semilogy(i, uni, "ko", label="measured: uniform cube noise")
    ax.semilogy(i, dit, "bx", label="measured: dithered quantizer")
    ax.set_xlabel("i (bits of the 32-bit fixed point kept)")
    ax.set_ylabel("mean normal change, radians")
    ax.set_title(name)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / f"{name}_fig4_3.png", dpi=120)
    plt.close(fig)
    write_csv([{"i": int(k), "l": float(x), **{kk: float(v[j]) for kk, v in est.items()},
                "measured_uniform": float(uni[j]), "measured_dither": float(dit[j])}
               for j, (k, x) in enumerate(zip(i, l))], out / f"{name}_fig4_3.csv")


def fig5_4(mesh, name, out, seed):
    plt = _plt()
    r = A.curvature_model(mesh, seed=seed)
    t = np.array(r["t"])
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for d, style in zip(A.DIRECTIONS, ("b", "g", "r")):
        k = np.array(r[d]["kappa_dif"])
        ax.plot(t, np.log2(k), style + "o", ms=3, label=f"{d}: a={r[d]['a']:.3f} b={r[d]['b']:.2f}")
        tt = t[t >= 12]
        ax.plot(tt, r[d]["a"] * tt + r[d]["b"], style + "-")
    ax.set_xlabel("t (mean strength 2^-t L)")
    ax.set_ylabel("log2 mean |kappa' - kappa|")
    ax.set_title(name)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / f"{name}_fig5_4.png", dpi=120)
    plt.close(fig)
    write_csv([{"t": int(x), **{d: r[d]["kappa_dif"][j] for d in A.DIRECTIONS}} for j, x in enumerate(t)],
              out / f"{name}_fig5_4.csv")


def fig5_5(out, seed):
    plt = _plt()
    p = A.pyramid_experiment(seed=seed)
    t = np.array(p["t"])
    fig, ax = plt.subplots(figsize=(6.5, 4.2))
    for d, style in (("normal", "b"), ("tangential", "g")):
        f = p["fit"][d]
        ax.plot(t, np.log2(p[d]), style + "o", ms=3, label=f"{d}: slope {f['a']:.3f}")
        tt = t[(t >= 2) & (t <= 20)]
        ax.plot(tt, f["a"] * tt + f["b"], style + "-")
    ax.set_xlabel("t (mean strength 2^-t, height = radius = 1)")
    ax.set_ylabel("log2 mean |kappa' - kappa| at the apex")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "fig5_5.png", dpi=120)
    plt.close(fig)
    write_csv([{"t": int(x), "normal": p["normal"][j], "tangential": p["tangential"][j]} for j, x in enumerate(t)],
              out / "fig5_5.csv")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("meshes", nargs="*", default=[str(SHARED / "classic" / "bunny.obj")])
    ap.add_argument("--out", default="out/analysis_figures")
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    fig4_2(out)
    fig5_5(out, args.seed)
    for path in args.meshes:
        mesh = meshmark.read_mesh(path)
        name = pathlib.Path(path).stem
        fig3_2(mesh, name, out, args.seed)
        fig4_3(mesh, name, out, args.seed)
        fig5_4(mesh, name, out, args.seed)
        print(f"{name}: figures written to {out}", flush=True)


if __name__ == "__main__":
    main()
