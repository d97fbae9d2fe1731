"""The scripts in examples/: every one starts with the current API (its --help, a child process each), and
the quick modes of the ones not run elsewhere print what the thesis and the CLI say. (The Blender examples
run in blender_tests/test_examples_*.py; informed_tracing, robustness_table, coding_curve, overmarking and
the carrier examples in their own tests.)"""
import csv
import json
import pathlib
import subprocess
import sys

import pytest

import meshmark
from meshmark.watermark import laplacian as L
from conftest import ROOT, shared_mesh

EXAMPLES = ROOT / "examples"
BPY_FREE = sorted(p.name for p in EXAMPLES.glob("*.py")
                  if not p.name.startswith("_") and "import bpy" not in p.read_text()
                  and "_blender_common" not in p.read_text() and "argparse" in p.read_text())


def _run(*args, timeout=600):
    return subprocess.run([sys.executable, *map(str, args)], cwd=EXAMPLES, capture_output=True, text=True,
                          timeout=timeout)


def test_the_list_covers_the_examples():
    assert len(BPY_FREE) >= 25 and "laplacian_capacity.py" in BPY_FREE and "knight_product.py" not in BPY_FREE


@pytest.mark.parametrize("name", BPY_FREE)
def test_example_starts(name):
    """Imports resolve against the installed package and the options parse (no test module imported)."""
    r = _run(name, "--help", timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "usage:" in r.stdout and "Traceback" not in r.stderr


def test_mesh_summary_prints_the_counts(tmp_path):
    r = _run("mesh_summary.py", ROOT.parent / "shared" / "meshes" / "classic")
    assert r.returncode == 0, r.stderr[-2000:]
    rows = {row["file"]: row for row in csv.DictReader(r.stdout.splitlines())}
    bunny = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    assert int(rows["bunny.obj"]["n_vertices"]) == len(bunny.V)


def test_laplacian_capacity_quick_agrees_with_the_cli_and_the_api(tmp_path):
    out = tmp_path / "cap.csv"
    r = _run("laplacian_capacity.py", "--quick", "--out", out)
    assert r.returncode == 0, r.stderr[-2000:]
    assert "Thesis parameters (params='thesis') beside Table 7.1" in r.stdout
    rows = {row["mesh"]: row for row in csv.DictReader(open(out))}
    bunny = rows["classic/bunny.obj"]
    m = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    assert int(bunny["K"]) == 498 == int(bunny["thesis_K"])  # K = ceil(N/70), Table 7.1
    assert int(bunny["capacity"]) == L.capacity(m, params="thesis")
    assert int(bunny["capacity_auto"]) == L.capacity(m)
    cli = subprocess.run([sys.executable, "-m", "meshmark", "capacity", shared_mesh("classic/bunny.obj"),
                          "--method", "laplacian", "--params", "thesis", "--json"], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    assert json.loads(cli.stdout)["capacity"] == int(bunny["capacity"])


def test_laplacian_false_alarms_quick_finds_none(tmp_path):
    r = _run("laplacian_false_alarms.py", "--quick", "--out", tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr[-2000:]
    lines = r.stdout.splitlines()
    assert any(l.startswith("wrong keys  classic/bunny.obj") and "n=20" in l and "detected=0" in l for l in lines)
    assert "unmarked meshes: 6 extractions over 3 meshes" in r.stdout and r.stdout.rstrip().endswith("detected=0")
    wrong = list(csv.DictReader(open(tmp_path / "wrong_keys.csv")))
    assert len(wrong) == 20 and all(w["detected"] == "0" for w in wrong)
