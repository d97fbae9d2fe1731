"""Invariance of every steganalysis feature component (issue 25; docs/steganalysis.md §2, "Invariance").

    nice -n 10 .venv/bin/python bench/steganalysis_invariance.py [--folders classic corpus corpus-large]
        [--sets yang208,lfs76s,nvt36s,lfs76,nvt36] [--out out/invariance] [--quick]

For every mesh and set: the largest change of any component, |dF| / (1 + |F|), under
  similarity   a random rotation with an axis flip, scale 3.7, a translation of ~3.7 mesh sizes,
  vertex_perm  a random vertex permutation,
  face_perm    a random face permutation with the corners of each face rotated,
  scale_1e-15  V * (1 + 1e-15);
and the storage test: the features of a moved copy (random rotation + translation, double) against
those of the same copy rounded to float32 (`float32`), set beside the change one embedding of each
registered stego method makes (`--marks`, on by default). The weakest mark is the method with the
smallest median (over meshes) of its median relative change over components; the criterion is, per
component, float32 change <= 0.1 x the median change of the weakest mark. Writes OUT/invariance.csv
(one row per mesh, set, transform), OUT/float32.csv (per set and component: the median change of each
method, the median and the maximum float32 change, their ratio) and prints the summary tables.
`--quick` runs three small meshes and no marks (a check that the script works, tested).
"""
from __future__ import annotations

import argparse
import csv
import pathlib
import sys
import time

import numpy as np

import meshmark
from meshmark.steganalysis import features as feat
from meshmark.steganalysis import protocol as P

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from _common import SHARED  # noqa: E402

QUICK = ["corpus/vhacd_eight.off", "corpus/thingi10k_1519468.stl", "corpus/c3d_alligator.obj"]


def rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q *= np.sign(np.diag(r))
    return q if np.linalg.det(q) > 0 else q @ np.diag([-1.0, 1, 1])


def transforms(V, T, rng):
    n = len(V)
    size = np.ptp(V, axis=0).max()
    R = rotation(rng) @ np.diag([-1.0, 1, 1])
    yield "similarity", (V @ R.T) * 3.7 + rng.normal(size=3) * size * 3.7, T
    pv = rng.permutation(n)
    inv = np.empty_like(pv)
    inv[pv] = np.arange(n)
    yield "vertex_perm", V[pv], inv[T]
    yield "face_perm", V, np.roll(T[rng.permutation(len(T))], 1, axis=1)
    yield "scale_1e-15", V * (1 + 1e-15), T


def rel(a, b):
    return np.abs(a - b) / (1 + np.abs(a))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--folders", nargs="+", default=["classic", "corpus"])
    ap.add_argument("--sets", default="yang208,lfs76s,nvt36s,lfs76,nvt36")
    ap.add_argument("--out", default="out/invariance")
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--no-marks", action="store_true")
    ap.add_argument("--limit", type=int, default=0)
    a = ap.parse_args(argv)
    sets = a.sets.split(",")
    files = [SHARED / p for p in QUICK] if a.quick else P.mesh_files([SHARED / f for f in a.folders])
    if a.limit:
        files = files[: a.limit]
    marks = not (a.no_marks or a.quick)
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows, f32 = [], {s: [] for s in sets}
    dmark = {s: {} for s in sets}
    t0 = time.perf_counter()
    for k, p in enumerate(files):
        name = str(p.relative_to(SHARED))
        try:
            m = meshmark.read_mesh(p)
            V, T = m.V, np.ascontiguousarray(m.triangles)
            F0 = {s: feat.features((V, T), s) for s in sets}
        except meshmark.MeshError as exc:
            print(f"{name}: skipped ({exc})", file=sys.stderr)
            continue
        rng = np.random.default_rng(k)
        for tname, Vt, Tt in transforms(V, T, rng):
            for s in sets:
                r = rel(F0[s], feat.features((Vt, np.ascontiguousarray(Tt)), s))
                j = int(np.argmax(r))
                rows.append({"mesh": name, "set": s, "transform": tname, "max_rel": float(r[j]),
                             "component": feat.feature_names(s)[j]})
        Vm = V @ rotation(rng).T + rng.normal(size=3) * np.ptp(V, axis=0).max()
        for s in sets:
            Fm = feat.features((Vm, T), s)
            f32[s].append(np.abs(feat.features((Vm.astype(np.float32).astype(np.float64), T), s) - Fm))
            rows.append({"mesh": name, "set": s, "transform": "float32", "max_rel": float(rel(Fm, Fm + f32[s][-1]).max()),
                         "component": feat.feature_names(s)[int(np.argmax(f32[s][-1]))]})
        if marks:
            for j, (meth, (embed, _)) in enumerate(P.STEGO_METHODS.items()):
                try:
                    Vs = np.asarray(embed(m, np.random.default_rng([k, j])))
                except meshmark.MeshError:
                    continue
                for s in sets:
                    dmark[s].setdefault(meth, []).append(np.abs(feat.features((Vs, T), s) - F0[s]))
        print(f"[{k + 1}/{len(files)}] {name} {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    with open(out / "invariance.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print("\n| set | transform | meshes | worst max |dF|/(1+|F|) | mesh | component | meshes > 1e-6 |")
    print("|---|---|---:|---:|---|---|---:|")
    for s in sets:
        for t in ("similarity", "vertex_perm", "face_perm", "scale_1e-15", "float32"):
            rs = [r for r in rows if r["set"] == s and r["transform"] == t]
            if not rs:
                continue
            worst = max(rs, key=lambda r: r["max_rel"])
            print(f"| {s} | {t} | {len(rs)} | {worst['max_rel']:.2e} | {worst['mesh']} | {worst['component']} | "
                  f"{sum(r['max_rel'] > 1e-6 for r in rs)} |")
    if not marks:
        return 0
    print("\n| set | weakest mark | components with max float32 change <= 0.1 x its median change | "
          "with median float32 change <= 0.1 x | worst component (max float32 / median mark) |")
    print("|---|---|---:|---:|---|")
    crow = []
    for s in sets:
        med = {meth: np.median(np.vstack(d), axis=0) for meth, d in dmark[s].items() if len(d) >= 5}
        X = np.vstack(f32[s])
        weakest = min(med, key=lambda meth: float(np.median(med[meth])))
        mw = med[weakest]
        ratio_max = X.max(0) / np.maximum(mw, 1e-300)
        ratio_med = np.median(X, 0) / np.maximum(mw, 1e-300)
        names = feat.feature_names(s)
        j = int(np.argmax(ratio_max))
        print(f"| {s} | {weakest} | {(ratio_max <= 0.1).sum()}/{len(mw)} | {(ratio_med <= 0.1).sum()}/{len(mw)} | "
              f"{names[j]} {ratio_max[j]:.3g} |")
        for c in range(len(mw)):
            crow.append({"set": s, "component": names[c], "weakest": weakest, "weakest_median_change": float(mw[c]),
                         "float32_median": float(np.median(X[:, c])), "float32_max": float(X[:, c].max()),
                         "ratio_max": float(ratio_max[c]), "ratio_median": float(ratio_med[c]),
                         **{f"median_{meth}": float(v[c]) for meth, v in med.items()}})
    with open(out / "float32.csv", "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(crow[0]))
        w.writeheader()
        w.writerows(crow)
    return 0


if __name__ == "__main__":
    sys.exit(main())
