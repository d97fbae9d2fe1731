"""Regression tests for the hostile-file classes of issue 11: each gives a MeshError that names the
problem (and the line), never a crash, a gigabyte allocation or a non-UTF-8 message.

The allocation cases run in a child process with an address-space limit (RLIMIT_AS) so a
regression fails the test instead of taking the machine down, and report the child's peak RSS.
"""
import json
import os
import struct
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import meshmark
from meshmark import MeshError

TRI_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TRI_F = np.array([[0, 1, 2], [0, 1, 3], [0, 2, 3], [1, 2, 3]])


def _ply(fmt, vtype, V, F, big=False, itype="int"):
    head = (f"ply\nformat {fmt} 1.0\nelement vertex {len(V)}\nproperty {vtype} x\nproperty {vtype} y\n"
            f"property {vtype} z\nelement face {len(F)}\nproperty list uchar {itype} vertex_indices\nend_header\n").encode()
    if fmt == "ascii":
        body = "".join(" ".join(str(int(c)) if "int" in vtype or "char" in vtype or "short" in vtype else repr(float(c))
                                for c in v) + "\n" for v in V)
        body += "".join("3 " + " ".join(map(str, f)) + "\n" for f in F)
        return head + body.encode()
    np_t = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4",
            "float": "f4", "double": "f8", "int8": "i1", "uint8": "u1", "int16": "i2", "uint16": "u2"}
    e = ">" if big else "<"
    rec = np.zeros(len(F), dtype=[("n", "u1"), ("i", e + np_t[itype], 3)])
    rec["n"], rec["i"] = 3, F
    return head + np.asarray(V, e + np_t[vtype]).tobytes() + rec.tobytes()


@pytest.mark.parametrize("vtype", ["char", "uchar", "short", "ushort", "int", "uint", "int8", "uint16", "double"])
@pytest.mark.parametrize("fmt", ["binary_little_endian", "binary_big_endian", "ascii"])
def test_ply_scalar_coordinate_types(tmp_path, fmt, vtype):
    """Legal PLY files with integer coordinates crashed CGAL's reader (SIGSEGV); they are read
    exactly now (integers convert to float64 without loss)."""
    V = TRI_V * 7
    p = tmp_path / "t.ply"
    p.write_bytes(_ply(fmt, vtype, V, TRI_F, big=fmt.endswith("big_endian")))
    m, info = meshmark.read_mesh(p, return_info=True)
    np.testing.assert_array_equal(m.V, V)
    np.testing.assert_array_equal(m.F, TRI_F)
    assert info["float32"] is False and info["binary"] == (fmt != "ascii")


@pytest.mark.parametrize("itype", ["uchar", "short", "uint", "int16"])
def test_ply_integer_index_types(tmp_path, itype):
    p = tmp_path / "t.ply"
    p.write_bytes(_ply("binary_little_endian", "float", TRI_V, TRI_F, itype=itype))
    np.testing.assert_array_equal(meshmark.read_mesh(p).F, TRI_F)


PLY_HEAD = "ply\nformat ascii 1.0\nelement vertex 3\n"
PLY_TAIL = "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n"

BAD_PLY = [
    ("z is a list", PLY_HEAD + "property float x\nproperty float y\nproperty list uchar float z\n" + PLY_TAIL,
     r"PLY header line 6: vertex coordinate 'z' is declared as a list"),
    ("property before element", "ply\nformat ascii 1.0\nproperty float x\n" + PLY_HEAD[21:] + PLY_TAIL,
     r"PLY header line 3: 'property' before any 'element'"),
    ("no coordinates", PLY_HEAD + "property float a\nproperty float b\nproperty float c\n" + PLY_TAIL,
     r"PLY header line 3: element 'vertex' has no 'x' property"),
    ("no z", PLY_HEAD + "property float x\nproperty float y\n" + PLY_TAIL.replace("0 0 0\n1 0 0\n0 1 0", "0 0\n1 0\n0 1"),
     r"element 'vertex' has no 'z' property"),
    ("count 1e308", "ply\nformat ascii 1.0\nelement vertex 1e308\nproperty float x\nproperty float y\nproperty float z\n" + PLY_TAIL,
     r"PLY header line 3: bad element count '1e308' \(a non-negative integer is needed\)"),
    ("count beyond int32", "ply\nformat ascii 1.0\nelement vertex 99999999999\n", r"declares 99999999999 records; at most 2147483647"),
    ("float indices", PLY_HEAD + "property float x\nproperty float y\nproperty float z\n" +
     PLY_TAIL.replace("uchar int", "uchar float"), r"face vertex indices must have an integer type, not 'float'"),
    ("ascii non-integer index", PLY_HEAD + "property float x\nproperty float y\nproperty float z\n" +
     PLY_TAIL.replace("3 0 1 2", "3 0 1.5 2"), r"PLY line 13: face 0 property 'vertex_indices': '1.5' is not an integer"),
    ("face scalar indices", PLY_HEAD + "property float x\nproperty float y\nproperty float z\n" +
     PLY_TAIL.replace("list uchar int", "int"), r"face property 'vertex_indices' must be a list"),
    ("unknown type", PLY_HEAD + "property float128 x\n" + PLY_TAIL, r"PLY header line 4: unknown PLY type 'float128'"),
    ("no properties", "ply\nformat ascii 1.0\nelement vertex 5\nelement face 0\nend_header\n",
     r"PLY header line 3: element 'vertex' has 5 records but no properties"),
]


