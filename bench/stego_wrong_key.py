"""Issue 23: does a wrong key tell a stego mesh from a clean one? (docs/stego.md §5, "What an
observer learns without the key").

N base meshes (the shared classic and corpus meshes, then generated noisy tori and cylinders; meshes
over --max-vertices are left out): each is embedded with a random message under the right key and
written as a file (fixed32: OBJ, 17 digits; float32: binary float PLY), and the clean base is
written in the same format. Then ``meshmark stego extract`` (in process, click's runner) with a
wrong key on all 2N files: the reason printed and the exit code are tallied, and the time of the
extraction itself (``stego.extract`` on the mesh read back) is measured for every file, stego and
clean interleaved. The timing figures: median per group, the paired median difference (stego minus
clean of the same base mesh) with a Wilcoxon signed-rank test, and a Mann-Whitney U test of the two
groups.

    nice -n 10 .venv/bin/python bench/stego_wrong_key.py [--n 100] [--precision fixed32|float32]
"""
from __future__ import annotations

import argparse
import collections
import os
import pathlib
import sys
import tempfile
import time

import numpy as np

import meshmark
from meshmark import shapes, stego

SHARED = pathlib.Path(os.environ.get("MESHMARK_SHARED", pathlib.Path(__file__).resolve().parents[2] / "shared")) / "meshes"
EXT = {"fixed32": ".obj", "float32": ".ply"}


def generated(i: int, rng) -> meshmark.Mesh:
    """A noisy torus or cylinder of a few thousand vertices (seeded)."""
    if i % 2:
        m = shapes.torus(int(rng.integers(24, 80)), int(rng.integers(12, 40)), 1.0, float(rng.uniform(0.2, 0.45)))
    else:
        m = shapes.cylinder(int(rng.integers(16, 64)), int(rng.integers(16, 96)), float(rng.uniform(0.1, 0.5)),
                            float(rng.uniform(1, 3)))
    scale = 0.002 * float(np.ptp(m.V, axis=0).max())
    return m.with_vertices(m.V + rng.normal(scale=scale, size=m.V.shape))

def base_meshes(n: int, max_vertices: int, rng):
    out = []
    for sub in ("classic", "corpus"):
        for p in sorted((SHARED / sub).iterdir()):
            if len(out) >= n:
                return out
            try:
                m = meshmark.read_mesh(p)
            except meshmark.MeshError:
                continue
            if 200 <= m.n_vertices <= max_vertices and m.n_faces:
                out.append((p.name, m))
    i = 0
    while len(out) < n:
        out.append((f"generated-{i}", generated(i, rng)))
        i += 1
    return out

def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--n", type=int, default=100, help="stego meshes (and as many clean ones)")
    ap.add_argument("--precision", choices=sorted(EXT), default="fixed32")
    ap.add_argument("--max-vertices", type=int, default=60_000)
    ap.add_argument("--seed", type=int, default=23)
    a = ap.parse_args()
    from click.testing import CliRunner
    from scipy import stats

    from meshmark.cli import main as cli
    from meshmark.stego.cli import write_verified

    rng = np.random.default_rng(a.seed)
    runner = CliRunner()
    answers = collections.Counter()
    t_stego, t_clean, skipped = [], [], []
    with tempfile.TemporaryDirectory() as d:
        bases = base_meshes(a.n + 20, a.max_vertices, rng)  # spares for meshes too small to embed into
        pairs = []
        for name, m in bases:
            if len(pairs) >= a.n:
                break
            cap = stego.capacity(m, precision=a.precision)["max_message_bytes"]
            if cap < 1:
                skipped.append(name)
                continue
            msg = rng.integers(0, 256, int(min(cap, 256)), dtype=np.uint8).tobytes()
            res = stego.embed(m, msg, "the right key", precision=a.precision)
            sp = os.path.join(d, f"s{len(pairs)}{EXT[a.precision]}")
            write_verified(sp, m, res.V, a.precision,
                           lambda back: stego.extract(back, "the right key", precision=a.precision).message == msg)
            cp = os.path.join(d, f"c{len(pairs)}{EXT[a.precision]}")
            meshmark.write_mesh(cp, m, binary=True, float32=a.precision == "float32", precision=17)
            pairs.append((name, sp, cp))
        for name, sp, cp in pairs:
            for kind, p in (("stego", sp), ("clean", cp)):
                r = runner.invoke(cli, ["stego", "extract", p, "--key", "a wrong key", "--precision", a.precision],
                                  catch_exceptions=False)
                msg = r.output.strip().split(": ", 1)[-1]
                answers[(kind, r.exit_code, msg)] += 1
            ms, mc = meshmark.read_mesh(sp), meshmark.read_mesh(cp)
            for kind, mm, acc in (("stego", ms, t_stego), ("clean", mc, t_clean)) if rng.random() < 0.5 else \
                    (("clean", mc, t_clean), ("stego", ms, t_stego)):
                t0 = time.perf_counter()
                stego.extract(mm, "a wrong key", precision=a.precision)
                acc.append(time.perf_counter() - t0)
    n_gen = sum(name.startswith("generated") for name, _, _ in pairs)
    print(f"{len(pairs)} stego + {len(pairs)} clean meshes ({a.precision}; bases: {len(pairs) - n_gen} shared, "
          f"{n_gen} generated); too small to embed into: {len(skipped)}")
    print("answers (group, exit code, message) -> count:")
    for k, v in sorted(answers.items()):
        print(f"  {k}: {v}")
    distinct = {(c, m) for (_, c, m) in answers}
    print(f"distinct (exit code, message) over all {sum(answers.values())} runs: {len(distinct)}")
    ts, tc = np.array(t_stego), np.array(t_clean)
    diff = ts - tc
    w = stats.wilcoxon(ts, tc)
    u = stats.mannwhitneyu(ts, tc)
    print(f"extract time, median: stego {1e3 * np.median(ts):.1f} ms, clean {1e3 * np.median(tc):.1f} ms; "
          f"paired median difference (stego - clean) {1e3 * np.median(diff):+.2f} ms "
          f"(IQR {1e3 * np.percentile(diff, 25):+.2f} .. {1e3 * np.percentile(diff, 75):+.2f} ms); "
          f"Wilcoxon signed-rank p = {w.pvalue:.3g}; Mann-Whitney U p = {u.pvalue:.3g}")
    return 0 if len(distinct) == 1 else 1

if __name__ == "__main__":
    sys.exit(main())
