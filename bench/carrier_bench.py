"""Bench: the Laplacian watermark with the default carrier ("local") against the thesis carrier, in one
process, alternating, best of N of the process CPU time (time.process_time: the shared machine's load
varies by the second, and wall time under load measures the other jobs; docs/carrier.md).

    .venv/bin/python bench/carrier_bench.py [--small] [--reps 7]

Same cases as bench/laplacian_bench.py (16-bit payload, thesis K/n_thr/n_robust, fresh arrays for every
timed call: edges, welding and the scalar are computed inside the timing). Prints embed and extract
times and their ratio new / thesis. The default carrier offers more carriers at the same K (bunny 104
vs 73), so embedding moves and extraction reads more pairs.
"""
import argparse
import sys
import time

import numpy as np

import os

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "reference"))
from laplacian_bench import load  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--small", action="store_true")
    ap.add_argument("--reps", type=int, default=7)
    ap.add_argument("--carrier", default="local")
    a = ap.parse_args()
    from meshmark.watermark import laplacian as L
    from meshmark.watermark.payload import Payload
    bits = Payload.from_bits(np.random.default_rng(0).integers(0, 2, 16))
    for which in ["bunny"] + ([] if a.small else ["elephant-1M"]):
        m = load(which)
        big = m.n_vertices > 200_000
        reps = max(2, a.reps // 3) if big else a.reps
        t = {c: {"embed": [], "extract": []} for c in ("thesis", a.carrier)}
        res = {}
        for c in t:
            L.embed(m, payload=Payload.from_bits([1, 0, 1, 1]), key="warm", carrier=c)  # warm-up
        for _ in range(reps):
            for c in t:
                V, F = m.V.copy(), m.F.copy()
                s = time.process_time()
                res[c] = L.embed(V, F, payload=bits, key="bench", carrier=c)
                t[c]["embed"].append(time.process_time() - s)
                for _ in range(1 if big else 3):
                    Vm, F2 = res[c].V.copy(), F.copy()
                    s = time.process_time()
                    x = L.extract(Vm, F2, keyfile=res[c].keyfile)
                    t[c]["extract"].append(time.process_time() - s)
                    assert x.cdr == 1.0
        b = {c: {k: min(v) for k, v in d.items()} for c, d in t.items()}
        for c in t:
            print(f"{which:<12} {c:<8} carriers {res[c].capacity:>5}  embed {b[c]['embed']:.4f} s  "
                  f"extract {b[c]['extract']:.4f} s  CPU (best of {len(t[c]['embed'])} / {len(t[c]['extract'])})")
        print(f"{which:<12} {a.carrier} / thesis: embed {b[a.carrier]['embed'] / b['thesis']['embed']:.2f}x, "
              f"extract {b[a.carrier]['extract'] / b['thesis']['extract']:.2f}x", flush=True)
    return 0


if __name__ == "__main__":
    sys.path.insert(0, ".")
    sys.exit(main())
