"""Two concurrent ``meshmark issue --copies 8`` processes on one new registry, repeated.

    .venv/bin/python bench/registry_concurrency.py [--runs 20] [--mesh classic/cow.obj]

Per run: both exit statuses, the ids recorded (16 distinct expected: 0001..0016) and whether every
copy file traces to its own id. The same check as tests/test_registry_hardening.py (3 runs there)."""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tests"))

from registry_cases import concurrent_run  # noqa: E402

SHARED = os.path.join(HERE, "..", "..", "shared", "meshes")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=20)
    ap.add_argument("--copies", type=int, default=8)
    ap.add_argument("--mesh", default="classic/cow.obj")
    a = ap.parse_args(argv)
    src = os.path.join(SHARED, a.mesh)
    good = 0
    for run in range(a.runs):
        with tempfile.TemporaryDirectory() as d:
            t = time.perf_counter()
            r = concurrent_run(src, d, a.copies)
            want = [f"{i:04d}" for i in range(1, 2 * a.copies + 1)]
            ok = r["codes"] == [0, 0] and r["ids"] == want and r["traced"] == {c: c for c in want}
            good += ok
            print(f"run {run + 1:2d}: exit {r['codes']}, {len(set(r['ids']))} distinct ids, "
                  f"{sum(k == v for k, v in r['traced'].items())} traced to themselves, "
                  f"{time.perf_counter() - t:.1f} s{'' if ok else '  FAILED ' + ' | '.join(r['errors'])}", flush=True)
    print(f"{good} of {a.runs} runs: two issues of {a.copies} copies each gave {2 * a.copies} distinct copies, "
          "each traced to itself")
    return 0 if good == a.runs else 1


if __name__ == "__main__":
    sys.exit(main())
