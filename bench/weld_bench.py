"""Bench: weld_vertices (merge vertices at exactly equal positions) vs numpy's unique(axis=0).

    .venv/bin/python bench/weld_bench.py

Extraction welds before it reads the mark, so the weld is paid on every verify; the budget for
extraction on 1M vertices is 0.3 s (bench/laplacian_bench.py) and the weld must cost well under
50 ms of it. Cases, each ~1M vertices:

* indexed: the shared elephant midpoint-subdivided to >= 1M vertices (nothing to merge: the common
  case, which must stay cheap);
* non-indexed: 350,000 triangles of a subdivided elephant with every corner stored apart (what Blender's
  glTF importer makes of a non-indexed glTF), 3 copies per face corner, welded back;
* shuffled: the non-indexed mesh with its vertices in random order (no memory locality).

Reference: ``numpy.unique(V, axis=0, return_inverse=True)`` (what the add-on used before), which
gives the same partition (checked) but sorts. Best of 5, same process.
"""
import os
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import meshmark  # noqa: E402
from _common import SHARED, best_of, midpoint_subdivide  # noqa: E402


def elephant(min_vertices=None, min_faces=None):
    m = meshmark.read_mesh(SHARED / "classic" / "elephant.off")
    V, F = m.V, m.F
    while (min_vertices and len(V) < min_vertices) or (min_faces and len(F) < min_faces):
        V, F = midpoint_subdivide(V, F)
    return V, F


def numpy_weld(m):
    _, inv = np.unique(m.V, axis=0, return_inverse=True)
    return inv.reshape(-1)


def same_partition(a, b):
    """Whether two labelings group the vertices identically."""
    _, ia = np.unique(a, return_inverse=True)
    _, ib = np.unique(b, return_inverse=True)
    pairs = np.unique(np.stack([ia.ravel(), ib.ravel()], 1), axis=0)
    return len(pairs) == ia.max() + 1 == ib.max() + 1


def main():
    V, F = elephant(min_vertices=1_000_000)
    indexed = meshmark.Mesh(V, F)
    V2, F2 = elephant(min_faces=350_000)
    F2 = F2[:350_000]  # 1.05M corners
    split = meshmark.Mesh(V2[F2.reshape(-1)], np.arange(F2.size, dtype=np.int32).reshape(-1, 3))
    rng = np.random.default_rng(0)
    perm = rng.permutation(split.n_vertices)
    inv = np.empty_like(perm)
    inv[perm] = np.arange(perm.size)
    shuffled = meshmark.Mesh(split.V[perm], inv[split.F].astype(np.int32))
    print(f"{'case':<12} {'vertices':>10} {'faces':>10} {'welded':>10} {'weld_vertices':>14} {'per 1M':>9} "
          f"{'numpy unique':>13}")
    for name, m in (("indexed", indexed), ("non-indexed", split), ("shuffled", shuffled)):
        t, w = best_of(lambda: meshmark.weld_vertices(m))
        t_np, ref = best_of(lambda: numpy_weld(m), repeat=2)
        assert same_partition(w.map, ref), name
        assert np.array_equal(w.mesh.V[w.map], m.V)
        print(f"{name:<12} {m.n_vertices:>10,} {m.n_faces:>10,} {w.mesh.n_vertices:>10,} {1e3 * t:>11.1f} ms "
              f"{1e9 * t / m.n_vertices:>6.1f} ms {1e3 * t_np:>10.0f} ms")
    # what extraction pays for welding on the indexed mesh (laplacian defaults; keyfile with and without weld)
    from meshmark.watermark import laplacian as L
    r = L.embed(indexed, payload="W", key="k")
    kf0 = meshmark.watermark.Keyfile(**{**r.keyfile.__dict__, "weld": False})
    t_w, x_w = best_of(lambda: L.extract(r.V, indexed, keyfile=r.keyfile), repeat=3)
    t_0, x_0 = best_of(lambda: L.extract(r.V, indexed, keyfile=kf0), repeat=3)
    assert x_w.cdr == x_0.cdr == 1.0
    print(f"extract, {indexed.n_vertices:,} vertices: {1e3 * t_w:.0f} ms with weld, {1e3 * t_0:.0f} ms without")


if __name__ == "__main__":
    main()
