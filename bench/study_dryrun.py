"""Dry run of a 10^6-task study: planning (spec validation, mesh digests, expansion) and key computation.

    .venv/bin/python bench/study_dryrun.py

200 shared meshes (classic + corpus-large, read in place) x 10 method variants (cho-mean, alpha drawn
in [0.02, 0.06]) x 500 attack settings (uniform noise, 500 strengths) x 1 seed = 1,000,000 tasks.
Prints the wall time of load_spec and of plan, the number of unique keys and the peak RSS of this
process (getrusage), beside the time of hashing the same number of 16-byte digests alone.
"""
import hashlib
import pathlib
import resource
import time

import numpy as np

from meshmark.study import load_spec, plan

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"


def main():
    spec = {"study": {"name": "dryrun-1e6", "seeds": [0]},
            "meshes": {"paths": [str(SHARED / "classic"), str(SHARED / "corpus-large")], "limit": 200},
            "methods": [{"name": "cho-mean", "random": {"alpha": [0.02, 0.06]}, "draws": 10}],
            "attacks": [{"name": "noise", "grid": {"strength": [float(x) for x in np.linspace(1e-4, 5e-3, 500)]}}],
            "measurements": ["nc", "cdr", "detection"]}
    t0 = time.perf_counter()
    sp = load_spec(spec)
    t1 = time.perf_counter()
    keys, idx, digests = plan(sp)
    t2 = time.perf_counter()
    n = len(keys)
    u = len(set(keys))
    t3 = time.perf_counter()
    for i in range(n):
        hashlib.blake2b(b"0123456789abcdef" * 4 + i.to_bytes(8, "little"), digest_size=16).hexdigest()
    t4 = time.perf_counter()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"tasks {n:,} ({len(sp.meshes)} meshes x {len(sp.methods)} methods x {len(sp.attacks)} attacks x "
          f"{len(sp.seeds)} seed), unique keys {u:,}")
    print(f"load_spec {t1 - t0:.2f} s, plan (digests + keys) {t2 - t1:.2f} s, total {t2 - t0:.2f} s; "
          f"bare blake2b of {n:,} keys {t4 - t3:.2f} s; peak RSS {rss:.0f} MB")


if __name__ == "__main__":
    main()