@pytest.mark.parametrize("name,text,message", BAD_PLY, ids=[c[0] for c in BAD_PLY])
def test_bad_ply_headers(tmp_path, name, text, message):
    p = tmp_path / "b.ply"
    p.write_bytes(text.encode())
    with pytest.raises(MeshError, match=message):
        meshmark.read_mesh(p)


BAD_TEXT = [
    ("obj fractional index", "t.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1.5 2 3\n", r"line 4: face index '1.5' is not an integer"),
    ("obj index beyond int32", "t.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999\n", r"line 4: face index '99999999999' is out of range"),
    ("obj relative index before start", "t.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n",
     r"line 4: face index -4 refers to a vertex that does not exist \(3 vertices before this line\)"),
    ("obj 2-gon", "t.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", r"line 4: a face needs at least 3 vertices, this one has 2"),
    ("off fractional index", "t.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", r"line 6: face index '1.5' is not an integer"),
    ("off corner count", "t.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n",
     r"line 6: face 0 declares 1000000000 corners but the line holds 3 indices"),
    ("off 10^9 vertices", "t.off", b"OFF\n1000000000 1 0\n0 0 0\n", r"the header declares 1000000000 vertices and 1 faces .*they need at least 6000000008 bytes but 6 follow"),
    ("off counts beyond int32", "t.off", b"OFF\n99999999999 1 0\n", r"at most 2147483647 of each are supported"),
    ("off vertex text", "t.off", b"OFF\n3 1 0\n0 0 0\n1 x 0\n0 1 0\n3 0 1 2\n", r"line 4: 'x' is not a number"),
]


@pytest.mark.parametrize("name,fname,content,message", BAD_TEXT, ids=[c[0] for c in BAD_TEXT])
def test_bad_obj_off(tmp_path, name, fname, content, message):
    p = tmp_path / fname
    p.write_bytes(content)
    with pytest.raises(MeshError, match=message):
        meshmark.read_mesh(p)


@pytest.mark.parametrize("fname,content,expected", [
    ("u.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n\xffx 1\nf 1 2 3\n", r"line 4: unrecognized OBJ statement '\\xffx'"),
    ("u.off", b"OFF\n\xff\xfe 1 0\n", r"OFF header: expected vertex/face/edge counts, found '\\xff\\xfe'"),
    ("u.ply", b"ply\nformat ascii 1.0\nelement vertex 3\n\xe9\xff float x\n", r"PLY header line 4: unknown PLY header keyword '\\xe9\\xff'"),
    ("u.ply", b"ply\nformat \xc3\xa9\xff 1.0\n", r"unknown PLY format '\u00e9\\xff'"),
])
def test_non_utf8_bytes_are_escaped(tmp_path, fname, content, expected):
    """A non-UTF-8 byte in a header ended in a UnicodeDecodeError traceback; it is shown escaped
    (valid UTF-8 such as 'é' is kept)."""
    p = tmp_path / fname
    p.write_bytes(content + b"end_header\n" if fname.endswith(".ply") and b"float x" in content else content)
    with pytest.raises(MeshError, match=expected) as exc:
        meshmark.read_mesh(p)
    str(exc.value).encode("utf-8")  # valid UTF-8 (would raise on a lone surrogate)


