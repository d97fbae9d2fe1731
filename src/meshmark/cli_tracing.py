"""``meshmark issue`` and ``meshmark trace``: copy tracing (meshmark.watermark.tracing)."""
from __future__ import annotations

import csv
import os
import sys

import click

from . import jsonout
from ._core import MeshError


def _read_ids(path: str) -> list:
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = [r for r in csv.reader(f) if r and r[0].strip() and not r[0].startswith("#")]
    except OSError as exc:
        raise MeshError(f"cannot read --ids '{path}': {exc.strerror or exc}") from None
    ids = [r[0].strip() for r in rows]
    if ids and ids[0].lower() in ("id", "copy", "copy_id"):
        ids = ids[1:]
    if not ids:
        raise MeshError(f"--ids '{path}' lists no ids (one per line, first column)")
    return ids


@click.command()
@click.argument("inp", metavar="IN")
@click.argument("outdir", metavar="OUTDIR")
@click.option("--copies", type=int, default=None, help="Number of copies (ids continue the registry's numbering).")
@click.option("--ids", "ids_csv", type=click.Path(dir_okay=False), default=None,
              help="CSV file with one copy id per line (first column), instead of --copies.")
@click.option("--key", required=True, help="The owner's secret key.")
@click.option("--registry", required=True, type=click.Path(dir_okay=False), help="SQLite registry (created if missing).")
@click.option("--method", type=click.Choice(["laplacian", "cho-mean", "cho-variance", "radial"]), default="laplacian",
              show_default=True)
@click.option("--params", "params_mode", type=click.Choice(["auto", "thesis"]), default="auto", show_default=True)
@click.option("--force", is_flag=True, default=False, help="Overwrite existing copy files in OUTDIR.")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def issue(inp, outdir, copies, ids_csv, key, registry, method, params_mode, force, as_json):
    """Write marked copies of IN into OUTDIR (IN's format), each with its own codeword, and record
    them in the registry."""
    from .atomic import write_all
    from .io import mesh_outputs, read_mesh
    from .watermark import tracing

    if (copies is None) == (ids_csv is None):
        raise MeshError("give exactly one of --copies N or --ids ids.csv")
    ids = _read_ids(ids_csv) if ids_csv else None
    mesh, fmt = read_mesh(inp, return_info=True)
    stem, ext = os.path.splitext(os.path.basename(inp))
    os.makedirs(outdir, exist_ok=True)
    if ids is not None and not force:
        clash = [c for c in ids if os.path.exists(os.path.join(outdir, f"{stem}-{c}{ext}"))]
        if clash:
            raise MeshError(f"{os.path.join(outdir, f'{stem}-{clash[0]}{ext}')} exists; pass --force to overwrite")
    out = tracing.issue(mesh, key=key, registry=registry, n_copies=copies, ids=ids, method=method,
                        params=params_mode, source_name=os.path.basename(inp), original=inp)
    paths = {}
    for cid, V in out:
        path = os.path.join(outdir, f"{stem}-{cid}{ext}")
        if os.path.exists(path) and not force:
            raise MeshError(f"{path} exists; pass --force to overwrite (the copies are recorded in the registry)")
        write_all(mesh_outputs(path, V, mesh, fmt), what=["copy"] * 2)  # a glTF copy: only its positions differ
        paths[cid] = path
    tracing.set_paths(registry, paths)
    d = {"input": inp, "registry": registry, "copies": [{"id": c, "path": p} for c, p in paths.items()]}
    click.echo(jsonout.dumps(d) if as_json else
               f"issued {len(paths)} copies of {inp} into {outdir} (ids {out[0][0]}..{out[-1][0]}); registry {registry}")


@click.command()
@click.argument("suspect", metavar="SUSPECT")
@click.option("--registry", required=True, type=click.Path(dir_okay=False, exists=False), help="SQLite registry.")
@click.option("--key", default=None, help="The owner's key (if the registry does not store it).")
@click.option("--original", default=None, type=click.Path(dir_okay=False),
              help="The unmarked original (default: the path recorded by issue, if its digest still matches).")
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def trace(suspect, registry, key, original, as_json):
    """Which issued copy is SUSPECT? Names the best copy if its false-alarm probability (corrected for
    every copy in the registry, and for the two tests when the original is used) is below 1e-6, else
    "none". With the original (--original, or the path issue recorded) the copy's keyed pattern is
    correlated too (informed tracing); without it only the blind codeword is read.

    Exit status: 0 a copy named, 1 none, 2 error.
    """
    from . import read_mesh
    from .watermark import tracing

    r = tracing.trace(read_mesh(suspect), registry=registry, key=key, original=original)
    d = {"input": suspect, **r}
    b, inf = r["blind"] or {}, r["informed"]
    ev = (f"blind {b.get('matches', 0)}/{b.get('n_carriers', 0)} bits" +
          (f", informed z {inf['z']:.1f} ({inf['correspondence']}, {inf['n_used']} vertices)" if inf else
           ", no original: blind only"))
    text = (f"{suspect}: copy {r['copy']} ({ev}; P(false alarm) {r['p_false_alarm']:.3g} over {r['n_copies']} "
            f"copies, evidence {r['evidence']})" if r["detected"] else
            f"{suspect}: none ({ev}; P(false alarm) {r['p_false_alarm']:.3g} over {r['n_copies']} copies, "
            f"evidence {r['evidence']})")
    click.echo(jsonout.dumps(d) if as_json else text)
    sys.exit(0 if r["detected"] else 1)


COMMANDS = (issue, trace)
