"""Acceptance measurements of issue 10 (automatic parameters, coding, tracing) on the shared meshes.

    .venv/bin/python examples/product_acceptance.py [--part fit|false|trace|all] [--out examples/out/product] [--quick]

Parameters: the automatic ones (``params="auto"``, the API and CLI default) everywhere.
``--quick``: the Fandisk and the Elephant only, 50 wrong keys, 2 keyfiles per mesh, 20 copies (5 traced).

* ``fit``: every classic and corpus mesh; on those of >= 5,000 welded vertices a random 16-bit payload
  is embedded with the default settings (``params="auto"``) and extracted after a random rotation,
  scaling x0.001, a vertex and face permutation, float32 storage and OBJ with 7 significant digits
  (CDR and message); on those of >= 8,000 the 4-byte text "ACME" must fit.
* ``false``: (a) 1,000 wrong keys on each of 3 marked meshes, (b) 20 keyfiles (20 keys) made on every
  shared mesh that takes a mark, extracted from the unmarked mesh; counts detections and messages.
* ``trace``: 1,000 copies of the Fandisk issued into a registry (real embeddings), then every shared
  mesh unmarked (and the Fandisk original) traced against it; counts named copies.
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
from meshmark.watermark import embed, extract, tracing  # noqa: E402
from meshmark.watermark.payload import Payload  # noqa: E402

from _common import SHARED, MESH_SUFFIXES, write_csv  # noqa: E402

# The counts of the full run; --quick (the test suite) uses QUICK: the Fandisk and the Elephant, fewer trials.
FULL = {"meshes": None, "wrong_keys": 1000, "keyfiles": 20, "copies": 1000, "traced": 50}
QUICK = {"meshes": ["classic/fandisk.obj", "classic/elephant.off"], "wrong_keys": 50, "keyfiles": 2, "copies": 20,
         "traced": 5}
N = dict(FULL)


def shared_meshes():
    if N["meshes"]:
        return [SHARED / rel for rel in N["meshes"]]
    out = []
    for sub in ("classic", "corpus"):
        for p in sorted((SHARED / sub).iterdir()):
            if p.suffix.lower() in MESH_SUFFIXES:
                out.append(p)
    return out


def _rotation(rng):
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    return Q * np.sign(np.linalg.det(Q))


def attacks(mesh, V, rng, tmp):
    """name -> (V, F-or-mesh) of the marked mesh after each benign operation."""
    perm = rng.permutation(mesh.n_vertices)
    inv = np.argsort(perm)
    fo = mesh.face_offsets
    faces = [inv[mesh.face_indices[fo[f]:fo[f + 1]]] for f in rng.permutation(mesh.n_faces)]
    path = os.path.join(tmp, "m.obj")
    meshmark.write_mesh(path, V, mesh, precision=7)
    obj = meshmark.read_mesh(path)
    return {"rotation": (V @ _rotation(rng).T, mesh), "scale_0.001": (V * 1e-3, mesh),
            "permutation": (V[perm], faces), "float32": (V.astype(np.float32).astype(np.float64), mesh),
            "obj_7_digits": (obj.V, obj)}


def part_fit(out):
    rows = []
    rng = np.random.default_rng(10)
    with tempfile.TemporaryDirectory() as tmp:
        for p in shared_meshes():
            m = meshmark.read_mesh(p)
            n = meshmark.weld_vertices(m).mesh.n_vertices
            row = {"mesh": f"{p.parent.name}/{p.name}", "welded_vertices": n}
            if n >= 5000:
                bits = rng.integers(0, 2, 16)
                try:
                    r = embed(m, payload=Payload.from_bits(bits), key=f"acc-{p.stem}")
                    row.update(capacity=r.capacity, K=r.keyfile.params.get("K"), n_thr=r.keyfile.params.get("n_thr"),
                               rung=r.keyfile.choice.get("rung"))
                    cdrs, msgs = [], []
                    for name, (V, F) in attacks(m, r.V, rng, tmp).items():
                        x = extract(V, F, keyfile=r.keyfile)
                        row[f"cdr_{name}"] = x.cdr
                        cdrs.append(x.cdr)
                        msgs.append(x.message_ok and x.message == Payload.from_bits(bits).bitstring())
                    row["min_cdr"] = min(cdrs)
                    row["all_messages"] = all(msgs)
                except MeshError as exc:
                    row["error16"] = str(exc)[:120]
            if n >= 8000:
                try:
                    embed(m, payload="ACME", key="acc-text")
                    row["text4_fits"] = True
                except MeshError as exc:
                    row["text4_fits"] = False
                    row["error_text"] = str(exc)[:120]
            print(row, flush=True)
            rows.append(row)
    keys = sorted({k for r in rows for k in r}, key=lambda k: (k not in ("mesh", "welded_vertices"), k))
    write_csv([{k: r.get(k, "") for k in keys} for r in rows], os.path.join(out, "fit.csv"))
    big = [r for r in rows if r["welded_vertices"] >= 5000]
    ok = [r for r in big if r.get("min_cdr") == 1.0 and r.get("all_messages")]
    text = [r for r in rows if r["welded_vertices"] >= 8000]
    print(f"16-bit payload, CDR 1.0 and message after all 5 operations: {len(ok)} of {len(big)} meshes >= 5,000 welded")
    print(f"4-byte text fits: {sum(bool(r.get('text4_fits')) for r in text)} of {len(text)} meshes >= 8,000 welded")


def part_false(out):
    rows = []
    rng = np.random.default_rng(11)
    for name in N["meshes"] or ("classic/bunny.obj", "classic/fandisk.obj", "classic/elephant.off"):
        m = meshmark.read_mesh(SHARED / name)
        r = embed(m, payload=Payload.from_bits(rng.integers(0, 2, 16)), key="the-owner")
        det = msg = 0
        for i in range(N["wrong_keys"]):
            x = extract(r.V, m, keyfile=r.keyfile, key=f"wrong-{i}-{rng.integers(1 << 30)}")
            det += x.detected
            msg += x.message is not None
        rows.append({"test": "wrong keys", "mesh": name, "trials": N["wrong_keys"], "detected": det, "messages": msg})
        print(rows[-1], flush=True)
    tot = {"trials": 0, "detected": 0, "messages": 0, "meshes": 0}
    for p in shared_meshes():
        m = meshmark.read_mesh(p)
        kfs = []
        for i in range(N["keyfiles"]):
            for payload in (Payload.from_bits(rng.integers(0, 2, 16)), Payload.from_bits([1])):
                try:
                    kfs.append(embed(m, payload=payload, key=f"k{i}-{p.stem}").keyfile)
                    break
                except MeshError:
                    continue
        if not kfs:
            continue
        det = msg = 0
        for kf in kfs:
            x = extract(m, keyfile=kf)
            det += x.detected
            msg += x.message is not None
        tot["trials"] += len(kfs)
        tot["detected"] += det
        tot["messages"] += msg
        tot["meshes"] += 1
        rows.append({"test": f"unmarked, {N['keyfiles']} keyfiles", "mesh": f"{p.parent.name}/{p.name}", "trials": len(kfs),
                     "detected": det, "messages": msg})
    print({"test": f"unmarked, {N['keyfiles']} keyfiles", **tot}, flush=True)
    write_csv(rows, os.path.join(out, "false_alarms.csv"))


def part_trace(out):
    fd = meshmark.read_mesh(SHARED / "classic/fandisk.obj")
    with tempfile.TemporaryDirectory() as tmp:
        reg = os.path.join(tmp, "r.sqlite")
        t = time.perf_counter()
        copies = tracing.issue(fd, key="studio", registry=reg, n_copies=N["copies"])
        print(f"issued {N['copies']} Fandisk copies in {time.perf_counter() - t:.1f} s", flush=True)
        k = N["traced"]
        right = sum(tracing.trace(V, fd, registry=reg)["copy"] == cid for cid, V in copies[:k])
        rows = [{"suspect": f"{k} issued copies", "named": right, "wrong": k - right, "p_false_alarm": "",
                 "matches": "", "n_carriers": ""}]
        named = 0
        n = 0
        for p in shared_meshes():
            r = tracing.trace(meshmark.read_mesh(p), registry=reg)
            named += r["copy"] is not None
            n += 1
            rows.append({"suspect": f"{p.parent.name}/{p.name}", "named": int(r["copy"] is not None), "wrong": "",
                         "p_false_alarm": r["p_false_alarm"], "matches": (r["blind"] or {}).get("matches", ""),
                         "n_carriers": (r["blind"] or {}).get("n_carriers", "")})  # best blind candidate
        print(f"issued copies traced right: {right}/{k}; unmarked meshes traced to a copy: {named} of {n}", flush=True)
    write_csv(rows, os.path.join(out, "trace.csv"))


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--part", default="all", choices=["fit", "false", "trace", "all"])
    ap.add_argument("--out", default=os.path.join(HERE, "out", "product"))
    ap.add_argument("--quick", action="store_true", help="2 meshes, 50 wrong keys, 2 keyfiles, 20 copies (tested)")
    a = ap.parse_args(argv)
    N.update(QUICK if a.quick else FULL)
    os.makedirs(a.out, exist_ok=True)
    for part, f in (("fit", part_fit), ("false", part_false), ("trace", part_trace)):
        if a.part in (part, "all"):
            t = time.perf_counter()
            f(a.out)
            print(f"part {part}: {time.perf_counter() - t:.0f} s", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
