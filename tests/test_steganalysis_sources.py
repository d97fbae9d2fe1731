"""Sources of the shared meshes and geometric deduplication (docs/steganalysis.md §6)."""
import shutil

import numpy as np

import meshmark
from meshmark.steganalysis.sources import deduplicate, geometry_hash, source_of
from conftest import shared_mesh


def test_source_of_shared_files_and_others(tmp_path):
    assert source_of(shared_mesh("corpus/vhacd_pig.off")) == "v-hacd"
    assert source_of(shared_mesh("corpus/odedstein_penguin.obj")) == "odedstein-meshes"
    assert source_of(shared_mesh("corpus/thingi10k_59758.stl")) == "thingi10k"
    assert source_of(shared_mesh("classic/bunny.obj")) == "common-3d-test-models"
    assert source_of(shared_mesh("classic/elephant.off")) == "pmp-data"
    assert source_of(shared_mesh("corpus-large/psb-seg/psb_001_human.off")) == "psb-seg"
    assert source_of(str(shared_mesh("corpus/vhacd_pig.off")) + "#crop0") == "v-hacd"  # a variant of a file
    p = tmp_path / "studio" / "a.obj"
    p.parent.mkdir()
    assert source_of(p) == "studio"


def test_deduplicate_bytes_formats_orders(tmp_path):
    m = meshmark.read_mesh(shared_mesh("corpus/vhacd_pig.off"))
    shutil.copy(shared_mesh("corpus/vhacd_pig.off"), tmp_path / "a.off")
    shutil.copy(shared_mesh("corpus/vhacd_pig.off"), tmp_path / "b.off")  # byte-identical
    pv = np.random.default_rng(0).permutation(m.n_vertices)
    inv = np.empty_like(pv)
    inv[pv] = np.arange(len(pv))
    meshmark.write_mesh(tmp_path / "c.ply", m.V[pv], inv[m.F][::-1], float32=True)  # float32, vertex + face order
    shutil.copy(shared_mesh("corpus/vhacd_eight.off"), tmp_path / "d.off")
    groups = deduplicate(sorted(tmp_path.iterdir()))
    assert [[p.name for p in g] for g in groups] == [["a.off", "b.off", "c.ply"], ["d.off"]]
    meshmark.write_mesh(tmp_path / "e.obj", m.V[pv], inv[m.F][::-1])  # the same doubles in another order and format
    assert geometry_hash(m) == geometry_hash(meshmark.read_mesh(tmp_path / "e.obj")) != geometry_hash(meshmark.read_mesh(tmp_path / "d.off"))
    # the one duplicate across the shared corpora: PSB's four-legged model 391 is v-hacd's cow2
    g = deduplicate([shared_mesh("corpus-large/psb-seg/psb_391_fourleg.off"), shared_mesh("corpus-large/v-hacd/vhacd_cow2.off"),
                     shared_mesh("classic/cow.obj")])
    assert [len(x) for x in g] == [1, 2] or [len(x) for x in g] == [2, 1]
