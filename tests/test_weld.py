"""Welding split vertices (meshmark.weld_vertices) and the watermark framework's weld step.

Exporters split a vertex into coincident copies at UV seams and sharp edges, and a non-indexed glTF
keeps every triangle corner apart (Blender imports the Fox as 576 loose triangles). The framework
welds exactly coincident vertices before a method runs, scatters the marked positions back to every
copy, and records the choice in the keyfile (docs/mesh_model.md, "Split vertices").
"""
import json

import numpy as np
import pytest

import meshmark
from meshmark import MeshError
from meshmark.watermark import METHODS, capacity, embed, extract, load_keyfile, save_keyfile
from meshmark.watermark import laplacian as L

from conftest import shared_mesh


def split_at_seam(m: meshmark.Mesh):
    """The mesh with a seam like a UV seam: every vertex used by faces on both sides of the plane
    x = median(x) gets a copy (appended after the originals, as exporters do) that the faces on the
    positive side use instead. Returns (split mesh, index of the original of each vertex)."""
    F = m.F
    side = m.V[F].mean(axis=1)[:, 0] > np.median(m.V[:, 0])
    on_pos = np.zeros(m.n_vertices, bool)
    on_neg = np.zeros(m.n_vertices, bool)
    on_pos[F[side].ravel()] = True
    on_neg[F[~side].ravel()] = True
    seam = np.flatnonzero(on_pos & on_neg)
    copy_of = np.arange(m.n_vertices)
    copy_of[seam] = m.n_vertices + np.arange(seam.size)
    F2 = F.copy()
    F2[side] = copy_of[F[side]]
    V2 = np.vstack([m.V, m.V[seam]])
    return meshmark.Mesh(V2, F2), np.concatenate([np.arange(m.n_vertices), seam])


def non_indexed(m: meshmark.Mesh):
    """Every triangle corner its own vertex (a non-indexed glTF / STL triangle soup)."""
    F = m.F
    return meshmark.Mesh(m.V[F.ravel()], np.arange(F.size, dtype=np.int32).reshape(F.shape)), F.ravel()


# --- the native weld --------------------------------------------------------------------------
def test_weld_small_cases():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [-0.0, 0, 0], [5, 5, 5]], float)
    F = [[0, 1, 2], [3, 5, 4], [6, 3, 1, 2]]  # the quad (6, 3, 1, 2) welds to (0, 1, 1, 2) -> triangle (0, 1, 2)
    w = meshmark.weld_vertices(V, F)
    # first-occurrence order; -0.0 == 0.0; the unreferenced vertex 7 is kept
    assert w.map.tolist() == [0, 1, 2, 1, 2, 3, 0, 4]
    assert w.first.tolist() == [0, 1, 2, 5, 7]
    assert w.n_merged == 3
    assert w.mesh.V.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0], [5, 5, 5]]
    assert w.mesh.face_indices.tolist() == [0, 1, 2, 1, 3, 2, 0, 1, 2] and w.face.tolist() == [0, 1, 2]
    assert w.mesh.face_offsets.tolist() == [0, 3, 6, 9]
    # a triangle whose corners weld together is dropped, and the face map says which survived
    V2 = np.vstack([V, [[1, 0, 0]]])
    w2 = meshmark.weld_vertices(V2, [[0, 1, 2], [1, 8, 5], [3, 5, 4]])
    assert w2.face.tolist() == [0, 2] and w2.mesh.n_faces == 2
    np.testing.assert_array_equal(w2.scatter(w2.mesh.V), V2)
    with pytest.raises(MeshError, match="leaves no face"):
        meshmark.weld_vertices(np.zeros((3, 3)), [[0, 1, 2]])


def test_weld_of_a_mesh_without_duplicates_is_the_identity(bunny):
    w = meshmark.weld_vertices(bunny)
    assert w.mesh is bunny and w.n_merged == 0
    assert np.array_equal(w.map, np.arange(bunny.n_vertices)) and np.array_equal(w.face, np.arange(bunny.n_faces))


