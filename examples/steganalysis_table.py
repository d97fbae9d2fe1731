"""Thesis Table 6.2 (the §6.4 steganalyzer against Cho's mean method and Yang's method): a wrapper of
the ``cho_table`` part of examples/studies/steganalysis.toml (``meshmark study run``; the code is
meshmark.steganalysis.table62).

    .venv/bin/python examples/steganalysis_table.py [--folders DIR ...] [--out out/steganalysis_table]
                                                    [--limit N] [--no-variants]
"""
import argparse
import pathlib
import tomllib

from meshmark.study import run

SPEC = pathlib.Path(__file__).resolve().parent / "studies" / "steganalysis.toml"

if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--folders", nargs="+", default=None, help="default: the spec's cho_table folders")
    ap.add_argument("--out", default="out/steganalysis_table")
    ap.add_argument("--limit", type=int, default=0, help="at most this many models per folder (0: all)")
    ap.add_argument("--no-variants", action="store_true", help="only the Table 6.2 cases")
    a = ap.parse_args()
    raw = tomllib.loads(SPEC.read_text())
    ct = raw["steganalysis"]["cho_table"]
    ct["folders"] = [str((SPEC.parent / f).resolve()) for f in ct["folders"]]
    if a.folders:
        ct["folders"] = [str(pathlib.Path(f).resolve()) for f in a.folders]
    ct.update(limit=a.limit, variants=not a.no_variants)
    raw["steganalysis"]["parts"] = ["cho_table"]
    run(raw, a.out, log=print)
