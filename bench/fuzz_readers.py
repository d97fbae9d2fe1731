"""A larger fuzz campaign of the mesh readers than the CI test (tests/test_fuzz_readers.py).

Default: 10,000 cases, with the large Horse PLY, Bunny OBJ and Elephant OFF among the seeds and
mesh_info run on every mesh that reads; several seeds can be given. Prints the JSON summary of each
seed (outcome counts, largest RSS growth as a multiple of the file size, failures with the kept file).

    .venv/bin/python bench/fuzz_readers.py --cases 10000 --seeds 1 2 --keep /tmp/fuzz-failures
"""
import argparse
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests"))
import fuzz_readers  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=10000)
    ap.add_argument("--seeds", type=int, nargs="+", default=[1])
    ap.add_argument("--keep", default="/tmp/meshmark-fuzz-failures")
    ap.add_argument("--no-large", action="store_true")
    ap.add_argument("--no-info", action="store_true")
    a = ap.parse_args()
    bad = 0
    for seed in a.seeds:
        d = fuzz_readers.run(a.cases, seed, keep=a.keep, large=not a.no_large, progress=True, info=not a.no_info)
        bad += len(d["failures"])
        print(json.dumps(d, indent=1), flush=True)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
