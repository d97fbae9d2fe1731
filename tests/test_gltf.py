"""glTF 2.0 in and out (meshmark.gltf, docs/gltf.md): the shared rigged characters and hand-built
assets (tests/gltf_assets.py) in every storage the writer handles.

The byte comparisons are made here from the files' own JSON with struct/json/re (not with the
package's span finder): outside the POSITION elements of the marked accessors and the text of the
``min``/``max`` arrays, the output must be the input byte for byte.
"""
import json
import os
import re
import struct

import numpy as np
import pytest

import meshmark
from meshmark.watermark import embed, extract
from meshmark.watermark.payload import Payload

from conftest import shared_mesh
from gltf_assets import OCTA_F, OCTA_V, asset, glb_bytes, gltf_bytes



def run(*args):
    """The meshmark command in this process: (exit status, stdout, stderr)."""
    from click.testing import CliRunner
    from meshmark.cli import main
    r = CliRunner().invoke(main, [str(a) for a in args])
    if r.exception and not isinstance(r.exception, SystemExit):
        raise r.exception
    return r.exit_code, r.stdout, r.stderr

BOUNDS = re.compile(rb'"(?:min|max)"\s*:\s*\[[^\]]*\]\s*')


def _glb(data: bytes):
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    chunks, off = [], 12
    while off < len(data):
        n, t = struct.unpack_from("<II", data, off)
        chunks.append((t, data[off + 8:off + 8 + n]))
        off += 8 + n
    return chunks


def _position_mask(doc, size, accessors):
    """Boolean mask over a buffer of the bytes of the given POSITION accessors' elements."""
    mask = np.zeros(size, bool)
    for ai in accessors:
        a = doc["accessors"][ai]
        v = doc["bufferViews"][a["bufferView"]]
        start, stride = v.get("byteOffset", 0) + a.get("byteOffset", 0), v.get("byteStride", 12)
        for i in range(a["count"]):  # small counts; an independent, obvious loop
            mask[start + i * stride:start + i * stride + 12] = True
        if "sparse" in a:  # the substituted values (tightly packed)
            s = a["sparse"]
            v = doc["bufferViews"][s["values"]["bufferView"]]
            start = v.get("byteOffset", 0) + s["values"].get("byteOffset", 0)
            mask[start:start + 12 * s["count"]] = True
    return mask


def _positions(doc):
    return sorted({p["attributes"]["POSITION"] for m in doc["meshes"] for p in m["primitives"]})


def _check_only_positions_changed(src: bytes, out: bytes):
    """Assert: same chunks; BIN equal outside the position elements; JSON equal outside min/max of
    POSITION accessors (text) and equal as data except those min/max. Returns the changed accessors."""
    a, b = _glb(src), _glb(out)
    assert [t for t, _ in a] == [t for t, _ in b] and len(a[1][1]) == len(b[1][1])
    da, db = json.loads(a[0][1]), json.loads(b[0][1])
    pos = _positions(da)
    mask = _position_mask(da, len(a[1][1]), pos)
    x, y = np.frombuffer(a[1][1], np.uint8), np.frombuffer(b[1][1], np.uint8)
    assert np.array_equal(x[~mask], y[~mask]), "a byte outside the positions changed"
    assert BOUNDS.sub(b"", a[0][1]).rstrip() == BOUNDS.sub(b"", b[0][1]).rstrip(), "JSON text changed outside min/max"
    changed = []
    for ai, (pa, pb) in enumerate(zip(da["accessors"], db["accessors"])):
        if ai not in pos:
            assert pa == pb, f"accessor {ai} changed"
            continue
        if pa != pb:
            changed.append(ai)
    for k in da:
        if k != "accessors":
            assert da[k] == db[k], k
    for c in a[2:]:
        assert c in b
    return changed, int((x != y).sum())


