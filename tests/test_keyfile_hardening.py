"""Keyfiles (issue 11): schema validation before use, the HMAC-SHA256 tag, key-less keyfiles
(--no-store-key), and embed writing OUT and the keyfile together or not at all."""
import hashlib
import json
import os
import subprocess
import sys

import pytest

import meshmark
import meshmark.watermark as W
from meshmark import MeshError
from meshmark.shapes import default_mesh
from meshmark.watermark.keyfile import KeyRequired, load_keyfile, save_keyfile, validate_keyfile_dict
from keyfile_fuzz import edit


@pytest.fixture(scope="module")
def marked():
    m = default_mesh()
    return m, W.embed(m, payload="h", key="owner-key")


@pytest.fixture
def saved(marked, tmp_path):
    path = tmp_path / "k.json"
    save_keyfile(marked[1].keyfile, path)
    return path, json.loads(path.read_text())


def _write(tmp_path, d, name="bad.json"):
    p = tmp_path / name
    p.write_text(json.dumps(d))
    return p




SCHEMA_CASES = [
    ("side_info.carriers", KeyError, r"side_info.carriers is missing"),
    ("side_info.carriers", {"a": 1}, r"side_info.carriers is not a list"),
    ("side_info.lo", "0.1", r"side_info.lo must be a number, got '0.1'"),
    ("params.K", KeyError, r"params.K is missing"),
    ("params.K", 1e12, r"params.K must be an integer, got 1000000000000.0"),
    ("params.K", 10**12, r"params.K must be in 4..1048576, got 1000000000000"),
    ("params.n_robust", -5, r"params.n_robust must be in 1..1000000000"),
    ("params.thesis_exact", "no", r"params.thesis_exact must be a bool, got 'no'"),
    ("side_info.carriers", ["1", "2"], r"side_info.carriers lists 2 carriers but coding.n_coded is"),
    ("mesh.n_vertices", -1, r"mesh.n_vertices must be in 0..2147483647, got -1"),
    ("coding.n_coded", "30", r"coding must have an integer n_coded"),
    ("coding.check_bits", 20, r"coding sizes are inconsistent with the payload \(info_bits must be 8, check_bits 0\)"),
    ("coding.scheme", "ldpc", r"coding scheme must be one of 'keyed-aes-ml-v1', 'tbcc9-r14-mac20', 'tbcc7-r13-mac20' or 'repeat'"),
    ("weld", 1, r"field 'weld' must be a bool, got 1"),
    ("tag", KeyError, r"field 'tag' is missing"),
    ("payload", [], r"field 'payload' must be a dict"),
]


@pytest.mark.parametrize("field,value,message", SCHEMA_CASES, ids=[f"{c[0]}={c[1]!r}"[:40] for c in SCHEMA_CASES])
def test_schema(saved, tmp_path, marked, field, value, message):
    path, d = saved
    bad = _write(tmp_path, edit(d, field, value))
    with pytest.raises(MeshError, match=message) as e:
        W.extract(marked[1].V, marked[0], keyfile=bad)
    assert "Traceback" not in str(e.value)


def test_carrier_values(saved, tmp_path):
    path, d = saved
    n = d["coding"]["n_coded"]
    for ids, msg in [(["x"] * n, r"carriers\[0\] must be an integer in 0..\d+, got 'x'"),
                     ([-1] + d["side_info"]["carriers"][1:], r"carriers\[0\] must be an integer in 0..\d+, got -1"),
                     ([d["side_info"]["carriers"][1]] * n, "lists a carrier twice"),
                     ([10**6] * n, r"got 1000000")]:
        with pytest.raises(MeshError, match=msg):
            load_keyfile(_write(tmp_path, edit(d, "side_info.carriers", ids)))


@pytest.mark.parametrize("text,message", [
    (b"\xff\xfe{}", r"is not UTF-8 text \(byte 0xff at offset 0\)"),
    (b"[" * 100000 + b"]" * 100000, r"nested too deeply|nested deeper than 8 levels"),
    (b'{"format": "meshmark-keyfile", "x": ' + b"[" * 50 + b"]" * 50 + b"}", r"nested deeper than 8 levels"),
    (b'{"a": NaN}', r"NaN is not allowed in a keyfile"),
    (b'{"a": 1e999}', r"the number 1e999 is out of range"),
    (b'{"a": -Infinity}', r"-Infinity is not allowed"),
    (b'{"a": ' + b"9" * 5000 + b"}", r"keyfile '.*'"),
    (b"7", r"not a JSON object"),
])
def test_hostile_json(tmp_path, text, message):
    p = tmp_path / "h.json"
    p.write_bytes(text)
    with pytest.raises(MeshError, match=message):
        load_keyfile(p)


def test_nan_lo_is_refused(saved, tmp_path):
    path, d = saved
    text = json.dumps(d).replace(f'"lo": {json.dumps(d["side_info"]["lo"])}', '"lo": NaN')
    assert "NaN" in text
    (tmp_path / "n.json").write_text(text)
    with pytest.raises(MeshError, match="NaN is not allowed"):
        load_keyfile(tmp_path / "n.json")


