"""Helpers shared by the bench scripts (timing, subdivided shared meshes). Not a test module."""
from __future__ import annotations

import pathlib
import time

import numpy as np

import meshmark

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"


def best_of(fn, repeat: int = 5):
    """Best wall time (s) over `repeat` runs, and the last result."""
    best, out = float("inf"), None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def best_of_clocks(fn, repeat: int = 3):
    """Best wall time and best CPU time (s, this process) over `repeat` runs, and the last result:
    on a shared machine the CPU time is the figure that does not depend on the other jobs."""
    wall, cpu, out = float("inf"), float("inf"), None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        wall, cpu = min(wall, time.perf_counter() - t), min(cpu, time.process_time() - c)
    return wall, cpu, out


def midpoint_subdivide(V: np.ndarray, F: np.ndarray):
    """One level of 1-to-4 midpoint subdivision (vectorized numpy)."""
    E, _ = meshmark.unique_edges(V, F)
    n = len(V)
    key = lambda a, b: np.minimum(a, b).astype(np.int64) * n + np.maximum(a, b)
    ekey = E[:, 0].astype(np.int64) * n + E[:, 1]
    mid = lambda a, b: n + np.searchsorted(ekey, key(a, b))
    a, b, c = F[:, 0], F[:, 1], F[:, 2]
    ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
    F2 = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1),
                         np.stack([ab, bc, ca], 1)])
    V2 = np.vstack([V, 0.5 * (V[E[:, 0]] + V[E[:, 1]])])
    return V2, F2.astype(np.int32)


def big_bunny(min_faces: int = 1_000_000) -> meshmark.Mesh:
    """The shared Stanford bunny, midpoint-subdivided until it has at least `min_faces` triangles."""
    m = meshmark.read_mesh(SHARED / "classic" / "bunny.obj")
    V, F = m.V, m.F
    while len(F) < min_faces:
        V, F = midpoint_subdivide(V, F)
    return meshmark.Mesh(V, F)


def big_elephant(min_vertices: int = 1_000_000, min_faces: int = 0) -> meshmark.Mesh:
    """The shared Elephant, midpoint-subdivided until it has at least `min_vertices` vertices and
    `min_faces` triangles (by default 1,280,700 vertices, 2,561,408 triangles)."""
    m = meshmark.read_mesh(SHARED / "classic" / "elephant.off")
    V, F = m.V, m.F
    while len(V) < min_vertices or len(F) < min_faces:
        V, F = midpoint_subdivide(V, F)
    return meshmark.Mesh(V, F)


def timings(fn, repeat: int = 3):
    """Run ``fn`` ``repeat`` times: ({"best", "median"} wall s, {"best", "median"} CPU s of this process,
    the last result). On a shared machine report both; the CPU time counts both threads of 2."""
    walls, cpus, out = [], [], None
    for _ in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        walls.append(time.perf_counter() - t)
        cpus.append(time.process_time() - c)
    stat = lambda x: {"best": float(np.min(x)), "median": float(np.median(x)), "all": [float(v) for v in x]}
    return stat(walls), stat(cpus), out


def fmt(w: dict, c: dict | None = None, unit: str = "s", scale: float = 1.0) -> str:
    """'best B (median M) s wall[, best b (median m) s CPU]' from :func:`timings`."""
    s = f"best {w['best'] * scale:.3g} (median {w['median'] * scale:.3g}) {unit} wall"
    return s + (f", best {c['best'] * scale:.3g} (median {c['median'] * scale:.3g}) {unit} CPU" if c else "")


def random_codeword(n_bits: int) -> bytes:
    """A random codeword of ``n_bits`` packed as the registry stores it (padding bits zero)."""
    import secrets
    bits = np.unpackbits(np.frombuffer(secrets.token_bytes((n_bits + 7) // 8), np.uint8))[:n_bits]
    return np.packbits(bits).tobytes()
