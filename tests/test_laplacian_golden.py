"""The Laplacian method's outputs, bit for bit, against golden records saved before the speed work of
issue 10 (docs/carrier.md section 5): same carriers, same bins, same marked vertices and positions, same
extracted bits and soft values, for the thesis and the default ("local") carrier, both solvers.

It runs the method layer (meshmark.watermark.laplacian.METHOD: resolve, carriers, embed, extract) with
fixed raw bits, below the framework's coding, so that a new coding scheme does not change these records.
The positions are compared by their SHA-256 (bit-identical or not); the records were written on x86-64
with GCC's Release build. To rewrite them (only for a change that is meant to alter the results):

    .venv/bin/python tests/test_laplacian_golden.py --write
"""
import hashlib
import json
import pathlib
import sys

import numpy as np
import pytest

import meshmark
from meshmark.watermark import laplacian as L

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from conftest import shared_mesh  # noqa: E402

GOLDEN = pathlib.Path(__file__).parent / "data" / "laplacian_golden.json"
CASES = [("classic/bunny.obj", "thesis", "iterative"), ("classic/bunny.obj", "local", "iterative"),
         ("classic/bunny.obj", "local", "direct"), ("classic/fandisk.obj", "thesis", "iterative"),
         ("classic/fandisk.obj", "local", "iterative"), ("classic/fandisk.obj", "local", "direct")]


def _sha(a) -> str:
    return hashlib.sha256(np.ascontiguousarray(a).tobytes()).hexdigest()


def record(rel: str, carrier: str, solver: str) -> dict:
    m = meshmark.read_mesh(shared_mesh(rel))
    mesh = meshmark.Mesh(m.V, m.F)
    M = L.METHOD
    p = M.resolve(mesh, {"K": None, "n_thr": 20, "carrier": carrier, "solver": solver})
    ids, side = M.carriers(mesh, p)
    bits = np.random.default_rng(7).integers(0, 2, len(ids))
    Vm, side_m, st = M.embed(mesh, p, side, ids, bits)
    marked = meshmark.Mesh(Vm, m.F)
    got, soft = M.extract(marked, p, side_m, ids)
    # a deformed copy (x1.02, small noise): the range search moves the bins (t != 1)
    Vd = Vm * 1.02 + np.random.default_rng(3).normal(0, 2e-4 * float(np.ptp(Vm, axis=0).max()), Vm.shape)
    deformed = meshmark.Mesh(Vd, m.F)
    side_d = dict(side_m, range_search=True)
    got_d, soft_d = M.extract(deformed, p, side_d, ids)
    changed = np.flatnonzero(np.any(Vm != mesh.V, axis=1))
    return {
        "K": int(p["K"]), "ids": [int(i) for i in ids], "lo": float(side["lo"]).hex(), "hi": float(side["hi"]).hex(),
        "values": _sha(L.carrier_values(mesh, carrier)), "marked_values": _sha(L.carrier_values(marked, carrier)),
        "V": _sha(Vm), "changed": _sha(changed.astype(np.int64)), "n_changed": int(changed.size),
        "stats": {k: int(v) for k, v in st.items()},
        "side": {k: (float(v).hex() if isinstance(v, float) else v) for k, v in side_m.items()},
        "bits_ok": bool(np.array_equal(got, bits)), "soft": [float(s).hex() for s in soft],
        "deformed_bits": [int(b) for b in got_d], "deformed_soft": [float(s).hex() for s in soft_d],
        "deformed_t": float(M._range(deformed, p, side_d["lo"], side_d["hi"], ids)).hex(),
    }


def _key(case) -> str:
    return "|".join(case)


@pytest.mark.parametrize("case", CASES, ids=_key)
def test_matches_golden(case):
    golden = json.loads(GOLDEN.read_text())
    assert _key(case) in golden, f"no golden record for {case}: run this file with --write"
    got, want = record(*case), golden[_key(case)]
    assert got["bits_ok"]
    for k in want:  # the discrete parts first: the first difference names what changed
        assert got[k] == want[k], f"{case}: {k} differs from the golden record"


if __name__ == "__main__":
    if "--write" not in sys.argv:
        sys.exit("usage: python tests/test_laplacian_golden.py --write")
    GOLDEN.parent.mkdir(exist_ok=True)
    out = {_key(c): record(*c) for c in CASES}
    GOLDEN.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {GOLDEN} ({len(out)} cases)")
