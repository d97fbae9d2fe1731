"""Shared bits of the example scripts (run from any directory: this folder is on sys.path)."""
import csv
import pathlib

SHARED = pathlib.Path(__file__).resolve().parents[2] / "shared" / "meshes"
MESH_SUFFIXES = {".obj", ".off", ".ply", ".stl"}


def write_csv(rows: list, path) -> pathlib.Path:
    """Write the dicts ``rows`` (the first row's keys as the header) to ``path``, creating its folder."""
    out = pathlib.Path(path)
    out.parent.mkdir(parents=True, exist_ok=True)
    with open(out, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    return out
