"""Malformed arrays and files: each gives a specific MeshError (a ValueError), never a crash."""
import json
import struct
import subprocess
import sys

import numpy as np
import pytest

import meshmark
from meshmark import Mesh, MeshError

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TRI_F = np.array([[0, 1, 2], [0, 1, 3]])


def test_meshError_is_a_value_error():
    assert issubclass(MeshError, ValueError)


ARRAY_CASES = [
    ("nan", lambda: Mesh(np.where(np.arange(12).reshape(4, 3) == 7, np.nan, TRI_V), TRI_F),
     r"vertex 2 has a non-finite coordinate \(0, nan, 0\)"),
    ("inf", lambda: Mesh(np.vstack([TRI_V, [np.inf, 0, 0]]), TRI_F), r"vertex 4 has a non-finite coordinate \(inf"),
    ("index out of range", lambda: Mesh(TRI_V, [[0, 1, 2], [0, 1, 4]]),
     r"face 1 \(0, 1, 4\) refers to vertex 4, but the mesh has 4 vertices \(valid indices are 0..3\)"),
    ("negative index", lambda: Mesh(TRI_V, [[0, -1, 2]]), r"face 0 \(0, -1, 2\) refers to vertex -1"),
    ("repeated vertex", lambda: Mesh(TRI_V, [[0, 1, 2], [3, 1, 3]]), r"face 1 \(3, 1, 3\) repeats vertex 3"),
    ("no vertices", lambda: Mesh(np.zeros((0, 3)), np.zeros((0, 3), int)), r"mesh has no vertices"),
    ("no faces", lambda: Mesh(TRI_V, np.zeros((0, 3), int)), r"mesh has no faces"),
    ("V shape", lambda: Mesh(np.zeros((4, 2)), TRI_F), r"V must have shape \(n, 3\), got \(4, 2\)"),
    ("V dtype", lambda: Mesh(np.array([["a", "b", "c"]]), TRI_F), r"V must hold real numbers, got dtype <U1"),
    ("F dtype", lambda: Mesh(TRI_V, TRI_F.astype(float)), r"F must hold integer vertex indices, got dtype float64"),
    ("F shape", lambda: Mesh(TRI_V, np.array([0, 1, 2])), r"F must have shape \(m, k\) with k >= 3, got \(3,\)"),
    ("2-gon", lambda: Mesh(TRI_V, np.array([[0, 1]])), r"a face needs at least 3 vertices"),
    ("2-gon in list", lambda: Mesh(TRI_V, [[0, 1, 2], [1, 2]]), r"face 1 has 2 vertices; a face needs at least 3"),
    ("index beyond int32", lambda: Mesh(TRI_V, np.array([[0, 1, 2**40]])), r"outside the 32-bit index range"),
    ("offsets", lambda: Mesh.from_polygons(TRI_V, np.array([0, 1, 2]), np.array([0, 4])),
     r"face offsets end at 4 but there are 3 corners"),
]


@pytest.mark.parametrize("name,make,message", ARRAY_CASES, ids=[c[0] for c in ARRAY_CASES])
def test_bad_arrays(name, make, message):
    with pytest.raises(MeshError, match=message):
        make()


def _ply_header(fmt, nv, nf, vtype="float"):
    return (f"ply\nformat {fmt} 1.0\nelement vertex {nv}\nproperty {vtype} x\nproperty {vtype} y\n"
            f"property {vtype} z\nelement face {nf}\nproperty list uchar int vertex_indices\nend_header\n").encode()


def _binary_ply(V, F, nan_at=None):
    V = np.asarray(V, "<f4").copy()
    if nan_at is not None:
        V[nan_at, 1] = np.nan
    rec = np.zeros(len(F), dtype=[("n", "u1"), ("i", "<i4", 3)])
    rec["n"], rec["i"] = 3, F
    return _ply_header("binary_little_endian", len(V), len(F)) + V.tobytes() + rec.tobytes()


def _binary_stl(n_declared, n_written):
    tri = struct.pack("<12fH", *([0.0] * 3 + [0, 0, 0, 1, 0, 0, 0, 1, 0]), 0)
    return b"\0" * 80 + struct.pack("<I", n_declared) + tri * n_written


