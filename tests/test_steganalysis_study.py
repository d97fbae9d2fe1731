"""The steganalysis task kind of `meshmark study run` (meshmark.steganalysis.study)."""
import csv
import json

import pytest
from click.testing import CliRunner

from meshmark import MeshError
from meshmark.cli import main
from meshmark.study import engine
from conftest import shared_mesh

SPEC = """
kind = "steganalysis"
[study]
name = "tiny"
[steganalysis]
parts = ["protocol", "cho_table"]
folders = ["{corpus}"]
limit = 6
methods = ["cho-variance", "lsb-5deg"]
feature_sets = ["yang208"]
runs = [{{ set = "yang208", classifier = "ensemble" }}, {{ set = "yang208", classifier = "qda", universal = "all" }}]
universal = []
splits = 3
pca_k = [2, 5]
holdout = 1
holdout_set = "yang208"
[steganalysis.cho_table]
folders = ["{corpus}"]
limit = 2
variants = false
"""


def test_study_run_writes_every_table_and_figure(tmp_path):
    corpus = shared_mesh("corpus/c3d_woody.obj").parent
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(corpus=corpus))
    out = tmp_path / "out"
    r = CliRunner().invoke(main, ["study", "run", str(spec), "--out", str(out), "--json"])
    assert r.exit_code == 0, r.output
    S = json.loads(r.output[r.output.index("{\n"):])
    assert S["ok"] is True and S["planned"] == 2 and S["tasks_ok"] == 2
    for f in ("dataset.npz", "protocol_splits.csv", "protocol_median.csv", "protocol_ranking.csv", "protocol_pca.csv",
              "protocol_pca.png", "protocol_accuracy.png", "protocol_holdout.csv", "cho_table.csv", "cho_table_summary.csv", "cho_table.png",
              "tables.md"):
        assert (out / f).is_file(), f
    med = list(csv.DictReader(open(out / "protocol_median.csv")))
    dets = {(r["classifier"], r["universal_training"], r["detector"]) for r in med}
    assert ("ensemble", "pick", "universal") in dets and ("qda", "all", "universal") in dets
    assert ("ensemble", "pick", "specific:cho-variance") in dets and ("ensemble", "pick", "specific:lsb-5deg") in dets
    rows = list(csv.DictReader(open(out / "protocol_splits.csv")))
    assert len(rows) == 2 * 3 * 3  # runs x splits x (2 specific + universal)
    assert all(0 <= float(r["accuracy"]) <= 1 for r in rows)
    assert {int(r["k"]) for r in csv.DictReader(open(out / "protocol_pca.csv"))} == {2, 5}
    tables = (out / "tables.md").read_text()
    assert "Ranking by detectability" in tables and "Table 6.2" in tables
    # a rerun reuses the cached dataset (resume)
    mtime = (out / "dataset.npz").stat().st_mtime
    spec.write_text(SPEC.format(corpus=corpus).replace('parts = ["protocol", "cho_table"]', 'parts = ["protocol"]'))
    assert CliRunner().invoke(main, ["study", "run", str(spec), "--out", str(out)]).exit_code == 0
    assert (out / "dataset.npz").stat().st_mtime == mtime


def test_bad_steganalysis_specs(tmp_path):
    with pytest.raises(MeshError, match="unknown kind"):
        engine.run({"kind": "nope"}, tmp_path)
    with pytest.raises(MeshError, match="unknown keys in \\[steganalysis\\]"):
        engine.run({"kind": "steganalysis", "steganalysis": {"split": 3}}, tmp_path)
    with pytest.raises(MeshError, match="parts"):
        engine.run({"kind": "steganalysis", "steganalysis": {"parts": ["tables"]}}, tmp_path)
    with pytest.raises(MeshError, match="no such folder"):
        engine.run({"kind": "steganalysis", "steganalysis": {"folders": ["/nonexistent"]}}, tmp_path)
