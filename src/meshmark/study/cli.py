"""``meshmark study run|status|plot`` (registered by one line at the end of meshmark/cli.py)."""
from __future__ import annotations

import os
import sys

import click

from .. import jsonout
from .._core import MeshError


@click.group("study")
def study():
    """Studies: method x parameter x attack x mesh grids (docs/studies.md)."""


def _dask_option(value):
    if value is None:
        return None
    if value.startswith("local:"):
        n = value.split(":", 1)[1]
        if not n.isdigit() or int(n) < 1:
            raise MeshError(f"--dask local:N needs N >= 1 workers, got {value!r}")
        return value
    if value.startswith(("tcp://", "tls://", "ws://", "wss://", "inproc://")):
        return value
    raise MeshError(f"--dask must be local:N or a scheduler address (tcp://host:8786), got {value!r}")


@study.command("run")
@click.argument("spec")
@click.option("--out", "out", required=True, help="Results folder (results/*.parquet, store/, runs.jsonl).")
@click.option("--workers", type=int, default=None,
              help="Local worker processes, 0..1024 (default: the core count; 0 = run in this process).")
@click.option("--dask", "dask", default=None, help="local:N (a LocalCluster of N workers) or tcp://host:8786.")
@click.option("--ship-meshes", is_flag=True, help="Send each mesh file's bytes to the workers (no shared path).")
@click.option("--chunk-size", type=int, default=None, help="Tasks per chunk, 1..1,000,000 (one mesh per chunk; default study.chunk_size, 64).")
@click.option("--retries", type=int, default=1, show_default=True, help="Times a failed task is run again, 0..100.")
@click.option("--dry-run", is_flag=True, help="Plan and compute the task keys only; print the counts and timing.")
@click.option("--progress/--no-progress", default=None, help="Progress bar (default: on a terminal).")
@jsonout.option("Print the summary as JSON.")
def run_cmd(spec, out, workers, dask, ship_meshes, chunk_size, retries, dry_run, progress, as_json):
    """Run (or resume) the study SPEC (a TOML file); results go under --out."""
    from . import engine
    from .spec import load_spec, plan
    import time

    from ..ranges import check_int
    if workers is not None:
        check_int("workers", workers, 0, 1024)
    if chunk_size is not None:
        check_int("chunk_size", chunk_size, 1, 1_000_000)
    check_int("retries", retries, 0, 100)
    if workers is not None and dask:
        raise MeshError("give --workers or --dask, not both")
    dask = _dask_option(dask)
    if dry_run:
        t0 = time.perf_counter()
        sp = load_spec(spec)
        keys, idx, _ = plan(sp)
        d = {"input": spec, "output": out, "dry_run": True, "tasks": len(keys), "meshes": len(sp.meshes), "methods": len(sp.methods), "attacks": len(sp.attacks),
             "seeds": len(sp.seeds), "seconds": round(time.perf_counter() - t0, 3),
             "unique_keys": len(set(keys))}
        if os.path.isdir(out):
            try:
                d["done"] = len(engine.finished_keys(out) & set(keys))
            except Exception:  # noqa: BLE001 - a dry run reports what it can
                pass
        jsonout.emit(d, as_json, indent=1, text=
                     f"{d['tasks']} tasks ({d['meshes']} meshes x {d['methods']} methods x {d['seeds']} seeds x "
                     f"{d['attacks']} attacks), {d['unique_keys']} unique keys, planned in {d['seconds']} s")
        return
    S = engine.run(spec, out, workers=workers, dask=dask, progress=progress, retries=retries,
                   ship_meshes=ship_meshes, chunk_size=chunk_size)
    if as_json:
        summary = S.to_dict()
        summary["tasks_ok"] = summary.pop("ok")  # "ok" is the command's own flag under --json (docs/json.md)
        d = jsonout.result({"input": spec, "output": out, "dry_run": False, **summary})
        if S.failed:  # exit 3: the failure object, with the summary
            d.update(jsonout.error_object(3, "tasks_failed", f"{S.failed} of {S.planned} tasks failed"))
        click.echo(jsonout.dumps(d, indent=1))
    else:
        click.echo(f"{S.planned} planned, {S.skipped} already done, {S.ok} ok, {S.mesh_error} mesh errors, "
                   f"{S.failed} failed; {S.wall:.1f} s. Results: {out}/results")
    if S.failed:
        sys.exit(3)


@study.command("status")
@click.argument("out")
@click.option("--spec", default=None, help="The spec, to count what is left to run.")
@jsonout.option()
def status_cmd(out, spec, as_json):
    """Counts of the results under OUT by status and method (and what is left, with --spec)."""
    from . import engine
    d = engine.status(out, spec)
    if as_json:
        jsonout.emit({"input": out, **d}, True, "", indent=1)
        return
    lines = [f"{d['rows']} results: " + ", ".join(f"{v} {k}" for k, v in d["by_status"].items())]
    if "planned" in d:
        lines.append(f"{d['planned']} planned, {d['remaining']} remaining")
    w = max(len(m) for m in d["by_method"])
    for m, c in d["by_method"].items():
        lines.append(f"  {m:<{w}}  " + ", ".join(f"{v} {k}" for k, v in sorted(c.items())))
    for e in d["errors"][:10]:
        lines.append(f"  error {e['key'][:12]}: {e['error']}")
    click.echo("\n".join(lines))


@study.command("plot")
@click.argument("results")
@click.option("--out", "out", default=None, help="Folder for the PNG figures and summary.csv (default RESULTS/plots).")
@click.option("--force", is_flag=True, default=False, help="Overwrite the figures of an earlier plot in --out.")
@jsonout.option("Print the files written as JSON.")
def plot_cmd(results, out, force, as_json):
    """Standard figures (CDR vs attack strength per method, detection vs deformation, capacity vs size)
    as PNG and a CSV summary (means per method and attack)."""
    from . import plot
    written = [str(p) for p in plot.plot(results, out, overwrite=force)]
    jsonout.emit({"input": results, "output": out or os.path.join(results, "plots"), "files": written}, as_json, "\n".join(written))
