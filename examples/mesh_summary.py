"""Summarise every mesh in a folder: counts, boundary, components, manifoldness (CSV to stdout).

    .venv/bin/python examples/mesh_summary.py ../shared/meshes/classic
"""
import csv
import pathlib
import sys

import meshmark

folder = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "../shared/meshes/classic")
fields = ["file", "n_vertices", "n_faces", "n_edges", "n_boundary_edges", "n_components", "manifold",
          "n_unreferenced_vertices", "bbox_diagonal", "mean_edge_length"]
out = csv.DictWriter(sys.stdout, fieldnames=fields, extrasaction="ignore")
out.writeheader()
for path in sorted(folder.iterdir()):
    if path.suffix.lower() not in {".obj", ".off", ".ply", ".stl"}:
        continue
    try:
        mesh, fmt = meshmark.read_mesh(path, return_info=True)
    except meshmark.MeshError as exc:
        print(f"skipping {path.name}: {exc}", file=sys.stderr)
        continue
    d = meshmark.mesh_info(mesh)
    d["n_faces"] = fmt["n_file_faces"]
    out.writerow({"file": path.name, **d})
