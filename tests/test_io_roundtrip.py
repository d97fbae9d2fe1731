"""Round trips through every format: F exact; V exact for double formats, float32-exact for float ones."""
import numpy as np
import pytest

import meshmark
from meshmark import Mesh
from conftest import shared_mesh

# (extension, write options, coordinates stored as float32?)
FORMATS = [
    ("obj", {}, False),
    ("off", {}, False),
    ("ply", {"binary": True}, False),
    ("ply", {"binary": False}, False),
    ("ply", {"binary": True, "float32": True}, True),
    ("ply", {"binary": False, "float32": True}, True),
    ("stl", {"binary": True}, True),
    ("stl", {"binary": False}, False),  # ASCII STL is decimal text: 17 digits round-trip float64
]
IDS = [f"{e}-{'-'.join(f'{k}={v}' for k, v in o.items()) or 'default'}" for e, o, _ in FORMATS]


def first_appearance_order(m: Mesh) -> Mesh:
    """Renumber vertices in order of first use by the faces (STL's order) and drop unreferenced ones."""
    idx = m.face_indices
    _, first = np.unique(idx, return_index=True)
    order = idx[np.sort(first)]
    new = np.empty(m.n_vertices, np.int64)
    new[order] = np.arange(len(order))
    return Mesh.from_polygons(m.V[order], new[idx], m.face_offsets)


@pytest.mark.parametrize("ext,opts,is_float", FORMATS, ids=IDS)
def test_roundtrip_bunny(tmp_path, bunny, ext, opts, is_float):
    src = first_appearance_order(bunny) if ext == "stl" else bunny
    path = tmp_path / f"bunny.{ext}"
    meshmark.write_mesh(path, src, **opts)
    back, info = meshmark.read_mesh(path, return_info=True)
    assert info["float32"] == is_float
    np.testing.assert_array_equal(back.face_indices, src.face_indices)
    np.testing.assert_array_equal(back.face_offsets, src.face_offsets)
    expected = src.V.astype(np.float32).astype(np.float64) if is_float else src.V
    np.testing.assert_array_equal(back.V, expected)  # bit-exact


@pytest.mark.parametrize("ext,opts,is_float", [f for f in FORMATS if f[0] != "stl"],
                         ids=[i for i, f in zip(IDS, FORMATS) if f[0] != "stl"])
def test_roundtrip_random_doubles_and_polygons(tmp_path, rng, ext, opts, is_float):
    """Awkward doubles (tiny, huge, negative, subnormal-free) and mixed polygon sizes."""
    V = rng.normal(size=(9, 3)) * 10.0 ** rng.integers(-12, 12, size=(9, 1))
    faces = [[0, 1, 2, 3], [2, 4, 5], [5, 6, 7, 8, 0]]
    m = Mesh(V, faces)
    path = tmp_path / f"poly.{ext}"
    meshmark.write_mesh(path, m, **opts)
    back = meshmark.read_mesh(path)
    assert back.face_sizes.tolist() == [4, 3, 5]
    np.testing.assert_array_equal(back.face_indices, m.face_indices)
    expected = V.astype(np.float32).astype(np.float64) if is_float else V
    np.testing.assert_array_equal(back.V, expected)


def test_stl_polygons_are_triangulated(tmp_path):
    V = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], float)
    meshmark.write_mesh(tmp_path / "q.stl", Mesh(V, [[0, 1, 2, 3]]))
    back = meshmark.read_mesh(tmp_path / "q.stl")
    assert back.F.tolist() == [[0, 1, 2], [0, 2, 3]]


def test_obj_decimals_rounds_like_exporters(tmp_path, bunny):
    m = bunny.with_vertices(bunny.V * np.pi)  # more digits than the file had
    meshmark.write_mesh(tmp_path / "b.obj", m, decimals=6)
    back = meshmark.read_mesh(tmp_path / "b.obj")
    err = np.abs(back.V - m.V).max()
    assert 0.4e-6 < err <= 0.5e-6 + 1e-15
    text = (tmp_path / "b.obj").read_text().splitlines()
    vline = next(l for l in text if l.startswith("v "))
    assert all(len(t.split(".")[1]) == 6 for t in vline.split()[1:])


def test_vertex_order_and_unreferenced_vertices_preserved(tmp_path, bunny):
    meshmark.write_mesh(tmp_path / "b.ply", bunny)
    back = meshmark.read_mesh(tmp_path / "b.ply")
    assert back.n_vertices == 35947
    assert meshmark.mesh_info(back)["n_unreferenced_vertices"] == 1113


def test_binary_off_little_endian_is_read():
    m, info = meshmark.read_mesh(shared_mesh("corpus/pmp_fairing-cross.off"), return_info=True)
    assert info["binary"] and info["float32"]
    assert (m.n_vertices, m.n_faces) == (4983, 9762)
    assert np.abs(m.V).max() <= 4.0 + 1e-6


def test_read_matches_independent_readers():
    """plyfile and a numpy OBJ parse agree with our readers."""
    from plyfile import PlyData
    p = shared_mesh("classic/horse.ply")
    ply = PlyData.read(str(p))
    m = meshmark.read_mesh(p)
    V = np.stack([ply["vertex"][k] for k in "xyz"], 1).astype(np.float64)
    np.testing.assert_array_equal(m.V, V)
    F = np.stack(ply["face"].data["vertex_indices"]).astype(np.int64)
    np.testing.assert_array_equal(m.F, F)
    lines = shared_mesh("classic/fandisk.obj").read_text().splitlines()
    Vo = np.array([[float(t) for t in l.split()[1:4]] for l in lines if l.startswith("v ")])
    np.testing.assert_array_equal(meshmark.read_mesh(shared_mesh("classic/fandisk.obj")).V, Vo)
