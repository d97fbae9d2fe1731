"""Standard figures and the CSV summary of a study's results (``meshmark study plot RESULTS``).

* ``summary.csv``: one row per (method, attack) with the number of tasks, of ok rows and mesh errors,
  and the mean of every numeric measurement column over the ok rows (timings included);
* ``cdr_vs_strength.png``: mean CDR against the attack level (the first numeric grid or random
  parameter of the attack entry, or ``level = "name"``), one panel per attack, one line per method;
* ``correlation_vs_strength.png``: the same for C of eq. 6.3.11 (the ``correlation`` measurement of
  the raw-bits method kinds: thesis Figs. 6.6-6.8);
* ``detection_vs_deformation.png``: detection rate and mean CDR against the bend angle (``bend`` /
  ``blender_bend`` attacks), one line per method;
* ``distortion_vs_strength.png`` (attack-only studies, every method ``none``): RMSE, Hausdorff and
  normal degradation against the attack level, one line per mesh;
* ``capacity_vs_size.png``: capacity (carrier bits) against the vertex count of the mesh, per method.

A figure whose data the study does not have is not written (the list of files written is returned).
"""
from __future__ import annotations

import csv
import json
import pathlib

import numpy as np

from .._core import MeshError
from .engine import load_results

DEFORM = ("bend", "blender_bend")


def _rows(results):
    return load_results(results).to_pylist()


def summary(rows) -> list:
    groups: dict = {}
    for r in rows:
        groups.setdefault((r["method"], r["attack"]), []).append(r)
    skip = {"seed", "attempt", "attack_level", "mesh_vertices", "mesh_faces"}
    num = [k for k, v in rows[0].items() if k not in skip
           and any(isinstance(r.get(k), (int, float)) and r.get(k) is not None for r in rows)] if rows else []
    out = []
    for (m, a), rs in groups.items():
        ok = [r for r in rs if r["status"] == "ok"]
        d = {"method": m, "attack": a, "attack_level": rs[0]["attack_level"], "tasks": len(rs), "ok": len(ok),
             "mesh_error": sum(r["status"] == "mesh_error" for r in rs), "error": sum(r["status"] == "error" for r in rs)}
        for k in num:
            vals = [float(r[k]) for r in ok if r.get(k) is not None and not isinstance(r.get(k), str)]
            d[k] = float(np.mean(vals)) if vals else None
        out.append(d)
    return out


def _attack_name(r) -> str:
    ch = json.loads(r["attack_chain"]) if r.get("attack_chain") else []
    return ch[0][0] if len(ch) == 1 else ("none" if not ch else "chain")