def test_weld_restores_split_meshes(bunny):
    split, orig = split_at_seam(bunny)
    assert split.n_vertices == 35947 + 300  # the bunny file's 35,947 vertices + 300 seam copies
    w = meshmark.weld_vertices(split)
    # the originals come first, so the welded mesh is the bunny itself, vertex for vertex
    assert w.n_merged == 300 and np.array_equal(w.map, orig)
    assert np.array_equal(w.mesh.V, bunny.V) and np.array_equal(w.mesh.face_indices, bunny.face_indices)
    soup, corner = non_indexed(bunny)
    ws = meshmark.weld_vertices(soup)
    assert ws.mesh.n_vertices == 34834  # the referenced vertices (the file has 1,113 unreferenced)
    assert ws.mesh.n_faces == bunny.n_faces == 69451
    np.testing.assert_array_equal(ws.mesh.V[ws.map], bunny.V[corner])
    assert meshmark.connected_components(soup)[1] == 69451 and meshmark.connected_components(ws.mesh)[1] == 1


# --- the framework: same carriers, bit-identical copies, keyfile --------------------------------
@pytest.mark.parametrize("method", list(METHODS))
def test_split_mesh_has_the_welded_capacity(bunny, method):
    split, _ = split_at_seam(bunny)
    assert capacity(split, method=method) == capacity(bunny, method=method) == capacity(bunny, method=method, weld=False)


def test_split_mesh_gets_the_welded_mark_and_copies_stay_identical(bunny):
    split, orig = split_at_seam(bunny)
    r0 = L.embed(bunny, payload="(c)ACME", key="s3cret")
    r = L.embed(split, payload="(c)ACME", key="s3cret")
    # auto parameters: 56 + 20 bits need 114 carriers: the third rung (K = ceil(N/35), n_thr = 23) has 149
    assert r.capacity == r0.capacity == 149 and r.stats["n_merged"] == 300
    assert r.keyfile.side_info["carriers"] == r0.keyfile.side_info["carriers"]
    assert r.keyfile.weld is True and r.keyfile.mesh["n_vertices"] == 35947
    assert r.keyfile.mesh["n_input_vertices"] == 35947 + 300
    # the marked originals are those of the unsplit bunny, bit for bit, and every copy equals its original
    assert np.array_equal(r.V[:bunny.n_vertices], r0.V)
    assert np.array_equal(r.V, r.V[orig])
    assert np.abs(r.V - split.V).max() > 0
    x = L.extract(r.V, split, keyfile=r.keyfile)
    assert (x.cdr, x.message, x.detected, x.n_vertices, x.n_merged, x.warnings) == (1.0, "(c)ACME", True, 35947, 300, [])
    assert x.same_vertex_count
    # the unsplit marked bunny reads the same with the split mesh's keyfile (and vice versa)
    assert L.extract(r0.V, bunny, keyfile=r.keyfile).cdr == 1.0
    assert L.extract(r.V, split, keyfile=r0.keyfile).cdr == 1.0


def test_without_weld_the_copies_crack_apart(bunny):
    split, orig = split_at_seam(bunny)
    r = L.embed(split, payload="(c)ACME", key="s3cret", weld=False)
    gap = np.linalg.norm(r.V - r.V[orig], axis=1)
    diag = np.linalg.norm(bunny.V.max(0) - bunny.V.min(0))
    # the seam copies are boundary vertices of two open halves: they move apart (a crack in the model)
    # measured: 1.0e-4 of the diagonal with the iterative reconstruction, 1.2e-3 with solver='direct'
    assert (gap > 0).sum() == 300 and gap.max() > 3e-5 * diag
    assert r.keyfile.weld is False and r.keyfile.mesh["n_vertices"] == 35947 + 300


def test_non_indexed_soup_is_marked_like_the_mesh(bunny):
    soup, corner = non_indexed(bunny)
    # unwelded, 208,353 corners of 69,451 loose triangles make a different histogram (K = 2977 bins)
    assert L.capacity(soup, weld=False) == 505  # thesis carrier: 402
    assert L.capacity(soup) == L.capacity(bunny) == 104  # welded: the bunny's 34,834 referenced vertices
    r = L.embed(soup, payload="soup", key="k")
    w = meshmark.weld_vertices(soup)
    assert np.array_equal(r.V, r.V[w.first][w.map])  # every corner of a vertex moved identically
    x = L.extract(r.V, soup, keyfile=r.keyfile)
    assert (x.cdr, x.message, x.n_vertices) == (1.0, "soup", 34834)
    # the same marked positions as an indexed mesh: welding at extraction is what reads them
    xi = L.extract(r.V[w.first], w.mesh.face_indices.reshape(-1, 3), keyfile=r.keyfile)
    assert (xi.cdr, xi.n_merged) == (1.0, 0)


