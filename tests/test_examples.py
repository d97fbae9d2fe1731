"""The scripts in examples/: RUNS names, for every script and study spec, the test that runs it for real (not
--help) and checks what it prints or writes; a new example without such a run fails here. Every bpy-free
script also starts with the current API (its --help, a child process each)."""
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


# script or study spec -> the test that runs it (a child process or its main()) and asserts on its output
Q, B = "tests/test_examples_quick.py", "blender_tests/test_examples_quick.py"
RUNS = {
    "analysis_figures.py": Q + "::test_analysis_figures_on_a_mesh",
    "analysis_tables.py": Q + "::test_analysis_tables_quick",
    "attack_table.py": Q + "::test_attack_table_quick",
    "blender_acceptance.py": B + "::test_blender_acceptance_quick",
    "blender_analyze.py": "blender_tests/test_examples_hiding.py::test_analyze_and_steganalysis_examples",
    "blender_capacity.py": "blender_tests/test_examples_blender.py::test_capacity_example",
    "blender_deformation_study.py": "blender_tests/test_examples_blender.py::test_embed_verify_and_study_examples",
    "blender_demo.py": B + "::test_blender_demo_quick",
    "blender_embed.py": "blender_tests/test_examples_blender.py::test_embed_verify_and_study_examples",
    "blender_steganalysis.py": "blender_tests/test_examples_hiding.py::test_analyze_and_steganalysis_examples",
    "blender_stego_embed.py": "blender_tests/test_examples_hiding.py::test_stego_examples",
    "blender_stego_extract.py": "blender_tests/test_examples_hiding.py::test_stego_examples",
    "blender_study.py": "blender_tests/test_examples_hiding.py::test_study_example",
    "blender_verify.py": "blender_tests/test_examples_blender.py::test_embed_verify_and_study_examples",
    "carrier_no_attack.py": Q + "::test_carrier_no_attack_quick",
    "carrier_skinning.py": B + "::test_carrier_skinning_quick",
    "cho_detector_study.py": Q + "::test_cho_detector_study_quick",
    "coding_curve.py": Q + "::test_coding_curve_quick",
    "coding_frame_ml.py": Q + "::test_coding_frame_ml_quick",
    "deformation_table.py": Q + "::test_deformation_table",
    "distortion_budget.py": Q + "::test_distortion_budget_quick",
    "informed_design_study.py": Q + "::test_informed_design_study_quick",
    "informed_tracing.py": "tests/test_informed.py::test_evaluation_quick_mode",
    "knight_parts.py": B + "::test_knight_parts_quick",
    "laplacian_capacity.py": "tests/test_examples.py::test_laplacian_capacity_quick_agrees_with_the_cli_and_the_api",
    "laplacian_distortion.py": Q + "::test_laplacian_distortion_quick",
    "laplacian_false_alarms.py": "tests/test_examples.py::test_laplacian_false_alarms_quick_finds_none",
    "laplacian_no_attack.py": Q + "::test_laplacian_no_attack_quick",
    "laplacian_robustness.py": Q + "::test_laplacian_robustness_quick",
    "mesh_summary.py": "tests/test_examples.py::test_mesh_summary_prints_the_counts",
    "overmarking.py": Q + "::test_overmarking_quick",
    "product_acceptance.py": Q + "::test_product_acceptance_quick",
    "radial_distortion.py": Q + "::test_radial_distortion_quick",
    "radial_robustness.py": Q + "::test_radial_robustness_quick",
    "robustness_table.py": "tests/test_robustness_study.py::test_quick_study_runs_and_the_table_has_every_row",
    "steganalysis_blender_holdout.py": B + "::test_steganalysis_blender_holdout_quick",
    "steganalysis_default_model.py": Q + "::test_steganalysis_default_model_quick",
    "steganalysis_protocol.py": Q + "::test_steganalysis_protocol_quick",
    "steganalysis_sources.py": Q + "::test_steganalysis_sources_quick",
    "steganalysis_table.py": Q + "::test_steganalysis_table_quick",
    "steganalysis_unseen.py": Q + "::test_steganalysis_unseen_quick",
    # the study specs: run in a reduced form by the example that wraps them (same methods and attacks)
    "studies/attack_table.toml": Q + "::test_attack_table_quick",
    "studies/deformation.toml": Q + "::test_deformation_table",
    "studies/laplacian_robustness.toml": Q + "::test_laplacian_robustness_quick",
    "studies/radial_robustness.toml": Q + "::test_radial_robustness_quick",
    "studies/robustness.toml": "tests/test_robustness_study.py::test_quick_study_runs_and_the_table_has_every_row",
    "studies/smoke.toml": "tests/test_study.py::test_smoke_results_are_real",
    "studies/steganalysis.toml": Q + "::test_steganalysis_protocol_quick",
    "studies/steganalysis_accuracy.toml": Q + "::test_steganalysis_accuracy_spec_small",
}


def test_every_example_has_a_real_run():
    """The directory listing against RUNS; each named test exists and names the script it runs."""
    files = {p.name for p in EXAMPLES.glob("*.py") if not p.name.startswith("_")}
    files |= {f"studies/{p.name}" for p in (EXAMPLES / "studies").glob("*.toml")}
    assert files == set(RUNS), (sorted(files - set(RUNS)), sorted(set(RUNS) - files))
    for script, where in RUNS.items():
        path, name = where.split("::")
        text = (ROOT / path).read_text()
        assert f"def {name}(" in text, where
        body = text[text.index(f"def {name}("):].split("\ndef ")[0]
        stem = pathlib.PurePath(script).stem  # named in the test, or imported by its module for a fixture
        assert stem in body or f"import {stem}" in text, (script, where)


def _run(*args, timeout=600):
    return subprocess.run([sys.executable, *map(str, args)], cwd=EXAMPLES, capture_output=True, text=True,
                          timeout=timeout)


def test_the_list_covers_the_examples():
    assert len(BPY_FREE) >= 25 and "laplacian_capacity.py" in BPY_FREE and "knight_parts.py" not in BPY_FREE


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