FILE_CASES = [
    ("missing", None, "missing.obj", r"cannot read '.*missing.obj': no such file"),
    ("empty", b"", "empty.ply", r"the file is empty"),
    ("unknown format", b"hello", "mesh.xyz", r"unsupported format '.xyz' \(supported: .obj .off .ply .stl\)"),
    ("truncated binary ply", _binary_ply(TRI_V, TRI_F)[:-10], "t.ply",
     r"truncated binary PLY: the header declares 4 vertices and 2 faces"),
    ("ply without end_header", b"ply\nformat ascii 1.0\nelement vertex 3\n", "h.ply", r"no 'end_header' line"),
    ("ply wrong magic", b"plx\nformat ascii 1.0\n", "m.ply", r"not a PLY file"),
    ("ply unknown format", b"ply\nformat binary_middle_endian 1.0\nend_header\n", "f.ply", r"unknown PLY format 'binary_middle_endian'"),
    ("ply nan", _binary_ply(TRI_V, TRI_F, nan_at=3), "nan.ply", r"vertex 3 has a non-finite coordinate \(0, nan, 1\)"),
    ("ply bad index", _binary_ply(TRI_V, [[0, 1, 2], [0, 1, 7]]), "i.ply", r"face 1 \(0, 1, 7\) refers to vertex 7"),
    ("ascii ply short", _ply_header("ascii", 4, 2) + b"0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n", "s.ply",
     r"header declares 4 vertices and 2 faces.*\(truncated or malformed file\)"),
    ("truncated binary stl", _binary_stl(10, 3), "t.stl", r"truncated binary STL: the header declares 10 triangles"),
    ("stl header only", b"\0" * 50, "h.stl", r"less than the 84-byte header"),
    ("ascii stl bad facet", b"solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\nendfacet\nendsolid\n",
     "a.stl", r"malformed ASCII STL"),
    ("obj garbage statement", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nxyz 1 2\nf 1 2 3\n", "g.obj", r"line 4: unrecognized OBJ statement 'xyz'"),
    ("obj nan", b"v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n", "n.obj", r"line 2: vertex coordinate 'nan' is not finite"),
    ("obj text coordinate", b"v 0 0 0\nv one 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj", r"line 2: 'one' is not a number"),
    ("obj index out of range", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n", "r.obj",
     r"line 4: face index 9 refers to a vertex that does not exist \(3 vertices in the file\)"),
    ("obj no faces", b"v 0 0 0\nv 1 0 0\n", "p.obj", r"no faces found \(an OBJ point cloud is not a mesh\)"),
    ("obj repeated vertex", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 1\n", "rep.obj", r"mesh has no faces"),
    ("off truncated", b"OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n", "t.off",
     r"could not parse the OFF data: the header declares 4 vertices and 2 faces \(truncated or malformed file\)"),
    ("off bad header", b"OFF\nfour two zero\n", "b.off", r"OFF header: expected vertex/face/edge counts, found 'four'"),
    ("binary off truncated", b"OFF BINARY\n" + struct.pack("<3i", 100, 50, 0), "b2.off", r"counts do not fit the file size"),
]


@pytest.mark.parametrize("name,content,fname,message", FILE_CASES, ids=[c[0] for c in FILE_CASES])
def test_bad_files(tmp_path, name, content, fname, message):
    path = tmp_path / fname
    if content is not None:
        path.write_bytes(content)
    with pytest.raises(MeshError, match=message):
        meshmark.read_mesh(path)


def test_strict_reading_rejects_collapsed_faces(tmp_path):
    p = tmp_path / "c.obj"
    p.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 1 4\n")
    m, info = meshmark.read_mesh(p, return_info=True)
    assert m.n_faces == 1 and info["n_dropped_faces"] == 1 and info["n_file_faces"] == 2
    with pytest.raises(MeshError, match=r"face 1 \(0, 0, 3\) repeats vertex 0"):
        meshmark.read_mesh(p, drop_collapsed=False)
    q = tmp_path / "q.obj"  # consecutive repeat in a quad merges into a triangle
    q.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 2 3\n")
    assert meshmark.read_mesh(q).F.tolist() == [[0, 1, 2]]


def test_directory_is_not_a_mesh(tmp_path):
    with pytest.raises(MeshError, match="not a regular file"):
        meshmark.read_mesh(tmp_path)


def test_write_errors(tmp_path):
    with pytest.raises(MeshError, match=r"unsupported format '.fbx'"):
        meshmark.write_mesh(tmp_path / "x.fbx", TRI_V, TRI_F)
    with pytest.raises(MeshError, match=r"cannot write '.*/no/such/dir/x.obj'"):
        meshmark.write_mesh(tmp_path / "no/such/dir/x.obj", TRI_V, TRI_F)
    with pytest.raises(MeshError, match="precision must be 1..17"):
        meshmark.write_mesh(tmp_path / "x.obj", TRI_V, TRI_F, precision=40)


def test_cli_reports_errors_without_traceback(tmp_path):
    p = tmp_path / "bad.ply"
    p.write_bytes(_binary_ply(TRI_V, TRI_F)[:-10])
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", "info", str(p), "--json"], capture_output=True, text=True)
    assert r.returncode == 2
    assert r.stderr.startswith("meshmark: error: cannot read") and "Traceback" not in r.stderr
    d = json.loads(r.stdout)  # the failure object (docs/json.md), the same message as on stderr
    assert d["ok"] is False and d["error"]["code"] == 2 and d["error"]["kind"] == "input"
    assert r.stderr == f"meshmark: error: {d['error']['message']}\n"


def test_cli_default_mesh_json():
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", "info", "--json"], capture_output=True, text=True, check=True)
    d = json.loads(r.stdout)
    assert d["format"] == "builtin" and d["n_faces"] == 9216 and d["manifold"] is True
