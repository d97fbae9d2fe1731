"""SIGKILL at 200 random moments of ``meshmark embed --force`` (issue 23 acceptance; the CI test,
tests/test_file_safety.py, does 40). Each kill lands at a uniform moment of a full run, or (every
other kill) in its last quarter where the files are written; after each kill the mesh and keyfile
at the output paths are classified, then a complete run must leave no meshmark temporary.

    nice -n 10 .venv/bin/python bench/kill_embed.py --kills 200 --seed 0

Prints a JSON summary; exit status 1 if any kill left a new mesh beside an old or missing keyfile
(the loop stops with the offending state) or a complete run left a temporary.
"""
from __future__ import annotations

import argparse
import json
import pathlib
import sys
import tempfile

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1] / "tests"))
import kill_embed  # noqa: E402

import meshmark  # noqa: E402
from meshmark.shapes import torus  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--kills", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--full-every", type=int, default=1, help="A complete run after every N kills.")
    a = ap.parse_args()
    with tempfile.TemporaryDirectory() as d:
        d = pathlib.Path(d)
        src = d / "in.ply"
        meshmark.write_mesh(src, torus(200, 150))  # 30,000 vertices
        try:
            seen, full = kill_embed.kill_run(src, d / "o.ply", d / "k.json", ["a", "b"], a.kills, a.seed, a.full_every)
        except AssertionError as exc:
            print(json.dumps({"kills": a.kills, "violation": str(exc)}, indent=1))
            return 1
    print(json.dumps({"kills": a.kills, "seed": a.seed, "mesh_vertices": 30000, **seen, "violations": 0}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