@pytest.mark.parametrize("method", ["cho-mean", "radial"])
def test_other_methods_weld_too(bunny, method):
    split, orig = split_at_seam(bunny)
    r = embed(split, payload="Hi", key="k", method=method)
    assert np.array_equal(r.V, r.V[orig]) and r.keyfile.weld
    x = extract(r.V, split, keyfile=r.keyfile)
    assert (x.cdr, x.message, x.n_merged) == (1.0, "Hi", 300)


def test_keyfile_round_trip_and_version_1(bunny, tmp_path):
    split, _ = split_at_seam(bunny)
    r = L.embed(split, payload="E", key="k")
    path = tmp_path / "k.json"
    save_keyfile(r.keyfile, path)
    d = json.loads(path.read_text())
    assert (d["version"], d["weld"]) == (3, True)
    assert load_keyfile(path).weld is True and load_keyfile(path).to_dict() == r.keyfile.to_dict()
    rn = L.embed(bunny, payload="E", key="k", weld=False)
    save_keyfile(rn.keyfile, tmp_path / "n.json")
    assert json.loads((tmp_path / "n.json").read_text())["weld"] is False
    assert load_keyfile(tmp_path / "n.json").weld is False
    # a version-1 keyfile (before welding existed) has no "weld" field: read as weld=False, so the
    # split mesh is read unwelded (with the vertex-count warning) exactly as version 1 did
    d1 = {k: v for k, v in d.items() if k not in ("weld", "tag")}  # (version 1 had no tag either)
    d1["version"] = 1
    (tmp_path / "v1.json").write_text(json.dumps(d1))
    k1 = load_keyfile(tmp_path / "v1.json")
    assert k1.weld is False
    x1 = L.extract(r.V, split, keyfile=k1)
    assert x1.n_merged == 0 and x1.n_vertices == 35947 + 300 and not x1.same_vertex_count
    assert "36247 vertices but the keyfile was made for 35947" in x1.warnings[0]
    assert L.extract(r.V, split, keyfile=path).warnings == []
    d1["weld"] = True  # a version-1 keyfile with the field is still read as version 1 (field ignored)
    (tmp_path / "v1b.json").write_text(json.dumps(d1))
    assert load_keyfile(tmp_path / "v1b.json").weld is False
    with pytest.raises(MeshError, match="weld must be True or False"):
        L.embed(bunny, payload="E", key="k", weld="yes")


def test_welded_vertex_count_in_the_warning(bunny):
    """A different mesh: the warning names the welded count and the count before welding."""
    r = L.embed(bunny, payload="E", key="k")
    elephant = meshmark.read_mesh(shared_mesh("classic/elephant.off"))
    soup, _ = non_indexed(elephant)
    x = L.extract(soup, keyfile=r.keyfile)
    assert not x.detected and x.n_vertices == 20007 and x.expected_vertices == 35947
    assert "20007 vertices (120066 before welding) but the keyfile was made for 35947" in x.warnings[0]


def test_cli_welds_by_default(tmp_path):
    """The Utah teapot file repeats 403 of its 3,644 vertices along its patch seams."""
    import subprocess
    import sys
    src = str(shared_mesh("classic/teapot.obj"))
    run = lambda *a: subprocess.run([sys.executable, "-m", "meshmark.cli", *a], capture_output=True, text=True)
    c = json.loads(run("capacity", src, "--method", "radial", "--json").stdout)
    c0 = json.loads(run("capacity", src, "--method", "radial", "--no-weld", "--json").stdout)
    assert (c["weld"], c["n_vertices"], c["capacity"]) == (True, 3241, 197)
    assert (c0["weld"], c0["n_vertices"], c0["capacity"]) == (False, 3644, 198)
    out, kf = str(tmp_path / "t.obj"), str(tmp_path / "k.json")
    e = run("embed", src, out, "--method", "radial", "--message", "tea", "--key", "k", "--keyfile", kf, "--json")
    assert e.returncode == 0, e.stderr
    assert json.loads(e.stdout)["weld"] is True and json.loads(open(kf).read())["weld"] is True
    marked = meshmark.read_mesh(out)
    w = meshmark.weld_vertices(marked)
    assert marked.n_vertices == 3644 and w.n_merged == 403  # the copies are still coincident in the file
    x = run("extract", out, "--keyfile", kf, "--json")
    d = json.loads(x.stdout)
    assert x.returncode == 0 and (d["message"], d["cdr"], d["n_vertices"], d["n_merged"]) == ("tea", 1.0, 3241, 403)
