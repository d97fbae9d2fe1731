"""The ``meshmark`` command line. Every subcommand takes ``--json`` for scripts."""
from __future__ import annotations

import json
import sys

import click

from ._core import MeshError


def _emit(result: dict, as_json: bool, text: str) -> None:
    click.echo(json.dumps(result, indent=2, sort_keys=False) if as_json else text)


def _format_info(path: str, d: dict) -> str:
    sizes = ", ".join(f"{k}-gon x{v}" for k, v in d["face_sizes"].items())
    lo, hi = d["bbox_min"], d["bbox_max"]
    rows = [
        ("mesh", path),
        ("vertices", f"{d['n_vertices']} ({d['n_unreferenced_vertices']} unreferenced)"),
        ("faces", f"{d['n_faces']} ({sizes})" + (f", {d['n_dropped_faces']} collapsed faces dropped" if d.get("n_dropped_faces") else "")),
        ("edges", f"{d['n_edges']}"),
        ("boundary edges", f"{d['n_boundary_edges']}"),
        ("components", f"{d['n_components']}"),
        ("manifold", ("yes" if d["manifold"] else
                      f"no ({d['non_manifold_edges']} non-manifold edges, {d['non_manifold_vertices']} non-manifold vertices)")),
        ("closed", "yes" if d["closed"] else "no"),
        ("degenerate faces", f"{d['n_degenerate_faces']}"),
        ("bounding box", f"[{lo[0]:.6g}, {lo[1]:.6g}, {lo[2]:.6g}] .. [{hi[0]:.6g}, {hi[1]:.6g}, {hi[2]:.6g}]"),
        ("bbox diagonal", f"{d['bbox_diagonal']:.6g}"),
        ("mean edge length", f"{d['mean_edge_length']:.6g}"),
    ]
    w = max(len(k) for k, _ in rows)
    return "\n".join(f"{k:<{w}}  {v}" for k, v in rows)


class _Group(click.Group):
    """Turns MeshError (bad input) into a one-line error and exit status 2, never a traceback."""

    def invoke(self, ctx):
        try:
            return super().invoke(ctx)
        except MeshError as exc:
            click.echo(f"meshmark: error: {exc}", err=True)
            sys.exit(2)


@click.group(cls=_Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="meshmark")
def main():
    """meshmark: hide and detect information in 3D triangle meshes."""


@main.command()
@click.argument("mesh", required=False)
@click.option("--json", "as_json", is_flag=True, help="Print the result as JSON.")
def info(mesh, as_json):
    """Counts, boundary, components, manifoldness, bounding box and mean edge length of MESH.

    Without MESH, describes the built-in default mesh.
    """
    from . import read_mesh, mesh_info
    from .shapes import default_mesh

    if mesh is None:
        m, path = default_mesh(), "(built-in default)"
        fmt = {"format": "builtin", "binary": False, "float32": False, "n_file_faces": m.n_faces, "n_dropped_faces": 0}
    else:
        (m, fmt), path = read_mesh(mesh, return_info=True), mesh
    d = mesh_info(m)
    # Counts are of the file's records (as SOURCES.md lists them): faces dropped on reading
    # (collapsed, repeating a vertex) count in n_faces and are reported as n_dropped_faces.
    d["n_faces"] = fmt["n_file_faces"]
    d = {"path": path, **fmt, **d}
    _emit(d, as_json, _format_info(path, d))


if __name__ == "__main__":  # pragma: no cover
    main()