@pytest.mark.parametrize("name", ["Fox", "Knight"])
def test_embed_rigged_changes_only_positions(name, tmp_path):
    src = shared_mesh(f"rigged/{name}.glb")
    out, kf = tmp_path / "marked.glb", tmp_path / "k.json"
    args = ["--bits", "1", "--K", "100", "--n-thr", "1", "--n-robust", "1", "--carrier", "thesis"] if name == "Fox" \
        else ["--message", "K"]
    r = run("embed", str(src), str(out), "--key", name, "--keyfile", str(kf), "--json", *args)
    assert r[0] == 0, r[2]
    d = json.loads(r[1])
    assert d["input"] == str(src) and d["output"] == str(out)
    data_in, data_out = src.read_bytes(), out.read_bytes()
    changed, n_bytes = _check_only_positions_changed(data_in, data_out)
    assert n_bytes > 100 and changed  # the mark is there
    assert len(data_in) == len(data_out)  # min/max rewritten within their old length
    # the new min/max are the marked positions' bounds (float32), as the spec requires
    doc = json.loads(_glb(data_out)[0][1])
    mesh, info = meshmark.read_mesh(out, return_info=True)
    for part, Vp in zip(info["gltf"].parts, info["gltf"].joined.split(mesh.V)):
        a = doc["accessors"][part.accessor]
        assert np.array_equal(np.float32(a["min"]), Vp.min(0).astype(np.float32))
        assert np.array_equal(np.float32(a["max"]), Vp.max(0).astype(np.float32))
    r = run("extract", str(out), "--keyfile", str(kf), "--json")
    assert r[0] == 0 and json.loads(r[1])["detected"], r[1] + r[2]
    r = run("extract", str(src), "--keyfile", str(kf))
    assert r[0] == 1  # the unmarked original


def test_read_rigged_counts_and_roundtrip(tmp_path):
    for name, nv, nf, parts in [("Fox", 1728, 576, 1), ("Knight", 7024, 6952, 15)]:  # SOURCES.md
        src = shared_mesh(f"rigged/{name}.glb")
        mesh, info = meshmark.read_mesh(src, return_info=True)
        g = info["gltf"]
        assert (mesh.n_vertices, mesh.n_faces, len(g.parts), info["format"], g.skinned) == (nv, nf, parts, "glb", True)
        out = tmp_path / f"{name}.glb"
        meshmark.write_mesh(out, mesh, source=g)  # nothing changed: the same file
        assert out.read_bytes() == src.read_bytes()
    # the Knight's 15 parts are its 15 meshes, in file order, each one POSITION accessor
    doc = json.loads(_glb(src.read_bytes())[0][1])
    assert [p.accessor for p in g.parts] == [m["primitives"][0]["attributes"]["POSITION"] for m in doc["meshes"]]


def _mark(mesh, V, seed=0, scale=1e-3):
    rng = np.random.default_rng(seed)
    return V + rng.normal(scale=scale, size=V.shape)


@pytest.mark.parametrize("kw", [{}, {"interleaved": True}, {"shared": False}, {"strip": True, "lines": True},
                                {"morph": True}, {"sparse": True}])
@pytest.mark.parametrize("container", ["glb", "gltf"])
def test_written_back_exactly(kw, container, tmp_path):
    doc, blob = asset(**kw)
    src = tmp_path / f"in.{container}"
    src.write_bytes(glb_bytes(doc, blob) if container == "glb" else gltf_bytes(doc, blob))
    mesh, info = meshmark.read_mesh(src, return_info=True)
    g = info["gltf"]
    assert mesh.n_vertices == 6 + (4 if kw.get("strip") else 0)
    # two primitives over one POSITION accessor: one block of 6 vertices, all 8 triangles
    assert np.array_equal(mesh.V[:6], OCTA_V.astype(np.float64)) and mesh.n_faces == 8 + 2 * bool(kw.get("strip"))
    assert sorted(map(tuple, np.sort(mesh.triangles[:8], 1))) == sorted(map(tuple, np.sort(OCTA_F.astype(int), 1)))
    out = tmp_path / f"out.{container}"
    meshmark.write_mesh(out, mesh, source=g)
    assert out.read_bytes() == src.read_bytes()  # unchanged: byte for byte
    V = _mark(mesh, mesh.V)
    meshmark.write_mesh(out, V, source=g)
    back = meshmark.read_mesh(out)
    assert np.array_equal(back.V, V.astype(np.float32).astype(np.float64))
    assert np.array_equal(back.face_indices, mesh.face_indices)
    if container == "glb":
        changed, _ = _check_only_positions_changed(src.read_bytes(), out.read_bytes())
        assert changed


