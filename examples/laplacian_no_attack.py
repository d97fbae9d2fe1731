"""No attack, storage, similarity and reordering: the Laplacian mark on every shared mesh (writes CSV).

    .venv/bin/python examples/laplacian_no_attack.py [--out out/laplacian_no_attack.csv] [--quick]

Parameters: the thesis' (``params="thesis"``), key "no-attack". ``--quick``: the Bunny and the Elephant only.

Every OBJ/OFF/PLY/STL mesh under ../shared/meshes (classic, corpus, corpus-large) that offers a
framed payload at the thesis defaults is marked with the longest of "(c)ACME", "(c)", "c" or the
single bit 1 that fits, under a fixed key. The mark is then extracted from the marked mesh as it is
and after: a float32 cast; an OBJ written with 6 decimals and read back; a random rotation and
translation; uniform scaling by 0.001 and by 1000; a random vertex and face permutation; and all of
these together. A row fails unless CDR = 1.0 and the exact message come back. `detected` is
reported too: a mesh with fewer than 20 carriers can never reach P(false alarm) < 1e-6 (2^-19 > 1e-6),
so its exact read-back is not "detected" by design.
"""
import argparse
import pathlib
import sys
import tempfile

import numpy as np

import meshmark
from meshmark.watermark.coding import min_carriers
from _common import SHARED, write_csv
from meshmark.watermark import laplacian as L
from meshmark.watermark.payload import Payload



def rotation(rng):
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    q = q @ np.diag(np.sign(np.diag(r)))
    return q if np.linalg.det(q) > 0 else -q


def variants(m, Vm, rng, tmp):
    R, t = rotation(rng), rng.normal(size=3) * 10
    perm = rng.permutation(m.n_vertices)
    inv = np.argsort(perm)
    Fp = inv[m.face_indices]  # faces reindexed, then shuffled
    fperm = rng.permutation(m.n_faces)
    off = m.face_offsets
    sizes = np.diff(off)[fperm]
    idx = np.concatenate([Fp[off[f]:off[f + 1]] for f in fperm]) if m.n_faces else Fp
    Pm = lambda V: meshmark.Mesh.from_polygons(V, idx, np.concatenate([[0], np.cumsum(sizes)]))
    meshmark.write_mesh(tmp / "m.obj", meshmark.Mesh.from_polygons(Vm, m.face_indices, m.face_offsets), decimals=6)
    yield "none", m.with_vertices(Vm)
    yield "float32", m.with_vertices(Vm.astype(np.float32).astype(float))
    yield "obj 6 decimals", meshmark.read_mesh(tmp / "m.obj")
    yield "rotation+translation", m.with_vertices(Vm @ R.T + t)
    yield "scale 0.001", m.with_vertices(Vm * 1e-3)
    yield "scale 1000", m.with_vertices(Vm * 1e3)
    yield "permutation", Pm(Vm[perm])
    yield "all together", Pm(((Vm[perm] * 1e3) @ R.T + t).astype(np.float32).astype(float))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/laplacian_no_attack.csv")
    ap.add_argument("--quick", action="store_true", help="the Bunny and the Elephant only (the test suite runs it)")
    a = ap.parse_args()
    files = sorted(p for p in SHARED.rglob("*") if p.suffix.lower() in {".obj", ".off", ".ply", ".stl"})
    if a.quick:
        files = [SHARED / "classic" / "bunny.obj", SHARED / "classic" / "elephant.off"]
    rng = np.random.default_rng(2026)
    rows, failures, skipped = [], 0, 0
    with tempfile.TemporaryDirectory() as d:
        tmp = pathlib.Path(d)
        for p in files:
            m = meshmark.read_mesh(p)
            try:
                cap = L.capacity(m, params="thesis")
            except meshmark.MeshError:
                cap = 0
            msg = next((s for s in ("(c)ACME", "(c)", "c") if min_carriers(8 * len(s)) <= cap), None)
            if msg is None and cap < min_carriers(1):
                skipped += 1
                continue
            payload = msg if msg is not None else Payload.from_bits([1])
            r = L.embed(m, payload=payload, key="no-attack", params="thesis")
            expect = msg if msg is not None else "1"
            for name, mm in variants(m, r.V, rng, tmp):
                x = L.extract(mm, keyfile=r.keyfile)
                ok = x.cdr == 1.0 and x.message == expect and (x.detected or r.capacity < 20)
                failures += not ok
                rows.append({"mesh": str(p.relative_to(SHARED)), "carriers": r.capacity, "attack": name,
                             "cdr": x.cdr, "message_ok": x.message == expect, "detected": x.detected, "ok": ok})
            bad = [row["attack"] for row in rows[-8:] if not row["ok"]]
            print(f"{str(p.relative_to(SHARED)):<48} carriers {r.capacity:4d}  {'OK' if not bad else 'FAIL ' + ', '.join(bad)}",
                  flush=True)
    out = write_csv(rows, a.out)
    n_mesh = len({r["mesh"] for r in rows})
    print(f"{n_mesh} meshes x 8 conditions: {len(rows) - failures} of {len(rows)} with CDR 1.0, the exact message "
          f"and detection (where >= 20 carriers make it possible); {skipped} meshes cannot carry a framed payload at the defaults. Wrote {out}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
