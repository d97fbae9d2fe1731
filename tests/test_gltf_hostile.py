"""Hostile glTF files (docs/gltf.md, docs/security.md): each is a MeshError naming what is wrong,
never a crash, a hang or a large allocation; the CLI exits 2. tests/test_fuzz_readers.py runs the
seeded campaign; these are the named cases."""
import json
import struct

import numpy as np
import pytest

import meshmark
from gltf_assets import asset, glb_bytes, gltf_bytes


def _doc():
    return asset(shared=False)


def _case(tmp_path, data: bytes, ext="glb"):
    p = tmp_path / f"h.{ext}"
    p.write_bytes(data)
    return p


def _edit(fn, ext="glb"):
    doc, blob = _doc()
    fn(doc)
    return glb_bytes(doc, blob) if ext == "glb" else gltf_bytes(doc, blob)


GOOD = glb_bytes(*_doc())
CASES = [
    ("empty", b"", "empty"),
    ("truncated", GOOD[:len(GOOD) // 2], "header gives"),
    ("short header", GOOD[:7], "too short for a GLB header"),
    ("chunk length", GOOD[:12] + struct.pack("<I", 10**9) + GOOD[16:], "declares 1000000000 bytes"),
    ("version 1", GOOD[:4] + struct.pack("<I", 1) + GOOD[8:], "only glTF 2.0"),
    ("bad JSON", GOOD[:20] + b"[" + GOOD[21:], "bad JSON"),
    ("huge count", _edit(lambda d: d["accessors"][0].update(count=2**31)), "need .* bytes; bufferView 0 has 72"),
    ("count without data", _edit(lambda d: d["accessors"][0].pop("bufferView") or d["accessors"][0].update(count=2**31)),
     "without a bufferView"),
    ("offset past view", _edit(lambda d: d["accessors"][0].update(byteOffset=64)), "bufferView 0 has 72"),
    ("view past buffer", _edit(lambda d: d["bufferViews"][0].update(byteLength=10**6)), "runs past buffer 0"),
    ("buffer past chunk", _edit(lambda d: d["buffers"][0].update(byteLength=10**6)), "exceeds the BIN chunk"),
    ("stride too small", _edit(lambda d: d["bufferViews"][0].update(byteStride=8)), "smaller than an element"),
    ("index out of range", _edit(lambda d: d["accessors"][2].update(componentType=5125, count=2)),
     "index 0 is|need"),
    ("wrong type", _edit(lambda d: d["accessors"][0].update(type="VEC2")), "expected VEC3"),
    ("component type", _edit(lambda d: d["accessors"][0].update(componentType="float")), "componentType|wrong type"),
    ("bad mode", _edit(lambda d: d["meshes"][0]["primitives"][0].update(mode=9)), "mode 9"),
    ("no accessors", _edit(lambda d: d.pop("accessors")), "no 'accessors' array"),
    ("draco", _edit(lambda d: d.update(extensionsUsed=["KHR_draco_mesh_compression"])), "decompress first"),
    ("meshopt", _edit(lambda d: d.update(extensionsRequired=["EXT_meshopt_compression"])), "decompress first"),
    ("no asset", _edit(lambda d: d.pop("asset")), "not a glTF 2.0 file"),
    ("no triangles", _edit(lambda d: [p.update(mode=0) for p in d["meshes"][0]["primitives"]]), "no triangle mesh"),
    ("sparse unsorted", _edit(lambda d: d["accessors"][0].update(sparse={
        "count": 2, "indices": {"bufferView": 2, "byteOffset": 4, "componentType": 5123}, "values": {"bufferView": 0}})),
     "strictly increasing"),
]


@pytest.mark.parametrize("name,data,message", CASES, ids=[c[0] for c in CASES])
def test_hostile_glb(tmp_path, name, data, message):
    with pytest.raises(meshmark.MeshError, match=message):
        meshmark.read_mesh(_case(tmp_path, data))


def test_deep_json_gltf(tmp_path):
    p = _case(tmp_path, b'{"asset":{"version":"2.0"},"x":' + b"[" * 100000 + b"]" * 100000 + b"}", "gltf")
    with pytest.raises(meshmark.MeshError, match="nests deeper than 64"):
        meshmark.read_mesh(p)


def test_data_uri_and_external(tmp_path):
    doc, blob = _doc()
    bad = json.loads(gltf_bytes(doc, blob))
    bad["buffers"][0]["uri"] = "data:application/octet-stream;base64,@@@"
    with pytest.raises(meshmark.MeshError, match="not valid base64"):
        meshmark.read_mesh(_case(tmp_path, json.dumps(bad).encode(), "gltf"))
    bad["buffers"][0]["uri"] = "https://example.com/a.bin"
    with pytest.raises(meshmark.MeshError, match="remote URI"):
        meshmark.read_mesh(_case(tmp_path, json.dumps(bad).encode(), "gltf"))
    bad["buffers"][0]["uri"] = "missing.bin"
    with pytest.raises(meshmark.MeshError, match="cannot read .*missing.bin"):
        meshmark.read_mesh(_case(tmp_path, json.dumps(bad).encode(), "gltf"))
    (tmp_path / "short.bin").write_bytes(blob[:10])
    bad["buffers"][0]["uri"] = "short.bin"
    with pytest.raises(meshmark.MeshError, match="has 10 bytes, byteLength says"):
        meshmark.read_mesh(_case(tmp_path, json.dumps(bad).encode(), "gltf"))


def test_node_cycle_and_nan(tmp_path):
    # a node graph that is its own child: positions are read from the meshes, never by walking nodes
    m = meshmark.read_mesh(_case(tmp_path, _edit(lambda d: d["nodes"][0].update(children=[0]))))
    assert m.n_vertices == 6
    doc, blob = _doc()
    blob = np.frombuffer(blob, np.uint8).copy()
    blob[12:16] = np.frombuffer(np.float32(np.nan).tobytes(), np.uint8)
    with pytest.raises(meshmark.MeshError, match=r"vertex 1 is not finite"):
        meshmark.read_mesh(_case(tmp_path, glb_bytes(doc, blob.tobytes())))


def test_cli_exit_2(tmp_path):
    from click.testing import CliRunner
    from meshmark.cli import main
    p = _case(tmp_path, GOOD[:100])
    r = CliRunner().invoke(main, ["info", str(p)])
    assert r.exit_code == 2 and r.stderr.startswith("meshmark: error:") and "header gives" in r.stderr
