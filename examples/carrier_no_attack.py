"""Every Laplacian carrier (docs/carrier.md) on the classic meshes, no attack and the lossless
attacks: embed a message with the automatic parameters and the carrier, read it back exactly after float32,
OBJ at 6 decimals, rotation + translation, x0.001, x1000, a vertex/face permutation and all together
(the variants of examples/laplacian_no_attack.py). Also the smallest relative margin |c1 - c2| / f of
the carrier pairs on the marked mesh (the embedding must give every pair its eq. 7.2.16 margin).

    .venv/bin/python examples/carrier_no_attack.py [--out build/carrier/no_attack.csv] [--carriers C,..] [--quick]

Parameters: the automatic ones (``params="auto"``) with each ``carrier=``; key "no-attack". ``--quick``: the Fandisk only.
"""
import argparse
import pathlib
import sys
import tempfile

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import meshmark  # noqa: E402
from _common import SHARED, write_csv  # noqa: E402
from laplacian_no_attack import variants  # noqa: E402
from meshmark.watermark import laplacian as lap  # noqa: E402
from meshmark.watermark.payload import Payload  # noqa: E402

MESHES = ["bunny.obj", "elephant.off", "horse.ply", "hand.obj", "fandisk.obj", "camelhead.off", "fertility.off",
          "spot.obj", "homer.obj", "teapot.obj"]


def min_margin(mesh, r):
    p, side = r.keyfile.params, r.keyfile.side_info
    ids = np.asarray(side["carriers"], np.int64)
    _, d, _ = lap.METHOD._lengths(mesh.with_vertices(r.V), p)
    c1, c2 = lap._pair_counts(np.sort(d[mesh.referenced() == 1]), side["lo"], side["hi"], p["K"], ids)
    return float((np.abs(c1 - c2) / np.maximum(c1 + c2, 1)).min())


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="build/carrier/no_attack.csv")
    ap.add_argument("--carriers", default=",".join(lap.CARRIERS))
    ap.add_argument("--quick", action="store_true", help="the Fandisk only (the test suite runs it)")
    a = ap.parse_args()
    rows = []
    for name in (["fandisk.obj"] if a.quick else MESHES):
        m = meshmark.read_mesh(SHARED / "classic" / name)
        for c in a.carriers.split(","):
            cap = lap.capacity(m, carrier=c)
            msg = "(c)" if cap >= 40 else "c" if cap >= 24 else None
            if cap < 17:  # the smallest framed payload (1 bit + 16 framing bits)
                rows.append({"mesh": name, "carrier": c, "capacity": cap, "exact": "", "min_margin": "", "rounds": ""})
                continue
            r = lap.embed(m, payload=msg if msg else Payload.from_bits([1]), key="no-attack", carrier=c)
            with tempfile.TemporaryDirectory() as tmp:
                ok = [lap.extract(mm, keyfile=r.keyfile) for _, mm in variants(m, r.V, np.random.default_rng(5),
                                                                                pathlib.Path(tmp))]
            exact = sum(x.cdr == 1.0 and x.message == (msg or "1") for x in ok)
            rows.append({"mesh": name, "carrier": c, "capacity": cap, "exact": f"{exact}/{len(ok)}",
                         "min_margin": round(min_margin(m, r), 3), "rounds": r.stats.get("n_solve_rounds")})
            print(rows[-1], flush=True)
    print(write_csv(rows, a.out))


if __name__ == "__main__":
    main()