def test_strip_and_lines():
    doc, blob = asset(strip=True, lines=True)
    import tempfile
    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "a.glb")
        open(p, "wb").write(glb_bytes(doc, blob))
        mesh, info = meshmark.read_mesh(p, return_info=True)
    T = mesh.triangles[-2:] - 6  # strip 0 1 2 3, glTF 2.0 §3.7.2.1: {v_i, v_i+(1+i%2), v_i+(2-i%2)}
    assert T.tolist() == [[0, 1, 2], [1, 3, 2]]
    notes = " ".join(info["gltf"].notes)
    assert "lines skipped" in notes and "triangle strip converted to 2 triangles" in notes


def test_interleaved_normals_untouched(tmp_path):
    doc, blob = asset(interleaved=True)
    src, out = tmp_path / "a.glb", tmp_path / "b.glb"
    src.write_bytes(glb_bytes(doc, blob))
    mesh, info = meshmark.read_mesh(src, return_info=True)
    meshmark.write_mesh(out, _mark(mesh, mesh.V), source=info["gltf"])
    rec_in = np.frombuffer(_glb(src.read_bytes())[1][1][:144], "<f4").reshape(6, 6)
    rec_out = np.frombuffer(_glb(out.read_bytes())[1][1][:144], "<f4").reshape(6, 6)
    assert np.array_equal(rec_in[:, 3:], rec_out[:, 3:]) and not np.array_equal(rec_in[:, :3], rec_out[:, :3])


def test_external_bin_and_other_folder(tmp_path):
    doc, blob = asset()
    doc["images"] = [{"uri": "tex%20a.png"}]
    (tmp_path / "in").mkdir()
    (tmp_path / "in" / "hero.bin").write_bytes(blob)
    (tmp_path / "in" / "tex a.png").write_bytes(b"\x89PNG fake")
    src = tmp_path / "in" / "hero.gltf"
    src.write_bytes(gltf_bytes(doc, blob, uri="hero.bin"))
    mesh, info = meshmark.read_mesh(src, return_info=True)
    before = (tmp_path / "in" / "hero.bin").read_bytes()
    (tmp_path / "out").mkdir()
    out = tmp_path / "out" / "marked.gltf"
    V = _mark(mesh, mesh.V)
    meshmark.write_mesh(out, V, source=info["gltf"])
    assert (tmp_path / "in" / "hero.bin").read_bytes() == before  # the input's buffer is never touched
    d = json.loads(out.read_bytes())
    assert d["buffers"][0]["uri"] == "marked.bin" and (tmp_path / "out" / "marked.bin").is_file()
    assert d["images"][0]["uri"] == "../in/tex%20a.png"  # unchanged file, named from the new folder
    assert np.array_equal(meshmark.read_mesh(out).V, V.astype(np.float32).astype(np.float64))
    # into the input's own folder under the input's name: refused (its .bin would be overwritten)
    with pytest.raises(meshmark.MeshError, match="file of the input"):
        meshmark.write_mesh(tmp_path / "in" / "hero.gltf", V, source=info["gltf"])
    # the writer refuses a source that changed since it was read
    src.write_bytes(src.read_bytes() + b" ")
    with pytest.raises(meshmark.MeshError, match="changed since it was read"):
        meshmark.write_mesh(out, V, source=info["gltf"])