def test_tag_detects_changes(saved, tmp_path, marked):
    path, d = saved
    assert len(d["tag"]) == 64 and load_keyfile(path).key == "owner-key"
    # the attack the old unkeyed SHA-256 allowed: change the message and recompute the digest
    bits = "".join("1" if b == "0" else "0" for b in d["payload"]["bits"])
    forged = edit(edit(d, "payload.bits", bits), "payload.sha256", hashlib.sha256(bits.encode()).hexdigest())
    validate_keyfile_dict(forged)  # passes the schema ...
    with pytest.raises(MeshError, match=r"was changed after it was written: its HMAC-SHA256 tag does not match"):
        load_keyfile(_write(tmp_path, forged))  # ... but not the tag
    for field, value in [("params.n_robust", 6), ("side_info.hi", d["side_info"]["hi"] * 1.01), ("key", "other")]:
        with pytest.raises(MeshError, match="tag does not match"):
            load_keyfile(_write(tmp_path, edit(d, field, value)))
    # re-indented / reordered JSON is the same content: still valid
    (tmp_path / "re.json").write_text(json.dumps(dict(reversed(list(d.items())))))
    assert load_keyfile(tmp_path / "re.json").key == "owner-key"


def test_no_store_key(marked, tmp_path):
    m, _ = marked
    r = W.embed(m, payload="h", key="secret-Key-123", store_key=False)
    p = tmp_path / "nokey.json"
    save_keyfile(r.keyfile, p)
    raw = p.read_bytes()
    assert b"secret-Key-123" not in raw and json.loads(raw)["key_stored"] is False
    with pytest.raises(KeyRequired, match=r"written without the key \(--no-store-key\): give the key"):
        W.extract(r.V, m, keyfile=p)
    assert W.extract(r.V, m, keyfile=p, key="secret-Key-123").detected
    with pytest.raises(MeshError, match="the key is wrong, or the keyfile was changed"):
        W.extract(r.V, m, keyfile=p, key="guess")


def _cli(*args):
    r = subprocess.run([sys.executable, "-m", "meshmark.cli", *map(str, args)], capture_output=True, text=True,
                       stdin=subprocess.DEVNULL, timeout=120)
    assert "Traceback" not in r.stderr
    return r


def test_cli_writes_both_or_neither(tmp_path):
    src = tmp_path / "in.obj"
    meshmark.write_mesh(src, default_mesh())
    common = ["--message", "h", "--key", "k"]
    r = _cli("embed", src, tmp_path / "out.obj", *common, "--keyfile", tmp_path / "nodir" / "k.json")
    assert r.returncode == 2 and "cannot write the keyfile" in r.stderr and "does not exist" in r.stderr
    r = _cli("embed", src, tmp_path / "nodir" / "out.obj", *common, "--keyfile", tmp_path / "k.json")
    assert r.returncode == 2 and "cannot write the marked mesh" in r.stderr
    r = _cli("embed", src, tmp_path / "out.obj", *common, "--keyfile", tmp_path)
    assert r.returncode == 2
    r = _cli("embed", src, tmp_path / "out.xyz", *common, "--keyfile", tmp_path / "k.json")  # the mesh write fails
    assert r.returncode == 2 and "unsupported format '.xyz'" in r.stderr
    assert sorted(os.listdir(tmp_path)) == ["in.obj"]  # nothing written, no temporary left
    r = _cli("embed", src, tmp_path / "out.obj", *common[:2], "--key", "kk", "--keyfile", tmp_path / "k.json",
             "--no-store-key")
    assert r.returncode == 0 and sorted(os.listdir(tmp_path)) == ["in.obj", "k.json", "out.obj"]
    r = _cli("extract", tmp_path / "out.obj", "--keyfile", tmp_path / "k.json")
    assert r.returncode == 2 and "written without the key" in r.stderr
    assert _cli("extract", tmp_path / "out.obj", "--keyfile", tmp_path / "k.json", "--key", "kk").returncode == 0
    r = _cli("extract", tmp_path / "out.obj", "--keyfile", tmp_path / "k.json", "--key", "nope")
    assert r.returncode == 2 and "the key is wrong" in r.stderr


def test_untagged_keyfile_is_reported(tmp_path):
    from conftest import shared_mesh
    """Stripping the tag and writing version 2 (a downgrade) still reads, but the result says that the
    keyfile could not be checked for changes."""
    import json
    m = meshmark.read_mesh(shared_mesh("classic/bunny.obj"))
    r = meshmark.watermark.embed(m, payload="OK", key="k")
    p = tmp_path / "k.json"
    meshmark.watermark.save_keyfile(r.keyfile, p)
    d = json.loads(p.read_text())
    assert "tag" in d
    x = meshmark.watermark.extract(r.V, m, keyfile=p)
    assert x.detected and not any("integrity tag" in w for w in x.warnings)
    del d["tag"]
    d["version"] = 2
    q = tmp_path / "k2.json"
    q.write_text(json.dumps(d))
    y = meshmark.watermark.extract(r.V, m, keyfile=q)
    assert y.detected and any("no integrity tag" in w for w in y.warnings)
