"""``meshmark steganalysis features|train|detect|evaluate`` (registered on the ``steganalysis`` group of
meshmark.cli; ``cho`` lives there). Bad input raises MeshError (exit status 2)."""
from __future__ import annotations

import csv
import pathlib
import sys

import click

from .. import jsonout
from .._core import MeshError


_emit = jsonout.emit


def _set_option(f):
    return click.option("--set", "feature_set", default="yang208", show_default=True,
                        help="Feature set: yang208, lfs76s, nvt36s (the stabilised sets), lfs76, nvt36 (as published) "
                             "or a '+' combination (yang208+lfs76s+nvt36s).")(f)


def check_output_path(out, force: bool | None = None, option: str = "--out") -> pathlib.Path:
    """MeshError (exit 2) before any work when ``out`` cannot be written: a folder, a missing or
    read-only parent folder; with ``force=False``, an existing file."""
    import os
    p = pathlib.Path(out)
    if force is False and p.exists() and not p.is_dir():
        raise MeshError(f"{option} {out} already exists; pass --force to overwrite it")
    if p.is_dir():
        raise MeshError(f"--out {out} is a folder; give a file name (.npz)")
    parent = p.parent if str(p.parent) else pathlib.Path(".")
    if not parent.is_dir():
        raise MeshError(f"--out {out}: the folder {parent} does not exist")
    if not os.access(parent, os.W_OK | os.X_OK):
        raise MeshError(f"--out {out}: the folder {parent} is not writable")
    if p.exists() and not os.access(p, os.W_OK):
        raise MeshError(f"--out {out} exists and is not writable")
    return p


def _write_csv(path, rows, fields, force: bool) -> None:
    import io
    from ..atomic import write_text
    buf = io.StringIO(newline="")
    w = csv.DictWriter(buf, fieldnames=fields)
    w.writeheader()
    w.writerows(rows)
    if not force and pathlib.Path(path).exists():  # appeared while the evaluation ran
        raise MeshError(f"--csv {path} already exists; pass --force to overwrite it")
    write_text(path, buf.getvalue())


