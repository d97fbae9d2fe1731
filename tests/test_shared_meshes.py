"""Every OBJ/OFF/PLY/STL mesh of ../shared/meshes/SOURCES.md reads with the listed counts."""
import json
import re
import subprocess
import sys

import pytest

import meshmark
from conftest import SHARED, sources_table


ROWS = sources_table()


@pytest.mark.parametrize("rel,n_vertices,n_faces,topology", ROWS, ids=[r[0] for r in ROWS])
def test_counts_match_sources(rel, n_vertices, n_faces, topology):
    mesh, info = meshmark.read_mesh(SHARED / rel, return_info=True)
    d = meshmark.mesh_info(mesh)
    assert d["n_vertices"] == n_vertices
    assert info["n_file_faces"] == n_faces
    assert mesh.n_faces == n_faces - info["n_dropped_faces"]
    m = re.search(r"(\d+) boundary edges", topology)
    assert d["n_boundary_edges"] == (int(m.group(1)) if m else (0 if "closed" in topology else d["n_boundary_edges"]))
    m = re.search(r"(\d+) unreferenced", topology)
    assert d["n_unreferenced_vertices"] == (int(m.group(1)) if m else 0)
    m = re.search(r"(\d+) components", topology)
    if m:
        assert d["n_components"] == int(m.group(1))
    m = re.search(r"genus (\d+)", topology)
    if m and d["manifold"]:
        # SOURCES.md did not check vertex-manifoldness: cow.obj has one pinched vertex (chi = 1).
        assert d["n_components"] == 1 and d["euler_characteristic"] == 2 - 2 * int(m.group(1))
    m = re.search(r"NON-manifold \((\d+) edges\)", topology)
    if info["n_dropped_faces"] == 0:  # collapsed STL triangles add degenerate edges to SOURCES' counts
        assert d["non_manifold_edges"] == (int(m.group(1)) if m else 0)


def test_cli_info_json_on_every_format():
    for rel in ["classic/bunny.obj", "classic/horse.ply", "classic/elephant.off", "corpus/thingi10k_100072.stl"]:
        out = subprocess.run([sys.executable, "-m", "meshmark.cli", "info", str(SHARED / rel), "--json"],
                             capture_output=True, text=True, check=True).stdout
        d = json.loads(out)
        row = next(r for r in ROWS if r[0] == rel)
        assert (d["n_vertices"], d["n_faces"]) == (row[1], row[2])
        for key in ("n_edges", "n_boundary_edges", "n_components", "manifold", "bbox_min", "bbox_max",
                    "mean_edge_length"):
            assert key in d