def test_quantized_read_and_refused_write(tmp_path):
    doc, blob = asset(quantized=True)
    src = tmp_path / "q.glb"
    src.write_bytes(glb_bytes(doc, blob))
    mesh, info = meshmark.read_mesh(src, return_info=True)
    assert info["gltf"].parts[0].encoding == "int16 normalized" and not info["float32"]
    assert np.allclose(mesh.V, OCTA_V / 0.75, atol=1 / 32767)  # SHORT normalized: c / 32767
    meshmark.write_mesh(tmp_path / "same.glb", mesh, source=info["gltf"])
    assert (tmp_path / "same.glb").read_bytes() == src.read_bytes()
    with pytest.raises(meshmark.MeshError, match="quantized .*dequantize"):
        meshmark.write_mesh(tmp_path / "o.glb", _mark(mesh, mesh.V), source=info["gltf"])


def test_shared_bytes_refused(tmp_path):
    doc, blob = asset()
    doc["accessors"].append({"bufferView": 0, "byteOffset": 12, "componentType": 5126, "count": 2, "type": "VEC3"})
    src = tmp_path / "a.glb"
    src.write_bytes(glb_bytes(doc, blob))
    mesh, info = meshmark.read_mesh(src, return_info=True)
    with pytest.raises(meshmark.MeshError, match="accessor 4 shares bytes"):
        meshmark.write_mesh(tmp_path / "b.glb", _mark(mesh, mesh.V), source=info["gltf"])


def test_plain_mesh_as_minimal_gltf(tmp_path):
    suz = meshmark.read_mesh(shared_mesh("classic/suzanne.obj"))  # quads and triangles
    for ext in ("glb", "gltf"):
        p = tmp_path / f"s.{ext}"
        meshmark.write_mesh(p, suz)
        back = meshmark.read_mesh(p)
        assert np.array_equal(back.V, suz.V.astype(np.float32).astype(np.float64))
        assert np.array_equal(back.triangles, suz.triangles)
        if ext == "glb":
            d = json.loads(_glb(p.read_bytes())[0][1])
            a = d["accessors"][d["meshes"][0]["primitives"][0]["attributes"]["POSITION"]]
            assert np.allclose(a["min"], suz.V.min(0), atol=1e-6) and np.allclose(a["max"], suz.V.max(0), atol=1e-6)


def test_cli_stego_and_issue_write_back(tmp_path):
    src = shared_mesh("rigged/Fox.glb")
    out = tmp_path / "st.glb"
    r = run("stego", "embed", str(src), str(out), "--message", "hi", "--key", "k", "--precision", "float32", "--json")
    assert r[0] == 0, r[2]
    _check_only_positions_changed(src.read_bytes(), out.read_bytes())
    r = run("stego", "extract", str(out), "--key", "k", "--precision", "float32")
    assert r[0] == 0 and r[1].strip() == "hi"
    r = run("stego", "embed", str(src), str(out), "--message", "hi", "--key", "k", "--force")
    assert r[0] == 2 and "float32" in r[2]
    src = shared_mesh("rigged/Knight.glb")
    r = run("issue", str(src), str(tmp_path / "c"), "--copies", "2", "--key", "s", "--registry",
                             str(tmp_path / "r.sqlite"), "--json")
    assert r[0] == 0, r[2]
    copies = json.loads(r[1])["copies"]
    for c in copies:
        _check_only_positions_changed(src.read_bytes(), open(c["path"], "rb").read())
    r = run("trace", copies[1]["path"], "--registry", str(tmp_path / "r.sqlite"), "--json")
    assert r[0] == 0 and json.loads(r[1])["copy"] == copies[1]["id"]


def test_cross_container_refused(tmp_path):
    mesh, info = meshmark.read_mesh(shared_mesh("rigged/Fox.glb"), return_info=True)
    with pytest.raises(meshmark.MeshError, match="as a .glb too"):
        meshmark.write_mesh(tmp_path / "a.gltf", mesh, source=info["gltf"])
    with pytest.raises(meshmark.MeshError, match=r"shape \(5, 3\)"):
        meshmark.write_mesh(tmp_path / "a.glb", mesh.V[:5], source=info["gltf"])
