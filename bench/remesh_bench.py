"""Bench: meshmark's isotropic remeshing (CGAL, native) next to pymeshlab's
meshing_isotropic_explicit_remeshing at the same target length and iterations, in the same process.
Not a test.

    .venv/bin/python bench/remesh_bench.py [--mesh classic/bunny.obj] [--repeat 3]

Prints the time of each, the ratio (> 1: meshmark is faster), and the vertex counts and mean edge
lengths of both results.
"""
import argparse
import pathlib
import time

import numpy as np

import meshmark
from meshmark import attacks as A

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"


def edges(V, T):
    E = np.unique(np.sort(np.concatenate([T[:, [0, 1]], T[:, [1, 2]], T[:, [2, 0]]]), 1), axis=0)
    return np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)


def main():
    import pymeshlab
    ap = argparse.ArgumentParser()
    ap.add_argument("--mesh", default="classic/bunny.obj")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--iterations", type=int, default=3)
    a = ap.parse_args()
    m = meshmark.read_mesh(SHARED / a.mesh)
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    m = meshmark.Mesh(m.V[used], (np.cumsum(used) - 1)[m.triangles])
    t_mm, t_ml = [], []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        out, L = A.remesh(m, iterations=a.iterations, return_target=True)
        t_mm.append(time.perf_counter() - t0)
        ms = pymeshlab.MeshSet()
        ms.add_mesh(pymeshlab.Mesh(m.V, m.triangles))
        t0 = time.perf_counter()
        ms.meshing_isotropic_explicit_remeshing(iterations=a.iterations, targetlen=pymeshlab.PureValue(L))
        t_ml.append(time.perf_counter() - t0)
    ref = ms.current_mesh()
    print(f"{a.mesh}: {m.n_vertices} vertices, {m.n_faces} triangles, target L = {L:.6g}, {a.iterations} iterations")
    print(f"meshmark (CGAL)  best {min(t_mm):.3f} s  -> {out.n_vertices} vertices, mean edge {edges(out.V, out.triangles).mean() / L:.3f} L")
    print(f"pymeshlab        best {min(t_ml):.3f} s  -> {ref.vertex_number()} vertices, mean edge "
          f"{edges(ref.vertex_matrix(), ref.face_matrix()).mean() / L:.3f} L")
    print(f"ratio pymeshlab / meshmark = {min(t_ml) / min(t_mm):.2f}")


if __name__ == "__main__":
    main()
