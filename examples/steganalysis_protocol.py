"""Thesis ch. 8 protocol on the shared corpora (specific and universal detectors for every feature set
and classifier, 30 cover-level splits, medians, Figs. 8.3-8.5, the ranking by detectability, hold-out
covers): a wrapper of the ``protocol`` part of examples/studies/steganalysis.toml (``meshmark study
run``; the code is meshmark.steganalysis.study).

    .venv/bin/python examples/steganalysis_protocol.py [--out out/steganalysis_protocol] [--splits 30]
        [--folders DIR ...] [--subset psb-seg] [--no-pca] [--holdout 20]

OUT/dataset.npz caches the features (delete it to rebuild). Writes OUT/tables.md, protocol_*.csv/png.
"""
import argparse
import pathlib
import tomllib

from meshmark.study import run

SPEC = pathlib.Path(__file__).resolve().parent / "studies" / "steganalysis.toml"

if __name__ == "__main__":
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="out/steganalysis_protocol")
    ap.add_argument("--folders", nargs="+", default=None, help="default: the spec's folders")
    ap.add_argument("--splits", type=int, default=None)
    ap.add_argument("--subset", default=None, help="only covers whose path contains this (e.g. psb-seg)")
    ap.add_argument("--no-pca", action="store_true", help="skip the accuracy-vs-components curve")
    ap.add_argument("--holdout", type=int, default=None, help="procedural covers (not in ../shared) to test on")
    a = ap.parse_args()
    raw = tomllib.loads(SPEC.read_text())
    cfg = raw["steganalysis"]
    cfg["parts"] = ["protocol"]
    cfg["folders"] = [str(pathlib.Path(f).resolve()) for f in a.folders] if a.folders else \
        [str((SPEC.parent / f).resolve()) for f in cfg["folders"]]
    for k, v in (("splits", a.splits), ("subset", a.subset), ("holdout", a.holdout)):
        if v is not None:
            cfg[k] = v
    if a.no_pca:
        cfg["pca_k"] = []
    run(raw, a.out, log=print)
