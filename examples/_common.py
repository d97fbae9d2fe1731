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


def quick_spec(path, meshes=None, seeds=(0,)):
    """The study spec at ``path`` in an example's quick mode: the same methods and attacks on ``meshes``
    (spec paths, relative to the spec's folder; default: the spec's own) and ``seeds``."""
    import tomllib
    from meshmark.study import load_spec
    path = pathlib.Path(path)
    raw = tomllib.loads(path.read_text())
    if meshes is not None:
        raw["meshes"]["paths"] = list(meshes)
    raw["study"]["seeds"] = list(seeds)
    return load_spec(raw, base=path.parent)
