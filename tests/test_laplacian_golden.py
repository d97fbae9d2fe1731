"""The Laplacian method's outputs against golden records saved before the speed work of issue 10
(docs/carrier.md): same carriers, same bins, same marked vertices and positions, same extracted bits and
soft values, for the thesis and the default ("local") carrier, both solvers.

It runs the method layer (meshmark.watermark.laplacian.METHOD: resolve, carriers, embed, extract) with
fixed raw bits, below the framework's coding, so that a new coding scheme does not change these records.

What is compared, and how:

* the discrete outcome exactly: K, the carrier ids, the moved-vertex count, the solver rounds and PCG
  iterations, the side information's flags, every extracted bit (clean and deformed copy);
* the floating-point outcome within a stated tolerance, never bit for bit: the direct solver runs
  CHOLMOD on the BLAS that OpenBLAS picks for the CPU (its Prescott, Sandybridge, Haswell, SkylakeX,
  Cooperlake and Zen kernels sum in different orders: the marked positions differ by ~1e-12 of the
  largest displacement between kernels). The displacement field dV = V_marked - V is recorded by its
  Frobenius norm, its largest entry and its projections on 4 fixed random fields (12 numbers, any
  change of the embedding beyond rounding moves them); they must agree within 1e-8 of ||dV||. Bin
  edges, carrier values and soft values within 1e-9 relative (scalar arithmetic, the same on every
  CPU for one compiler, but not promised across compilers).

tests/test_blas_kernels.py runs this file under each OpenBLAS kernel. To rewrite the records (only for a
change that is meant to alter the results):

    .venv/bin/python tests/test_laplacian_golden.py --write
"""
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
EXACT = ("K", "ids", "n_changed", "stats", "bits_ok", "deformed_bits", "side_other")
FIELD_ATOL = 1e-8   # of ||field||: projections of a displacement field
SCALAR_RTOL = 1e-9  # bin edges, values, soft values


def _fingerprint(x) -> dict:
    """Norm, largest entry and projections on 4 fixed random fields of an (n,) or (n, 3) array."""
    x = np.asarray(x, dtype=np.float64).reshape(len(x), -1)
    R = np.random.default_rng(20130101).standard_normal((x.shape[0], 4))
    return {"norm": float(np.linalg.norm(x)), "max": float(np.abs(x).max()),
            "proj": (x.T @ R).ravel().tolist()}


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
    values = L.carrier_values(mesh, carrier)
    return {
        "K": int(p["K"]), "ids": [int(i) for i in ids], "n_changed": int(np.any(Vm != mesh.V, axis=1).sum()),
        "stats": {k: int(v) for k, v in st.items()}, "bits_ok": bool(np.array_equal(got, bits)),
        "deformed_bits": [int(b) for b in got_d],
        "side_other": {k: v for k, v in side_m.items() if not isinstance(v, float)},
        "scalars": {"lo": float(side["lo"]), "hi": float(side["hi"]),
                    **{f"side_{k}": float(v) for k, v in side_m.items() if isinstance(v, float)},
                    "deformed_t": float(M._range(deformed, p, side_d["lo"], side_d["hi"], ids))},
        "soft": [float(s) for s in soft], "deformed_soft": [float(s) for s in soft_d],
        "values": _fingerprint(values), "dV": _fingerprint(Vm - mesh.V),
        "d_values": _fingerprint(L.carrier_values(marked, carrier) - values),
    }


def _key(case) -> str:
    return "|".join(case)


def _close_fingerprint(got, want, name):
    scale = want["norm"]
    assert abs(got["norm"] - scale) <= FIELD_ATOL * scale, (name, got["norm"], scale)
    assert abs(got["max"] - want["max"]) <= FIELD_ATOL * scale, (name, got["max"], want["max"])
    np.testing.assert_allclose(got["proj"], want["proj"], rtol=0, atol=FIELD_ATOL * scale, err_msg=name)


@pytest.mark.parametrize("case", CASES, ids=_key)
def test_matches_golden(case):
    golden = json.loads(GOLDEN.read_text())
    assert _key(case) in golden, f"no golden record for {case}: run this file with --write"
    got, want = record(*case), golden[_key(case)]
    assert got["bits_ok"]
    for k in EXACT:  # the discrete parts first: the first difference names what changed
        assert got[k] == want[k], f"{case}: {k} differs from the golden record"
    assert got["scalars"].keys() == want["scalars"].keys()
    for k, v in want["scalars"].items():
        assert got["scalars"][k] == pytest.approx(v, rel=SCALAR_RTOL, abs=1e-300), f"{case}: {k}"
    for k in ("soft", "deformed_soft"):
        np.testing.assert_allclose(got[k], want[k], rtol=SCALAR_RTOL, atol=1e-12, err_msg=f"{case}: {k}")
    for k in ("values", "dV", "d_values"):
        _close_fingerprint(got[k], want[k], f"{case}: {k}")


if __name__ == "__main__":
    if "--write" not in sys.argv:
        sys.exit("usage: python tests/test_laplacian_golden.py --write")
    GOLDEN.parent.mkdir(exist_ok=True)
    out = {_key(c): record(*c) for c in CASES}
    GOLDEN.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {GOLDEN} ({len(out)} cases)")