def add_commands(group: click.Group) -> None:
    @group.command("features")
    @click.argument("inp", metavar="IN")
    @_set_option
    @jsonout.option()
    def features_cmd(inp, feature_set, as_json):
        """The steganalysis feature vector of IN."""
        from .features import feature_names, features

        F = features(inp, feature_set)
        names = feature_names(feature_set)
        d = {"input": inp, "feature_set": feature_set, "n_features": int(F.size), "features": [float(x) for x in F],
             "names": names}
        _emit(d, as_json, "\n".join(f"{n:32s} {x: .6g}" for n, x in zip(names, F)), aliases={"set": "feature_set"})

    @group.command("train")
    @click.argument("covers", nargs=-1, required=True)
    @click.option("--out", "out", required=True, type=click.Path(), help="Model file to write (.npz).")
    @_set_option
    @click.option("--classifier", type=click.Choice(["ensemble", "qda"]), default="ensemble", show_default=True)
    @click.option("--methods", default=None, help="Comma-separated stego methods to generate (default: all registered; 'none': only --stego).")
    @click.option("--stego", "stego", multiple=True, help="Folder or file of stego meshes made elsewhere (repeatable).")
    @click.option("--seed", type=int, default=0, show_default=True)
    @click.option("--domain-rate", type=click.FloatRange(0, 0.5), default=0.05, show_default=True,
                  help="Domain check: share of the training covers (each against the others) beyond which a mesh is "
                       "'cannot judge'; 0 = no check.")
    @click.option("--force", is_flag=True, default=False, help="Overwrite an existing --out.")
    @jsonout.option("Print a summary as JSON.")
    def train_cmd(covers, out, feature_set, classifier, methods, stego, seed, domain_rate, force, as_json):
        """Train a universal and per-method detectors on the cover meshes COVERS (files or folders) and
        their stego versions, and save the model to --out."""
        import numpy as np

        from . import protocol as P
        from .model import Model, corpus_hash

        from ..ranges import check_seed
        check_output_path(out, force)  # before hours of training (issue 23)
        check_seed(seed)
        paths = P.mesh_files(covers)
        if not paths:
            raise MeshError(f"empty training corpus: no .obj/.off/.ply/.stl meshes in {', '.join(covers)}")
        ms = [] if methods == "none" else (methods.split(",") if methods else None)
        with P.one_thread():
            ds = P.build_dataset(paths, ms, (feature_set,), seed=seed)
            X, y, lab = ds["X"][feature_set], ds["method"] != "cover", list(ds["method"])
            if stego:
                from .features import features
                ext = [features(p, feature_set) for p in P.mesh_files(stego)]
                if ext:
                    X = np.vstack([X, ext])
                    y = np.r_[y, np.ones(len(ext), bool)]
                    lab += ["external"] * len(ext)
            if len(X) == 0:
                raise MeshError("empty training corpus: no cover could be read and featurised")
            training = {"corpus_hash": corpus_hash(paths), "n_covers": int((~y).sum()), "n_stego": int(y.sum()),
                        "methods": sorted({l for l in lab if l != "cover"}), "seed": seed,
                        "covers": [pathlib.Path(p).name for p in ds["path"]]}
            model = Model.train(X, y, lab, feature_set, classifier, training)
            c = np.flatnonzero(ds["method"] == "cover")
            if domain_rate > 0 and len(c) >= 2:
                model.training["domain"] = model.set_domain(X[c], ds["cover"][c], rate=domain_rate, group_kind="one cover file")
        model.save(out, overwrite=force)
        d = {"output": out, "model": out, "feature_set": feature_set, "classifier": classifier, **{k: v for k, v in training.items()
                                                                                  if k != "covers"}}
        _emit(d, as_json, f"wrote {out}: {classifier} on {feature_set}, {d['n_covers']} covers, {d['n_stego']} stego "
                          f"({', '.join(d['methods'])})")

    @group.command("detect")
    @click.argument("inp", metavar="IN")
    @click.option("--model", "model_path", default=None, type=click.Path(dir_okay=False),
                  help="Model file (default: the model shipped with meshmark).")
    @jsonout.option()
    def detect_cmd(inp, model_path, as_json):
        """Is IN a stego mesh? The verdict ("marked", "no evidence" or "cannot judge": the mesh lies outside
        the model's training covers or is too small), the universal probability and one per stego method.

        Exit status: 0 marked, 1 no evidence or cannot judge, 2 error."""
        from .model import Model

        model = Model.load(model_path)
        r = model.detect(inp)
        d = {"input": inp, "verdict": r["verdict"], "reason": r["reason"], "detected": bool(r["marked"]),
             "probability": r["probability"], "threshold": r["threshold"],
             "methods": r["methods"], "feature_set": r["feature_set"], "classifier": r["classifier"],
             "model": str(model_path or "default")}
        for k in ("domain_distance", "domain_threshold", "in_domain"):
            if k in r:
                d[k] = r[k]
        if "operating_point" in r:  # the model's cross-validated false-positive and detection rates
            d["operating_point"] = r["operating_point"]
        if "in_distribution" in r:  # the model has an out-of-distribution guard
            d.update(in_distribution=bool(r["in_distribution"]), outside_fraction=r["outside_fraction"])
            if "warning" in r:
                d["warning"] = r["warning"]
        per = ", ".join(f"{k} {v:.2f}" for k, v in sorted(r["methods"].items(), key=lambda kv: -kv[1]))
        head = (f"{inp}: CANNOT JUDGE: {d['reason']}" if d["verdict"] == "cannot judge" else
                f"{inp}: {'MARKED' if d['detected'] else 'no evidence of a mark'} (universal P = {d['probability']:.2f}, "
                f"marked above {d['threshold']:.2f})")
        _emit(d, as_json, head + (f"\nper method: {per}" if per else "")
                          + (f"\nwarning: {d['warning']}" if "warning" in d else "")
                          + (f"\nthis model, cross-validated on its covers: {100 * d['operating_point']['cv_fpr']:.0f} % of "
                             f"clean meshes called marked, {100 * d['operating_point']['cv_tpr']:.0f} % of marked ones found"
                             if "operating_point" in d else ""), aliases={"marked": "detected"})
        sys.exit(0 if d["detected"] else 1)

    @group.command("evaluate")
    @click.argument("covers", nargs=-1, required=True)
    @_set_option
    @click.option("--classifier", type=click.Choice(["ensemble", "qda"]), default="ensemble", show_default=True)
    @click.option("--splits", type=int, default=30, show_default=True, help="Random splits, 1..10,000.")
    @click.option("--test-fraction", type=float, default=0.3, show_default=True,
                  help="Share of the covers tested per split, (0, 1).")
    @click.option("--methods", default=None, help="Comma-separated stego methods (default: all registered).")
    @click.option("--dataset", type=click.Path(dir_okay=False),
                  help="Cache of the features (.npz): read if present and built for the same covers, methods and sets, else written.")
    @click.option("--protocol", "proto", type=click.Choice(["splits", "sources"]), default="splits", show_default=True,
                  help="splits: the thesis' random cover-level splits; sources: leave one source out (per-source table).")
    @click.option("--dedup/--no-dedup", default=True, show_default=True,
                  help="Drop covers that are the same geometry as another (byte-identical or another format / order).")
    @click.option("--csv", "csv_path", type=click.Path(dir_okay=False), help="Write one row per split and detector.")
    @click.option("--force", is_flag=True, default=False, help="Overwrite an existing --csv file.")
    @jsonout.option("Print the median table as JSON.")
    def evaluate_cmd(covers, feature_set, classifier, splits, test_fraction, methods, dataset, proto, dedup, csv_path,
                     force, as_json):
        """Thesis chapter 8 protocol on COVERS: random cover-level splits (or, with --protocol sources,
        leave one source out), specific and universal detectors, median accuracy / TPR / FPR / P_E."""
        from . import protocol as P

        from ..ranges import check_float, check_int
        check_int("splits", splits, 1, 10_000)  # before the corpus is read
        check_float("test_fraction", test_fraction, 0.0, 1.0, low_open=True, high_open=True)
        if dataset:
            check_output_path(dataset, option="--dataset")  # a cache: read when it matches, never replaced
        if csv_path:
            check_output_path(csv_path, force, "--csv")
        paths = P.mesh_files(covers)
        if not paths:
            raise MeshError(f"empty corpus: no meshes in {', '.join(covers)}")
        if dedup:
            from .sources import deduplicate
            paths = [g[0] for g in deduplicate(paths)]
        ms = methods.split(",") if methods else None
        sets = tuple(feature_set.split("+"))
        key = P.dataset_key(paths, ms, sets)
        ds = None
        if dataset and pathlib.Path(dataset).is_file():
            ds = P.load_dataset(dataset, expect_key=key)  # MeshError when built for other covers / methods / sets
        if ds is None:
            with P.one_thread():
                ds = P.build_dataset(paths, ms, sets)
            if dataset:
                P.save_dataset(ds, dataset, key=key)
        if proto == "sources":
            from .loso import evaluate_by_source, source_table
            rows = evaluate_by_source(ds, feature_set, classifier)
            table = source_table(rows)
            if csv_path:
                _write_csv(csv_path, rows, sorted({k for r in rows for k in r}), force)
            text = "| source | covers | universal | universal@5% | FPR | TPR |\n|---|---:|---:|---:|---:|---:|\n" + "\n".join(
                f"| {r['source']} | {r['n_covers']} | {r['universal']:.3f} | {r['universal@fpr']:.3f} | {r['fpr']:.3f} | "
                f"{r['tpr']:.3f} |" for r in table)
            _emit({"feature_set": feature_set, "classifier": classifier, "protocol": "sources", "table": table},
                  as_json, text)
            return
        rows = P.evaluate(ds, feature_set, classifier, splits, test_fraction)
        if csv_path:
            _write_csv(csv_path, rows, list(rows[0]), force)
        table = P.median_table(rows)
        text = "| detector | splits | accuracy | TPR | FPR | P_E |\n|---|---:|---:|---:|---:|---:|\n" + "\n".join(
            f"| {r['detector']} | {r['splits']} | {r['median_accuracy']:.3f} | {r['median_tpr']:.3f} | "
            f"{r['median_fpr']:.3f} | {r['median_pe']:.3f} |" for r in table)
        _emit({"feature_set": feature_set, "classifier": classifier, "table": table}, as_json, text)
