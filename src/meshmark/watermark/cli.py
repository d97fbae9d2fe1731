"""``meshmark issue`` and ``meshmark trace``: copy tracing (meshmark.watermark.tracing)."""
from __future__ import annotations

import csv
import io
import os
import sys

import click

from .. import jsonout
from .._core import MeshError


MAX_IDS_BYTES = 64 << 20


def _read_ids(path: str) -> list:
    """The ids of an --ids CSV file (first column; '#' comments and an 'id' header skipped), each
    checked (usable in a file name) with its line named."""
    from ..atomic import read_at_most
    from .registry import MAX_COPIES, check_copy_id, shown

    raw = read_at_most(path, MAX_IDS_BYTES, f"--ids '{shown(path)}'")
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise MeshError(f"--ids '{shown(path)}' is not UTF-8 text (byte 0x{raw[exc.start]:02x} on line {line})") from None
    try:
        rows = [(i + 1, r) for i, r in enumerate(csv.reader(io.StringIO(text, newline="")))]
    except csv.Error as exc:
        raise MeshError(f"--ids '{shown(path)}' is not a CSV file: {exc}") from None
    rows = [(n, r[0].strip()) for n, r in rows if r and r[0].strip() and not r[0].strip().startswith("#")]
    if rows and rows[0][1].lower() in ("id", "copy", "copy_id"):
        rows = rows[1:]
    if not rows:
        raise MeshError(f"--ids '{shown(path)}' lists no ids (one per line, first column)")
    if len(rows) > MAX_COPIES:
        raise MeshError(f"--ids '{shown(path)}' lists {len(rows):,} ids; one issue makes at most {MAX_COPIES:,} copies")
    return [check_copy_id(c, f"--ids line {n}: the id") for n, c in rows]


class _CopyFiles:
    """Writes each copy to a temporary file beside ``<stem>-<id><ext>`` (tracing.issue renames it
    into place once every copy is written, in the registry's transaction)."""

    def __init__(self, outdir, stem, ext, mesh, fmt, force):
        self.outdir, self.stem, self.ext, self.mesh, self.fmt, self.force = outdir, stem, ext, mesh, fmt, force

    def path(self, cid):
        return os.path.join(self.outdir, f"{self.stem}-{cid}{self.ext}")

    def check(self, ids):
        if not self.force:
            clash = [c for c in ids if os.path.lexists(self.path(c))]
            if clash:
                raise MeshError(f"{self.path(clash[0])} exists; pass --force to overwrite (nothing was recorded)")

    def write(self, cid, V):
        from ..atomic import temp_path
        from ..io import mesh_outputs

        files = []
        try:
            for final, writer in mesh_outputs(self.path(cid), V, self.mesh, self.fmt):
                tmp = temp_path(final)
                files.append((tmp, final))
                writer(tmp)
        except BaseException as exc:
            for tmp, _ in files:
                if os.path.lexists(tmp):
                    os.remove(tmp)
            if isinstance(exc, OSError):
                raise MeshError(f"cannot write copy {cid} into '{self.outdir}': {exc.strerror or exc}") from None
            raise
        return files


@click.command()
@click.argument("inp", metavar="IN")
@click.argument("outdir", metavar="OUTDIR")
@click.option("--copies", type=click.IntRange(1, 100_000), default=None,
              help="Number of copies, 1..100,000 (ids continue the asset's numbering).")
@click.option("--ids", "ids_csv", type=click.Path(dir_okay=False), default=None,
              help="CSV file with one copy id per line (first column), instead of --copies.")
@click.option("--key", required=True, help="The owner's secret key.")
@click.option("--registry", required=True, help="The registry of copies (an SQLite file, created 0600 if missing).")
@click.option("--method", type=click.Choice(["laplacian", "cho-mean", "cho-variance", "radial"]), default="laplacian",
              show_default=True)
@click.option("--params", "params_mode", type=click.Choice(["auto", "thesis"]), default="auto", show_default=True)
@click.option("--force", is_flag=True, default=False, help="Overwrite existing copy files in OUTDIR.")
@click.option("--wait", type=click.FloatRange(0, 86_400), default=600, show_default=True,
              help="Seconds to wait while another issue writes to the same registry, then give up (exit 2).")
@jsonout.option()
def issue(inp, outdir, copies, ids_csv, key, registry, method, params_mode, force, wait, as_json):
    """Write marked copies of IN into OUTDIR (IN's format), each with its own codeword, and record
    them in the registry."""
    from ..io import read_mesh
    from . import tracing

    if (copies is None) == (ids_csv is None):
        raise MeshError("give exactly one of --copies N or --ids ids.csv")
    ids = _read_ids(ids_csv) if ids_csv else None
    reg = tracing.Registry(registry)  # a foreign or damaged file is refused before any work
    try:
        mesh, fmt = read_mesh(inp, return_info=True)
        stem, ext = os.path.splitext(os.path.basename(inp))
        sink = _CopyFiles(outdir, stem, ext, mesh, fmt, force)
        if ids is not None:
            sink.check(ids)
        os.makedirs(outdir, exist_ok=True)
        out = tracing.issue(mesh, key=key, registry=reg, n_copies=copies, ids=ids, method=method,
                            params=params_mode, source_name=os.path.basename(inp), original=inp, sink=sink,
                            wait=wait)
    finally:
        reg.close()
    paths = dict(out)
    dist = out.distortion
    d = {"input": inp, "output": outdir, "registry": registry,
         "copies": [{"id": c, "path": p} for c, p in paths.items()], "distortion": dist}
    text = f"issued {len(paths)} copies of {inp} into {outdir} (ids {out[0][0]}..{out[-1][0]}); registry {registry}"
    if dist["copies_beyond"]:
        lim = dist["limits"]
        text += (f"\nwarning: {dist['copies_beyond']} of {dist['n_copies']} copies change the mesh more than is invisible "
                 f"(up to {dist['largest_share']:.1f} times the limit: vertex RMSE {lim['rmse']:g} or Hausdorff "
                 f"{lim['hausdorff']:g} of the bounding-box diagonal, or {lim['normal_deg']:g} degrees of normal change); "
                 f"the marks may be visible on this mesh (docs/tracing.md, \"Distortion budget\")")
    jsonout.emit(d, as_json, text)


@click.command()
@click.argument("suspect", metavar="SUSPECT")
@click.option("--registry", required=True, help="The registry of copies (opened read-only).")
@click.option("--key", default=None, help="The owner's key (if the registry does not store it).")
@click.option("--original", default=None, type=click.Path(dir_okay=False),
              help="The unmarked original (default: the path recorded by issue, if its digest still matches).")
@jsonout.option()
def trace(suspect, registry, key, original, as_json):
    """Which issued copy is SUSPECT? Names the best copy if its false-alarm probability (corrected for
    every copy in the registry, and for the two tests when the original is used) is below 1e-6, else
    "none". With the original (--original, or the path issue recorded) the copy's keyed pattern is
    correlated too (informed tracing); without it only the blind codeword is read.

    Exit status: 0 a copy named, 1 none, 2 error.
    """
    from .. import read_mesh
    from . import tracing

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
    jsonout.emit(d, as_json, text)
    sys.exit(0 if r["detected"] else 1)


COMMANDS = (issue, trace)
