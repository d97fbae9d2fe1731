"""Bench: copy tracing against a registry of 10,000 copies, beyond the extraction itself.

    .venv/bin/python bench/trace_bench.py [--copies 10000]

One copy of the Bunny is issued for real (meshmark.watermark.tracing.issue) and the registry is
filled up to --copies with random codewords for the same asset (tracing only reads the codewords;
embedding 10,000 meshes would measure the embedder, not the tracer). Prints the best of 7 of:
reading the carriers alone (framework.read_soft, the extraction), the whole trace(), and the
difference (target: <= 50 ms at 10,000 copies).
"""
import argparse
import os
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import meshmark  # noqa: E402
from meshmark.watermark import framework, tracing  # noqa: E402

from _common import SHARED, best_of, random_codeword  # noqa: E402


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--copies", type=int, default=10_000)
    a = ap.parse_args()
    m = meshmark.read_mesh(SHARED / "classic" / "bunny.obj")
    with tempfile.TemporaryDirectory() as tmp:
        reg_path = os.path.join(tmp, "r.sqlite")
        (cid, V), = tracing.issue(m, key="studio", registry=reg_path, n_copies=1)
        with tracing.Registry(reg_path) as reg:
            (asset_id, setup, C), = reg.assets()
            reg.begin()  # rows with their checks, as issue records them
            reg.add_copies(asset_id, [(f"r{i:06d}", random_codeword(C), None) for i in range(a.copies - 1)])
            reg.commit()
        kf = tracing._setup_keyfile(setup, setup["key"])
        suspect = m.with_vertices(V)

        def extraction():
            mesh, _, _, _ = framework._prepare(suspect, kf)
            return framework.read_soft(mesh, kf, setup["key"])

        t_x, _ = best_of(extraction, 7)
        t_t, r = best_of(lambda: tracing.trace(suspect, registry=reg_path), 7)
    print(f"registry: {a.copies} copies, {C} carriers; traced copy {r['copy']} (issued {cid}), "
          f"P(false alarm) {r['p_false_alarm']:.3g}")
    print(f"extraction {1e3 * t_x:.1f} ms, trace {1e3 * t_t:.1f} ms: tracing costs {1e3 * (t_t - t_x):.1f} ms "
          f"beyond the extraction (target <= 50 ms), {(t_t - t_x) / t_x:.2f}x the extraction")
    return 0 if r["copy"] == cid else 1


if __name__ == "__main__":
    sys.exit(main())
