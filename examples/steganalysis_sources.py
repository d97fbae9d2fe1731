"""The headline steganalysis protocol on the shared corpora: leave one source out, beside the thesis'
random splits (docs/steganalysis.md §6).

    nice -n 10 .venv/bin/python examples/steganalysis_sources.py [--folders classic corpus corpus-large]
        [--dataset out/sources/dataset.npz] [--set yang208+lfs76s+nvt36s] [--splits 30] [--out out/sources] [--quick]

1. Covers: every mesh of the folders (under ../shared/meshes), deduplicated by geometry
   (sources.deduplicate: byte-identical files, the same geometry in another format or order); each is
   marked once by every registered stego method (protocol.build_dataset, seeded); features cached in
   --dataset (keyed on covers, methods and sets: a cache built for others is refused).
2. Leave one source out (loso.evaluate_by_source): per source, the universal detector at 0.5 and at the
   threshold calibrated to 5 % FPR on the training sources, its detection rate per method at that
   threshold, and every specific detector's accuracy -> OUT/sources.csv, OUT/sources_table.csv.
3. The thesis protocol on the same dataset (30 random cover-level splits) -> OUT/splits_median.csv.
Prints both as Markdown tables. `--quick`: two sources, three methods, two splits (tested).
"""
from __future__ import annotations

import argparse
import csv
import pathlib
import sys
import time

import numpy as np

from meshmark.steganalysis import loso, protocol as P
from meshmark.steganalysis.sources import deduplicate, source_of

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"


def write(path, rows):
    keys = sorted({k for r in rows for k in r})
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--folders", nargs="+", default=["classic", "corpus", "corpus-large"])
    ap.add_argument("--dataset", default=None)
    ap.add_argument("--set", dest="fset", default="yang208+lfs76s+nvt36s")
    ap.add_argument("--splits", type=int, default=30)
    ap.add_argument("--out", default="out/sources")
    ap.add_argument("--quick", action="store_true")
    a = ap.parse_args(argv)
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    files = P.mesh_files([SHARED / f for f in a.folders])
    methods = None
    if a.quick:
        files = [p for p in files if source_of(p) in ("pmp-data", "tosca")] or files[:4]
        methods, a.splits = ["cho-variance", "lsb-5deg", "radial"], 2
    groups = deduplicate(files)
    dups = [g for g in groups if len(g) > 1]
    files = [g[0] for g in groups]
    print(f"{len(files)} covers after deduplication ({sum(len(g) - 1 for g in dups)} duplicates: "
          + "; ".join(" = ".join(str(p.relative_to(SHARED)) for p in g) for g in dups) + ")")
    sets = tuple(a.fset.split("+"))
    key = P.dataset_key(files, methods, sets)
    dpath = pathlib.Path(a.dataset) if a.dataset else out / "dataset.npz"
    t0 = time.perf_counter()
    if dpath.is_file():
        ds = P.load_dataset(dpath, expect_key=key)
    else:
        with P.one_thread():
            ds = P.build_dataset(files, methods, sets, log=lambda s: print(s, file=sys.stderr, flush=True))
        P.save_dataset(ds, dpath, key=key)
    print(f"dataset {len(ds['method'])} rows ({time.perf_counter() - t0:.0f} s)")
    t1 = time.perf_counter()
    rows = loso.evaluate_by_source(ds, a.fset, "ensemble")
    table = loso.source_table(rows)
    write(out / "sources.csv", rows)
    write(out / "sources_table.csv", table)
    meths = sorted({k.split(":", 1)[1] for d in table for k in d if k.startswith("specific:")})
    print(f"\nLeave one source out, {a.fset} + ensemble ({time.perf_counter() - t1:.0f} s)")
    print("| source | covers | universal (0.5) | universal (5 % FPR point) | FPR | TPR | "
          + " | ".join(f"{m} det. / spec." for m in meths) + " |")
    print("|---|---:|---:|---:|---:|---:|" + "---:|" * len(meths))
    for d in table:
        print(f"| {d['source']} | {d['n_covers']} | {d['universal']:.3f} | {d['universal@fpr']:.3f} | {d['fpr']:.3f} | "
              f"{d['tpr']:.3f} | " + " | ".join(f"{d.get('detects:' + m, np.nan):.2f} / {d.get('specific:' + m, np.nan):.2f}"
                                                for m in meths) + " |")
    t2 = time.perf_counter()
    med = P.median_table(P.evaluate(ds, a.fset, "ensemble", a.splits, 0.3))
    write(out / "splits_median.csv", med)
    print(f"\nThesis protocol ({a.splits} random cover-level splits, 30 % test; {time.perf_counter() - t2:.0f} s)")
    print("| detector | accuracy | TPR | FPR | P_E |\n|---|---:|---:|---:|---:|")
    for r in med:
        print(f"| {r['detector']} | {r['median_accuracy']:.3f} | {r['median_tpr']:.3f} | {r['median_fpr']:.3f} | "
              f"{r['median_pe']:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
