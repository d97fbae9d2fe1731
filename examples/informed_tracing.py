"""Informed tracing, measured: copies issued with default settings, each attacked and traced with the
original, on every shared classic and corpus mesh with at least 5,000 welded vertices.

    .venv/bin/python examples/informed_tracing.py [--quick] [--copies 100] [--seeds 3]
        [--meshes bunny,cat] [--wrong-keys 10] [--out examples/out/informed]

Per mesh: ``tracing.issue`` of --copies copies (timed; distortion of every copy against the original:
vertex RMSE and Hausdorff distance over the bounding-box diagonal, mean normal change in degrees, also
for copies issued without the pattern, today's default); then for each attack of ATTACKS and each
seed s, copy number (s * 37 + attack index) mod copies is attacked and traced with ``original=``:
right copy / wrong copy / none, the informed z and the evidence used. False alarms: the unmarked
original under every attack (traced against its registry), each attacked copy against another
asset's registry and original, and --wrong-keys wrong keys per trial (first seed of each attack
unless --all-false-alarms) (the informed statistic is
recomputed for the wrong key's fields on the same residual, the blind test with the full trace for
the first wrong key). Writes trials.csv, distortion.csv and summary.md in --out. --quick: one small
mesh, 10 copies, one seed, a few attacks (the test suite runs it).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import meshmark  # noqa: E402
from meshmark import MeshError  # noqa: E402
from meshmark import attacks  # noqa: E402
from meshmark.attacks import bend  # noqa: E402
from meshmark.watermark import informed, tracing  # noqa: E402

from _common import SHARED, MESH_SUFFIXES, write_csv  # noqa: E402


def remesh(m, seed=0):
    """Isotropic remeshing at the mean edge length (pymeshlab; meshmark gains --type remesh separately)."""
    import pymeshlab

    ms = pymeshlab.MeshSet()
    T = m.triangles
    ms.add_mesh(pymeshlab.Mesh(m.V, T))
    E = m.V[T[:, [0, 1, 2]]] - m.V[T[:, [1, 2, 0]]]
    L = float(np.linalg.norm(E, axis=2).mean())
    ms.meshing_isotropic_explicit_remeshing(iterations=3, targetlen=pymeshlab.PureValue(L))
    out = ms.current_mesh()
    return meshmark.Mesh(out.vertex_matrix(), out.face_matrix().astype(np.int32))


def _srt(m, seed):
    m = attacks.similarity(m, seed=seed)
    m = attacks.reorder(m, seed=seed)
    return attacks.file_roundtrip(m, format="obj")


def _crop(fr):
    dirs = [(1, 0, 0), (0, 1, 0), (0, 0, 1)]
    return lambda m, s: attacks.crop(m, fraction=fr, normal=dirs[s % 3])


ATTACKS = {
    "noise 0.1 %": lambda m, s: attacks.noise(m, strength=0.001, seed=s),
    "noise 0.25 %": lambda m, s: attacks.noise(m, strength=0.0025, seed=s),
    "smooth x10": lambda m, s: attacks.smooth(m, lam=0.02, iterations=10),
    "smooth x30": lambda m, s: attacks.smooth(m, lam=0.02, iterations=30),
    "quantize 10": lambda m, s: attacks.quantize(m, bits=10),
    "quantize 8": lambda m, s: attacks.quantize(m, bits=8),
    "simplify 50 %": lambda m, s: attacks.simplify(m, fraction=0.5),
    "simplify 25 %": lambda m, s: attacks.simplify(m, fraction=0.25),
    "crop 10 %": _crop(0.1),
    "crop 30 %": _crop(0.3),
    "loop subdivision": lambda m, s: attacks.subdivide(m, scheme="loop"),
    "isotropic remesh": lambda m, s: remesh(m, s),
    "bend 30": lambda m, s: bend(m, degrees=30),
    "bend 60": lambda m, s: bend(m, degrees=60),
    "similarity+reorder+OBJ": _srt,
    "chain": lambda m, s: _srt(attacks.noise(attacks.simplify(bend(m, degrees=30), fraction=0.5), strength=0.001,
                                             seed=s), s),
}
QUICK = ("noise 0.1 %", "simplify 25 %", "similarity+reorder+OBJ")


def test_set(names=None):
    out = []
    for sub in ("classic", "corpus"):
        for p in sorted((SHARED / sub).iterdir()):
            if p.suffix.lower() not in MESH_SUFFIXES:
                continue
            if names and not any(n in p.stem for n in names):
                continue
            m = meshmark.weld_vertices(meshmark.read_mesh(p)).mesh
            if m.n_vertices >= 5000:
                out.append((p, m))
    return out


def distortion(orig, V):
    """Vertex RMSE and symmetric Hausdorff distance over the diagonal, mean normal change in degrees."""
    from meshmark import metrics

    d = metrics.bbox_diagonal(orig)
    mv = orig.with_vertices(V)
    h = max(metrics.hausdorff_distance(orig, mv)["upper"], metrics.hausdorff_distance(mv, orig)["upper"])
    return {"rmse": metrics.vertex_rmse(orig.V, V) / d, "hausdorff": h / d,
            "normal_deg": float(metrics.normal_degradation(orig.V, V, orig, degrees=True))}


def run_mesh(path, mesh, a, rows, drows, other):
    name = path.stem
    tmp = tempfile.mkdtemp(prefix="mm-inf-")
    reg = os.path.join(tmp, "r.sqlite")
    t = time.perf_counter()
    copies = tracing.issue(mesh, key="studio", registry=reg, n_copies=a.copies, original=str(path))
    t_issue = time.perf_counter() - t
    reg0 = os.path.join(tmp, "r0.sqlite")
    base = tracing.issue(mesh, key="studio", registry=reg0, n_copies=min(3, a.copies), informed=False)
    for k, (cid, V) in enumerate(copies[:3]):
        drows.append({"mesh": name, "kind": "blind+pattern", "copy": cid, **distortion(mesh, V)})
        drows.append({"mesh": name, "kind": "blind (today)", "copy": base[k][0], **distortion(mesh, base[k][1])})
        with tracing.Registry(reg) as R:
            (_, setup, _), = R.assets()
        orig = informed.Original(mesh, setup["informed"])
        pat = orig.marked(orig.patterns([informed.copy_seed("studio", tracing.source_digest(mesh), cid)])[:, 0])
        drows.append({"mesh": name, "kind": "pattern alone", "copy": cid, **distortion(mesh, pat)})
    print(f"{name}: {mesh.n_vertices} vertices, issued {a.copies} copies in {t_issue:.1f} s", flush=True)
    names = QUICK if a.quick else tuple(ATTACKS)
    wrong_keys = [f"wrong-{i}" for i in range(a.wrong_keys)]
    for ai, an in enumerate(names):
        for s in range(a.seeds):
            j = (s * 37 + ai) % len(copies)
            cid, V = copies[j]
            try:
                sus = ATTACKS[an](mesh.with_vertices(V), s)
            except Exception as exc:  # noqa: BLE001 - an attack that fails on this mesh is reported
                rows.append({"mesh": name, "attack": an, "seed": s, "kind": "copy", "truth": cid, "named": "ERROR",
                             "z": np.nan, "p": np.nan, "evidence": str(exc)[:60], "time": 0})
                continue
            t = time.perf_counter()
            r = tracing.trace(sus, registry=reg, original=mesh)
            dt = time.perf_counter() - t
            inf = r["informed"] or {}
            rows.append({"mesh": name, "attack": an, "seed": s, "kind": "copy", "truth": cid, "named": r["copy"],
                         "z": inf.get("z", np.nan), "p": r["p_false_alarm"], "evidence": r["evidence"],
                         "blind_p": r["blind"]["p_false_alarm"], "corr": inf.get("correspondence", ""),
                         "n_used": inf.get("n_used", 0), "time": dt})
            if s > 0 and not a.all_false_alarms:
                continue
            # unmarked original under the same attack
            un = ATTACKS[an](mesh, s)
            r0 = tracing.trace(un, registry=reg, original=mesh)
            rows.append({"mesh": name, "attack": an, "seed": s, "kind": "unmarked", "truth": "", "named": r0["copy"],
                         "z": (r0["informed"] or {}).get("z", np.nan), "p": r0["p_false_alarm"],
                         "evidence": r0["evidence"], "time": 0})
            # wrong keys: full trace for the first, the informed statistic for the rest
            if wrong_keys:
                try:  # the registry keeps the key's hash: a wrong key is refused before any reading
                    rk = tracing.trace(sus, registry=reg, original=mesh, key=wrong_keys[0])
                except MeshError as exc:
                    assert "wrong key" in str(exc), exc
                    rk = {"copy": None, "informed": None, "p_false_alarm": 1.0, "evidence": "refused"}
                rows.append({"mesh": name, "attack": an, "seed": s, "kind": "wrong key", "truth": "",
                             "named": rk["copy"], "z": (rk["informed"] or {}).get("z", np.nan),
                             "p": rk["p_false_alarm"], "evidence": rk["evidence"], "time": 0})
                extra = wrong_key_z(sus, orig, mesh, copies, wrong_keys[1:])
                for wk, z in extra:
                    p = min(1.0, 2 * len(copies) * informed.tail_probability(z))
                    rows.append({"mesh": name, "attack": an, "seed": s, "kind": "wrong key (informed)", "truth": "",
                                 "named": "WRONG" if p < 1e-6 else None, "z": z, "p": p, "evidence": "informed",
                                 "time": 0})
            # another asset's registry and original
            if other is not None:
                ro = tracing.trace(sus, registry=other[0], original=other[1])
                rows.append({"mesh": name, "attack": an, "seed": s, "kind": "other registry", "truth": "",
                             "named": ro["copy"], "z": (ro["informed"] or {}).get("z", np.nan),
                             "p": ro["p_false_alarm"], "evidence": ro["evidence"], "time": 0})
        done = [r for r in rows if r["mesh"] == name and r["attack"] == an and r["kind"] == "copy"]
        ok = sum(r["named"] == r["truth"] for r in done)
        print(f"  {an:24s} right {ok}/{len(done)}  z {', '.join('%.1f' % r['z'] for r in done)}  "
              f"{np.mean([r['time'] for r in done]):.2f} s/trace", flush=True)
    return reg, mesh, t_issue


def wrong_key_z(sus, orig, mesh, copies, keys):
    """The best informed z over the copies' fields under each wrong key, on the suspect's residual."""
    if not keys:
        return []
    det = informed.detect(sus, orig, [], return_u=True)
    u = det["u"]
    nu = float(np.linalg.norm(u))
    sha = tracing.source_digest(mesh)
    out = []
    for k in keys:
        seeds = [informed.copy_seed(k, sha, c) for c, _ in copies]
        z = meshmark._core.keyed_gaussian_dots(u, seeds) / nu if nu > 0 else np.zeros(len(seeds))
        out.append((k, float(np.max(z))))
    return out


def summary(rows, drows, times, path):
    import collections

    lines = ["| attack | trials | right | wrong | none | median z | min z |", "|---|---|---|---|---|---|---|"]
    by = collections.defaultdict(list)
    for r in rows:
        if r["kind"] == "copy":
            by[r["attack"]].append(r)
    for an, rs in by.items():
        zs = [r["z"] for r in rs if np.isfinite(r["z"])]
        right = sum(r["named"] == r["truth"] for r in rs)
        wrong = sum(r["named"] not in (None, r["truth"]) for r in rs)
        lines.append(f"| {an} | {len(rs)} | {100 * right / len(rs):.1f} % | {wrong} | {len(rs) - right - wrong} | "
                     f"{np.median(zs) if zs else float('nan'):.1f} | {min(zs) if zs else float('nan'):.1f} |")
    lines += ["", "| false-alarm trials | trials | named a copy |", "|---|---|---|"]
    for kind in ("unmarked", "wrong key", "wrong key (informed)", "other registry"):
        rs = [r for r in rows if r["kind"] == kind]
        lines.append(f"| {kind} | {len(rs)} | {sum(r['named'] is not None for r in rs)} |")
    lines += ["", "| distortion (max over copies and meshes) | RMSE / diag | Hausdorff / diag | mean normal change (deg) |",
              "|---|---|---|---|"]
    for kind in ("pattern alone", "blind (today)", "blind+pattern"):
        rs = [r for r in drows if r["kind"] == kind]
        if rs:
            lines.append(f"| {kind} | {max(r['rmse'] for r in rs):.2e} | {max(r['hausdorff'] for r in rs):.2e} | "
                         f"{max(r['normal_deg'] for r in rs):.3f} |")
    lines += ["", "| mesh | vertices | issue time (s) |", "|---|---|---|"] + [f"| {m} | {n} | {t:.1f} |" for m, n, t in times]
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    print("\n".join(lines))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--copies", type=int, default=100)
    ap.add_argument("--seeds", type=int, default=3)
    ap.add_argument("--meshes", default="")
    ap.add_argument("--wrong-keys", type=int, default=10)
    ap.add_argument("--all-false-alarms", action="store_true",
                    help="false-alarm trials for every seed (default: the first seed of each attack)")
    ap.add_argument("--out", default=os.path.join(HERE, "out", "informed"))
    a = ap.parse_args(argv)
    if a.quick:
        a.copies, a.seeds, a.wrong_keys = min(a.copies, 10), 1, min(a.wrong_keys, 2)
        a.meshes = a.meshes or "cat-low"
    meshes = test_set([s for s in a.meshes.split(",") if s] or None)
    if not meshes:
        raise SystemExit("no mesh of the test set matches --meshes")
    os.makedirs(a.out, exist_ok=True)
    rows, drows, times, other = [], [], [], None
    for path, mesh in meshes:
        reg, m, t_issue = run_mesh(path, mesh, a, rows, drows, other)
        other = (reg, m)
        times.append((path.stem, mesh.n_vertices, t_issue))
        write_csv(rows, os.path.join(a.out, "trials.csv"))
        write_csv(drows, os.path.join(a.out, "distortion.csv"))
    summary(rows, drows, times, os.path.join(a.out, "summary.md"))
    bad = sum(r["named"] not in (None, r.get("truth") or None) for r in rows if r["kind"] != "copy") + \
        sum(r["named"] not in (None, r["truth"]) for r in rows if r["kind"] == "copy")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
