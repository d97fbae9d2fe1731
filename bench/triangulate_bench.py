"""Triangulation of one huge polygon: meshmark.triangulate against mapbox_earcut (the earcut C++
library's PyPI wheel, `pip install mapbox-earcut`) in the same process, for 1k/20k/100k/1M corners,
on a deep star (long thin ears), a wavy circle and a star on a saddle (non-planar; meshmark only:
earcut takes 2-D points). Prints the best of 3 wall times and the ratio; then `meshmark info` on
a 20,000- and a 100,000-corner OBJ through the real CLI.

    .venv/bin/python bench/triangulate_bench.py [--max 1000000]
"""
from __future__ import annotations

import argparse
import pathlib
import subprocess
import sys
import tempfile
import time

import numpy as np

import meshmark
from _common import best_of


def star(n, seed=0):
    rng = np.random.default_rng(seed)
    t = 2 * np.pi * np.arange(n) / n
    r = np.where(np.arange(n) % 2, 0.5, 1.0) + rng.uniform(0, 0.3, n)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def wavy(n):
    t = 2 * np.pi * np.arange(n) / n
    r = 1 + 0.05 * np.sin(37 * t) + 0.001 * np.sin(np.arange(n))
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--max", type=int, default=1_000_000)
    args = ap.parse_args()
    try:
        import mapbox_earcut as earcut
    except ImportError:
        earcut = None
        print("mapbox_earcut not installed (pip install mapbox-earcut): meshmark times only")
    print(f"{'shape':8} {'corners':>9} {'meshmark s':>11} {'earcut s':>9} {'ratio':>6}")
    for n in [1000, 20000, 100000, 1000000]:
        if n > args.max:
            continue
        for name, q in [("star", star(n)), ("wavy", wavy(n)), ("saddle", star(n, 1))]:
            z = 0.1 * (q[:, 0] ** 2 - q[:, 1] ** 2) if name == "saddle" else np.zeros(n)
            m = meshmark.Mesh.from_polygons(np.column_stack([q, z]), np.arange(n), np.array([0, n]))
            rep = 1 if n >= 1000000 else 3
            tm, (T, _) = best_of(lambda: meshmark.triangulate(m), rep)
            assert T.shape == (n - 2, 3)
            te = ratio = float("nan")
            if earcut is not None and name != "saddle":
                te, _ = best_of(lambda: earcut.triangulate_float64(q, np.array([n], dtype=np.uint32)), rep)
                ratio = tm / te
            print(f"{name:8} {n:>9} {tm:>11.4f} {te:>9.4f} {ratio:>6.2f}", flush=True)
    with tempfile.TemporaryDirectory() as d:
        for n in [20000, 100000]:
            q = star(n)
            path = pathlib.Path(d) / f"star{n}.obj"
            path.write_text("".join(f"v {x:.17g} {y:.17g} 0\n" for x, y in q) + "f " +
                            " ".join(map(str, range(1, n + 1))) + "\n")
            cli = pathlib.Path(sys.executable).with_name("meshmark")
            t = time.perf_counter()
            subprocess.run([str(cli), "info", str(path), "--json"], check=True, capture_output=True)
            print(f"meshmark info, one {n}-corner star face ({path.stat().st_size / 1e6:.1f} MB OBJ): "
                  f"{time.perf_counter() - t:.2f} s (process start included)")


if __name__ == "__main__":
    main()
