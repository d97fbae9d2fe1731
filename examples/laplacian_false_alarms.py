"""False alarms of the Laplacian watermark: wrong keys and unmarked meshes (writes CSV).

    .venv/bin/python examples/laplacian_false_alarms.py [--keys 1000] [--keyfiles 20] [--out out/false_alarms] [--quick]

Marks use the thesis parameters (``params="thesis"``), the setting Table 7.3's false-alarm figures are for.
``--quick``: the Bunny only in part 1 (20 keys), four classic meshes in part 2 (the cow cannot carry a coded payload at these parameters) (2 keyfiles each).

1. Wrong keys: Bunny, Horse and Elephant are marked under one key; extraction with N random wrong
   keys must never report `detected`. The NC of each try goes to wrong_keys.csv.
2. Unmarked meshes: for every OBJ/OFF/PLY/STL mesh in ../shared/meshes (corpus and corpus-large included) that can
   carry a framed payload, K keyfiles are made by embedding random payloads (1..16 bits) under random
   keys; extracting from the unmarked original with each must never report `detected`.
"""
import argparse
import csv
import os
import pathlib
import sys
import time

import numpy as np

import meshmark
from meshmark.watermark import laplacian as L
from meshmark.watermark.coding import max_data_bits
from meshmark.watermark.payload import Payload

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--keys", type=int, default=1000)
    ap.add_argument("--keyfiles", type=int, default=20)
    ap.add_argument("--out", default="out/false_alarms")
    ap.add_argument("--quick", action="store_true", help="a few meshes and keys (the test suite runs it)")
    a = ap.parse_args(argv)
    marked_meshes = ["classic/bunny.obj", "classic/horse.ply", "classic/elephant.off"]
    if a.quick:
        a.keys, a.keyfiles, marked_meshes = min(a.keys, 20), min(a.keyfiles, 2), marked_meshes[:1]
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(2026)

    with open(out / "wrong_keys.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mesh", "try", "nc", "cdr", "p_false_alarm", "detected"])
        for rel in marked_meshes:
            m = meshmark.read_mesh(SHARED / rel)
            r = L.embed(m, payload=Payload.from_bits(rng.integers(0, 2, 12)), key="owner-key", params="thesis")
            ncs, hits = [], 0
            for t in range(a.keys):
                x = L.extract(r.V, m, keyfile=r.keyfile, key=os.urandom(12).hex())
                ncs.append(x.nc)
                hits += x.detected
                w.writerow([rel, t, f"{x.nc:.4f}", f"{x.cdr:.4f}", f"{x.p_false_alarm:.3g}", int(x.detected)])
            ncs = np.array(ncs)
            print(f"wrong keys  {rel:<24} n={a.keys} bits={r.capacity} detected={hits} NC mean {ncs.mean():+.3f} "
                  f"sd {ncs.std():.3f} min {ncs.min():+.3f} max {ncs.max():+.3f}", flush=True)

    files = sorted(p for p in SHARED.rglob("*") if p.suffix.lower() in {".obj", ".off", ".ply", ".stl"})
    if a.quick:
        files = [SHARED / "classic" / n for n in ("bunny.obj", "horse.ply", "elephant.off", "cow.obj")]
    total = hits = skipped = 0
    with open(out / "unmarked.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["mesh", "capacity", "keyfile", "payload_bits", "matches", "bits", "p_false_alarm", "detected"])
        for p in files:
            m = meshmark.read_mesh(p)
            try:
                cap = L.capacity(m, params="thesis")
            except meshmark.MeshError:
                cap = 0
            if max_data_bits(cap) < 1 or cap < 8:
                skipped += 1
                continue
            for k in range(a.keyfiles):
                nb = int(rng.integers(1, min(16, max_data_bits(cap)) + 1))
                r = L.embed(m, payload=Payload.from_bits(rng.integers(0, 2, nb)), key=os.urandom(12).hex(),
                            params="thesis")
                x = L.extract(m, keyfile=r.keyfile)
                total += 1
                hits += x.detected
                w.writerow([p.relative_to(SHARED), cap, k, nb, x.matches, x.n_bits, f"{x.p_false_alarm:.3g}", int(x.detected)])
    print(f"unmarked meshes: {total} extractions over {len(files) - skipped} meshes "
          f"({skipped} cannot carry a coded payload at thesis defaults), detected={hits}")
    return 1 if hits else 0


if __name__ == "__main__":
    sys.exit(main())