def test_non_utf8_file_name(tmp_path):
    """`meshmark info $'\\xff.obj'` gave a traceback: the name is passed as bytes and shown escaped."""
    name = os.fsdecode(b"\xff.obj")
    p = tmp_path / name
    p.write_bytes(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    assert meshmark.read_mesh(p).n_faces == 1
    with pytest.raises(MeshError, match=r"\\xff-missing.obj': no such file"):
        meshmark.read_mesh(tmp_path / os.fsdecode(b"\xff-missing.obj"))
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", "info", os.fsencode(tmp_path) + b"/\xfemissing.obj"],
                       capture_output=True)
    assert r.returncode == 2 and b"Traceback" not in r.stderr and b"\\xfemissing.obj" in r.stderr
    r.stderr.decode("utf-8")


# --- allocation bombs: a child process under RLIMIT_AS, reporting its peak RSS -----------------
_CHILD = textwrap.dedent("""
    import json, resource, sys
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))
    import meshmark
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    try:
        meshmark.read_mesh(sys.argv[1])
        out = "read"
    except meshmark.MeshError as e:
        out = str(e)
    after = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(json.dumps({"out": out, "grew_kb": after - before}))
""")


def _bombs():
    ply_face = (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                b"property float z\nelement face 1\nproperty list uint int vertex_indices\nend_header\n"
                + struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack("<I", 2**31) + struct.pack("<3i", 0, 1, 2))
    ply_count = (b"ply\nformat binary_little_endian 1.0\nelement vertex 2000000000\nproperty float x\nproperty float y\n"
                 b"property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n" + b"\0" * 200)
    return [
        ("ply face list 2^31", "a.ply", ply_face, r"face 0 declares a list of 2147483648 items but only 12 bytes are left"),
        ("ply vertex count 2e9", "b.ply", ply_count, r"truncated binary PLY: the header declares 2000000000 vertices"),
        ("off face line 1e9", "c.off", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n1000000000 0 1 2\n", r"declares 1000000000 corners"),
        ("off header 1e9 vertices", "d.off", b"OFF\n1000000000 1000000000 0\n0 0 0\n", r"they need at least"),
        ("ply count 1e308", "e.ply", b"ply\nformat ascii 1.0\nelement vertex 1e308\n", r"bad element count '1e308'"),
        ("binary off counts", "f.off", b"OFF BINARY\n" + struct.pack(">3i", 2**30, 2**30, 0), r"counts do not fit the file size"),
        ("binary stl count", "g.stl", b"\0" * 80 + struct.pack("<I", 2**31) + b"\0" * 50, r"truncated binary STL"),
    ]


@pytest.mark.parametrize("name,fname,content,message", _bombs(), ids=[b[0] for b in _bombs()])
def test_counts_are_checked_before_allocating(tmp_path, name, fname, content, message):
    p = tmp_path / fname
    p.write_bytes(content)
    r = subprocess.run([sys.executable, "-c", _CHILD, str(p)], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0, r.stderr[-2000:]
    d = json.loads(r.stdout)
    assert d["out"] != "read"
    import re
    assert re.search(message, d["out"]), d["out"]
    assert d["grew_kb"] < 16 * 1024, d  # far below the gigabytes CGAL's readers took


def test_long_header_and_huge_polygon(tmp_path):
    """A legal PLY with 200,000 comment lines reads (the header is bounded by the file, not a line
    count); one face of 100,000 corners is checked for repeats in O(k log k) (the quadratic scan took
    minutes per million corners), and a repeat in it is found."""
    p = tmp_path / "c.ply"
    p.write_bytes(b"ply\nformat ascii 1.0\n" + b"comment x\n" * 200000 + PLY_HEAD[21:].encode() +
                  b"property float x\nproperty float y\nproperty float z\n" + PLY_TAIL.encode())
    assert meshmark.read_mesh(p).n_faces == 1
    n = 100000
    verts = b"".join(b"v %d %d 0\n" % (i % 1000, i // 1000) for i in range(n))
    q = tmp_path / "poly.obj"
    q.write_bytes(verts + b"f " + b" ".join(b"%d" % (i + 1) for i in range(n)) + b"\n")
    m = meshmark.read_mesh(q)
    assert m.face_sizes.tolist() == [n] and meshmark.mesh_info(m)["n_faces"] == 1
    q.write_bytes(verts + b"f " + b" ".join(b"%d" % (i + 1) for i in range(n)) + b" 5\n")
    with pytest.raises(MeshError, match=r"face 0 \(0, 1, 2, 3, 4, 5, 6, 7, \.\.\.\) repeats vertex 4"):
        meshmark.read_mesh(q, drop_collapsed=False)
    with pytest.raises(MeshError, match="mesh has no faces"):
        meshmark.read_mesh(q)  # the collapsed face is dropped, and nothing is left
