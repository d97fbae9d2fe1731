"""Bench: reading a binary PLY of >= 1,000,000 triangles, meshmark vs plyfile (+ numpy) in one run.

    .venv/bin/python bench/read_ply.py

Target (foundation issue): meshmark <= 1 s and not slower than the plyfile reference.
A raw numpy structured-dtype read of this exact layout is printed too, as the lower bound that a
reader specialised to one file layout can reach.
"""
import os
import sys
import tempfile

import numpy as np
from plyfile import PlyData

import meshmark
from _common import best_of, big_bunny


def main():
    mesh = big_bunny()
    path = os.path.join(tempfile.mkdtemp(), "big.ply")
    meshmark.write_mesh(path, mesh, binary=True, float32=True)
    size = os.path.getsize(path) / 1e6
    print(f"file: {mesh.n_vertices:,} vertices, {mesh.n_faces:,} triangles, binary float PLY, {size:.1f} MB")

    t_mm, m = best_of(lambda: meshmark.read_mesh(path), 3)

    def plyfile_read():
        ply = PlyData.read(path)
        v = ply["vertex"].data
        V = np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64)
        F = np.stack(ply["face"].data["vertex_indices"]).astype(np.int32)
        return V, F

    def plyfile_known_len():  # plyfile's fast path, when the caller knows every face is a triangle
        ply = PlyData.read(path, known_list_len={"face": {"vertex_indices": 3}})
        v = ply["vertex"].data
        V = np.stack([v["x"], v["y"], v["z"]], 1).astype(np.float64)
        F = np.asarray(ply["face"].data["vertex_indices"]).astype(np.int32)
        return V, F

    def numpy_raw():  # exact-layout structured read: header skip + np.fromfile
        with open(path, "rb") as f:
            header = b""
            while not header.endswith(b"end_header\n"):
                header += f.readline()
            V = np.fromfile(f, dtype="<f4", count=3 * mesh.n_vertices).reshape(-1, 3).astype(np.float64)
            rec = np.fromfile(f, dtype=[("n", "u1"), ("i", "<i4", 3)], count=mesh.n_faces)
        return V, rec["i"].astype(np.int32)

    t_pf, (Vp, Fp) = best_of(plyfile_read, 1)
    t_pk, _ = best_of(plyfile_known_len, 3)
    t_np, (Vn, Fn) = best_of(numpy_raw, 3)
    assert np.array_equal(m.V, Vp) and np.array_equal(m.F, Fp) and np.array_equal(m.V, Vn)

    print(f"{'reader':<36}{'time (s)':>10}{'meshmark speed-up':>20}")
    for name, t in [("meshmark.read_mesh (CGAL)", t_mm), ("plyfile (general lists)", t_pf),
                    ("plyfile (known_list_len=3)", t_pk), ("numpy fromfile (fixed layout)", t_np)]:
        print(f"{name:<36}{t:>10.3f}{t / t_mm:>19.2f}x")
    ok = t_mm <= 1.0 and t_mm <= t_pf
    print(f"target: <= 1 s and not slower than plyfile: {'MET' if ok else 'NOT MET'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
