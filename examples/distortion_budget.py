"""Distortion budget of issued copies (issue 22): every copy issued with default settings, against
vertex RMSE <= 1e-4, Hausdorff <= 5e-4 (both of the bounding-box diagonal) and mean normal change
<= 0.25 degrees, on every shared classic and corpus mesh with at least 5,000 welded vertices.

    .venv/bin/python examples/distortion_budget.py [--copies 100] [--baseline 10] [--meshes bunny,cat]
        [--out examples/out/distortion_budget] [--quick]

Per mesh: ``tracing.issue`` of --copies copies with the defaults (blind codeword + informed pattern),
and of --baseline copies without the pattern (``informed=False``: the blind mark alone, the default
before informed tracing); for every copy, against the welded original (meshmark.metrics): vertex RMSE
and the symmetric Hausdorff distance (upper bound of ``hausdorff_distance``) over the diagonal, and
the mean normal change (``normal_degradation``, degrees). Writes copies.csv (one row per copy, after
each mesh) and summary.md (per mesh: the maxima, and how many copies are within all three limits).
A mesh that cannot be issued is listed with the error. --quick: the odedstein cat, 3 copies and 1
without the pattern (the test suite runs it).
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from meshmark import MeshError  # noqa: E402
from meshmark.watermark import tracing  # noqa: E402

from _common import write_csv  # noqa: E402
from informed_tracing import distortion, test_set  # noqa: E402

BUDGET = {"rmse": 1e-4, "hausdorff": 5e-4, "normal_deg": 0.25}


def within(r: dict) -> bool:
    return all(r[k] <= v for k, v in BUDGET.items())


def run_mesh(path, mesh, kind, n, rows):
    with tempfile.TemporaryDirectory() as tmp:
        t = time.perf_counter()
        try:
            copies = tracing.issue(mesh, key="studio", registry=os.path.join(tmp, "r.sqlite"), n_copies=n,
                                   informed=(kind == "default"))
        except MeshError as exc:
            return time.perf_counter() - t, str(exc)
    t_issue = time.perf_counter() - t
    for cid, V in copies:
        rows.append({"mesh": path.stem, "n_vertices": mesh.n_vertices, "kind": kind, "copy": cid,
                     **distortion(mesh, V)})
    return t_issue, ""


def summary(rows, errors, a):
    lines = [f"| mesh | vertices | copies (default) | RMSE / diag max | Hausdorff / diag max | normal change max (°) | "
             f"within budget | blind only ({a.baseline} copies): RMSE / Hausdorff / normal max | within |",
             "|---|---|---|---|---|---|---|---|---|"]
    meshes = dict.fromkeys((r["mesh"], r["n_vertices"]) for r in rows)
    meshes.update(dict.fromkeys(errors))
    n_ok = n_copies = n_all = n_meshes = 0
    for name, nv in meshes:
        d = [r for r in rows if r["mesh"] == name and r["kind"] == "default"]
        b = [r for r in rows if r["mesh"] == name and r["kind"] == "blind only"]
        mx = lambda rs, k: max(r[k] for r in rs)
        if d:
            ok = sum(within(r) for r in d)
            n_ok, n_copies = n_ok + ok, n_copies + len(d)
            n_all, n_meshes = n_all + (ok == len(d)), n_meshes + 1
            cells = f"{len(d)} | {mx(d, 'rmse'):.2e} | {mx(d, 'hausdorff'):.2e} | {mx(d, 'normal_deg'):.3f} | {ok}/{len(d)}"
        else:
            cells = f"0 | – | – | – | not issued: {errors.get((name, nv), {}).get('default', '')[:80]}"
        if b:
            base = (f"{mx(b, 'rmse'):.2e} / {mx(b, 'hausdorff'):.2e} / {mx(b, 'normal_deg'):.3f} | "
                    f"{sum(within(r) for r in b)}/{len(b)}")
        else:
            base = f"– | {errors.get((name, nv), {}).get('blind only', '')[:60] or '–'}"
        lines.append(f"| {name} | {nv:,} | {cells} | {base} |")
    lines += ["", f"Default copies within all three limits: {n_ok} of {n_copies}; meshes with every copy within: "
              f"{n_all} of {n_meshes}."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--copies", type=int, default=100, help="copies issued per mesh with the defaults")
    ap.add_argument("--baseline", type=int, default=10, help="copies issued per mesh without the pattern (0: none)")
    ap.add_argument("--meshes", default="", help="comma-separated parts of file names (default: the whole test set)")
    ap.add_argument("--out", default=os.path.join(HERE, "out", "distortion_budget"))
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args(argv)
    if a.quick:
        a.copies, a.baseline, a.meshes = min(a.copies, 3), min(a.baseline, 1), a.meshes or "cat-low"
    meshes = test_set([s for s in a.meshes.split(",") if s] or None)
    if not meshes:
        raise SystemExit("no mesh of the test set matches --meshes")
    print(f"{len(meshes)} meshes with >= 5,000 welded vertices: "
          + ", ".join(f"{p.stem} ({m.n_vertices})" for p, m in meshes), flush=True)
    os.makedirs(a.out, exist_ok=True)
    rows, errors = [], {}
    for path, mesh in meshes:
        for kind, n in (("default", a.copies), ("blind only", a.baseline)):
            if n <= 0:
                continue
            t_issue, err = run_mesh(path, mesh, kind, n, rows)
            if err:
                errors.setdefault((path.stem, mesh.n_vertices), {})[kind] = err
            done = [r for r in rows if r["mesh"] == path.stem and r["kind"] == kind]
            print(f"{path.stem} ({mesh.n_vertices}) {kind}: {len(done)} copies, issue {t_issue:.1f} s, "
                  + (f"within budget {sum(within(r) for r in done)}/{len(done)}, max RMSE "
                     f"{max(r['rmse'] for r in done):.2e}, Hausdorff {max(r['hausdorff'] for r in done):.2e}, "
                     f"normal {max(r['normal_deg'] for r in done):.3f}" if done else f"ERROR {err}"), flush=True)
        if rows:
            write_csv(rows, os.path.join(a.out, "copies.csv"))
        with open(os.path.join(a.out, "summary.md"), "w") as f:
            f.write(summary(rows, errors, a))
    text = summary(rows, errors, a)
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