def plot(results, out=None, overwrite: bool = False) -> list:
    """Write the figures and summary.csv into ``out`` (default RESULTS/plots); a folder that already
    holds a summary.csv is written into only with ``overwrite=True`` (MeshError otherwise)."""
    out = pathlib.Path(out) if out else pathlib.Path(results) / "plots"
    if out.exists() and not out.is_dir():
        raise MeshError(f"--out {out} is a file; give a folder for the figures")
    if not overwrite and (out / "summary.csv").exists():
        raise MeshError(f"{out} already holds the figures of a study plot ({out / 'summary.csv'}); "
                        "pass --force to overwrite them")
    from ..optional import pyplot
    plt = pyplot("meshmark study plot")

    out.mkdir(parents=True, exist_ok=True)
    rows = _rows(results)
    written = []
    summ = summary(rows)
    with open(out / "summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(summ[0]))
        w.writeheader()
        w.writerows(summ)
    written.append(out / "summary.csv")
    ok = [r for r in rows if r["status"] == "ok"]
    methods = list(dict.fromkeys(r["method"] for r in ok if r["method_name"] != "none"))

    def mean_by(rs, key, value):
        d: dict = {}
        for r in rs:
            if r.get(value) is not None and r.get(key) is not None:
                d.setdefault(r[key], []).append(float(r[value]))
        ks = sorted(d)
        return ks, [float(np.mean(d[k])) for k in ks]

    def panels(metric, ylabel, ylim, fname, rs_all, xlabel="attack level"):
        """mean ``metric`` against the attack level, one panel per attack name, one line per method"""
        by_attack: dict = {}
        for r in rs_all:
            if r.get(metric) is not None and r.get("attack_level") is not None:
                by_attack.setdefault(_attack_name(r), []).append(r)
        if not by_attack or not methods:
            return
        n = len(by_attack)
        fig, axes = plt.subplots(1, n, figsize=(4.2 * n, 3.6), squeeze=False)
        for ax, (att, rs) in zip(axes[0], sorted(by_attack.items())):
            for m in methods:
                x, y = mean_by([r for r in rs if r["method"] == m], "attack_level", metric)
                if x:
                    ax.plot(x, y, "-o", label=m, ms=4)
            ax.set_title(att)
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
            ax.set_ylim(*ylim)
            ax.grid(alpha=0.3)
        axes[0][0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / fname, dpi=110)
        plt.close(fig)
        written.append(out / fname)

    plain = [r for r in ok if _attack_name(r) not in DEFORM]
    deform = [r for r in ok if _attack_name(r) in DEFORM]
    # CDR (and C of eq. 6.3.11 for the raw-bits kinds) against strength, one panel per attack name
    panels("cdr", "mean CDR", (0.4, 1.02), "cdr_vs_strength.png", plain)
    panels("correlation", "mean correlation C (eq. 6.3.11)", (-0.2, 1.05), "correlation_vs_strength.png", plain)
    # detection rate and CDR against deformation
    dr = [r for r in deform if r.get("detected") is not None]
    if dr:
        fig, axes = plt.subplots(1, 2, figsize=(10, 3.6))
        for ax, (col, lab, lim) in zip(axes, (("detected", "detection rate", (-0.02, 1.02)),
                                              ("cdr", "mean CDR", (0.4, 1.02)))):
            for m in methods:
                x, y = mean_by([r for r in dr if r["method"] == m], "attack_level", col)
                if x:
                    ax.plot(x, y, "-o", label=m)
            ax.set_xlabel("bend (degrees)")
            ax.set_ylabel(lab)
            ax.set_ylim(*lim)
            ax.grid(alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "detection_vs_deformation.png", dpi=110)
        plt.close(fig)
        written.append(out / "detection_vs_deformation.png")
    # attack-only studies (no method): the distortion of each attack against its level, per mesh
    if not methods:
        dist = [r for r in plain if r.get("attack_level") is not None]
        cols = [c for c in ("rmse_rel", "hausdorff_rel", "normal_deg_mean") if any(r.get(c) is not None for r in dist)]
        if cols:
            meshes = list(dict.fromkeys(r["mesh"] for r in dist))
            atts = sorted({_attack_name(r) for r in dist})
            fig, axes = plt.subplots(len(cols), len(atts), figsize=(3.6 * len(atts), 3.0 * len(cols)), squeeze=False)
            for i, c in enumerate(cols):
                for j, att in enumerate(atts):
                    ax = axes[i][j]
                    for mesh in meshes:
                        x, y = mean_by([r for r in dist if r["mesh"] == mesh and _attack_name(r) == att],
                                       "attack_level", c)
                        if x and any(v > 0 for v in y):
                            ax.plot(x, y, "-o", ms=3, label=pathlib.Path(mesh).stem)
                    ax.set_title(att, fontsize=9)
                    ax.set_ylabel(c, fontsize=8)
                    if c != "normal_deg_mean" and ax.has_data():
                        ax.set_yscale("log")
                    ax.grid(alpha=0.3)
            axes[0][0].legend(fontsize=6)
            fig.tight_layout()
            fig.savefig(out / "distortion_vs_strength.png", dpi=100)
            plt.close(fig)
            written.append(out / "distortion_vs_strength.png")
    # capacity against size
    cr = {}
    for r in ok:
        if r.get("capacity") is not None:
            cr[(r["method"], r["mesh"])] = (r["mesh_vertices"], r["capacity"])
    if cr:
        fig, ax = plt.subplots(figsize=(5.5, 4))
        for m in methods:
            pts = [v for (mm, _), v in cr.items() if mm == m]
            if pts:
                x, y = zip(*pts)
                ax.scatter(x, y, s=10, label=m, alpha=0.7)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("vertices")
        ax.set_ylabel("capacity (carrier bits)")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "capacity_vs_size.png", dpi=110)
        plt.close(fig)
        written.append(out / "capacity_vs_size.png")
    return [str(p) for p in written]
