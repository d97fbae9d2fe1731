"""The keyfile validation layer (issue 23, meshmark.watermark.keyfile_schema): each failure a hostile
user found (exit 3 or a wrong "not detected") is now exit 2 naming the field, through the real CLI."""
import json
import subprocess
import sys

import pytest

import meshmark
import meshmark.watermark as W
from conftest import shared_mesh
from keyfile_fuzz import edit, run_fork
from meshmark import MeshError
from meshmark.watermark.keyfile import load_keyfile, validate_keyfile_dict


@pytest.fixture(scope="module")
def marked(tmp_path_factory):
    """{method: (mesh path, tagged keyfile dict)} on the cow."""
    d = tmp_path_factory.mktemp("kf")
    mesh = meshmark.read_mesh(shared_mesh("classic/cow.obj"))
    out = {}
    for method in ("laplacian", "radial", "cho-mean", "cho-variance"):
        r = W.embed(mesh, payload="h", key="ownerA", method=method)
        p = d / f"{method}.obj"
        meshmark.write_mesh(p, r.V, mesh.F)
        out[method] = (p, json.loads(r.keyfile.to_json()))
    return out


def _untagged(d, version=2):
    d = {k: v for k, v in d.items() if k != "tag"}
    d["version"] = version
    if version == 1:
        d.pop("weld")
    return d


def _cli(tmp_path, mesh, kf, *extra):
    """(status, stderr) of ``meshmark extract`` in a forked child (tests/keyfile_fuzz.py; the
    mutation test checks that it answers as ``python -m meshmark`` does)."""
    p = tmp_path / "k.json"
    p.write_bytes(json.dumps(kf, indent=1).encode("utf-8", "surrogatepass") if isinstance(kf, dict) else kf)
    code, _, err = run_fork(["extract", str(mesh), "--keyfile", str(p), *extra])
    assert "Traceback" not in err and "internal error" not in err, err
    return code, err


def test_cli_subprocess_surrogate_key(marked, tmp_path):
    """The real command line: --key bytes that are not UTF-8 (b'ownerA\\xff')."""
    mesh, d = marked["laplacian"]
    p = tmp_path / "k.json"
    p.write_text(json.dumps(d))
    r = subprocess.run([sys.executable, "-m", "meshmark", "extract", str(mesh), "--keyfile", str(p), "--key",
                        b"ownerA\xff"], capture_output=True, stdin=subprocess.DEVNULL, timeout=120)
    assert r.returncode == 2 and b"--key: the key is not valid UTF-8: 'ownerA\\xff'" in r.stderr, r.stderr




def test_unmutated_keyfiles_detect(marked, tmp_path):
    for method, (mesh, d) in marked.items():
        for kf in (d, _untagged(d), _untagged(d, 1)):
            assert _cli(tmp_path, mesh, kf)[0] == 0, method


@pytest.mark.parametrize("tag", ["é" * 64, "0" * 63 + "é", "ü" + "a" * 63, "A" * 64, "0" * 63, 64])
def test_tag_not_ascii_hex(marked, tmp_path, tag):
    mesh, d = marked["laplacian"]
    code, err = _cli(tmp_path, mesh, {**d, "tag": tag})
    assert code == 2 and "field 'tag' must be" in err, err


def test_key_with_a_lone_surrogate_in_the_file(marked, tmp_path):
    mesh, d = marked["laplacian"]
    for kf in (_untagged({**d, "key": "ownerA\udcff"}), {**d, "key": "ownerA\udcff"}):
        code, err = _cli(tmp_path, mesh, kf)
        assert code == 2 and "field 'key' is not valid UTF-8" in err, err
    # anywhere else too, keys of objects included
    code, err = _cli(tmp_path, mesh, edit(d, "choice.mode", "\ud800"))
    assert code == 2 and "field 'choice.mode' is not valid UTF-8" in err
    code, err = _cli(tmp_path, mesh, {**d, "x\udcff": 1})
    assert code == 2 and "is not valid UTF-8" in err


@pytest.mark.parametrize("key", ["ownerA\udcff", "\udcff"])
def test_key_with_a_lone_surrogate_on_the_command_line(marked, tmp_path, key):
    mesh, d = marked["laplacian"]
    for kf in (d, _untagged(d)):
        code, err = _cli(tmp_path, mesh, kf, "--key", key)
        assert code == 2 and "--key: the key is not valid UTF-8" in err, err
    nokey = {k: v for k, v in _untagged(d, 3).items() if k != "key"}
    nokey["key_stored"] = False
    code, err = _cli(tmp_path, mesh, W.keyfile.sign_keyfile(nokey, "ownerA"), "--key", key)
    assert code == 2 and "--key: the key is not valid UTF-8" in err, err


@pytest.mark.parametrize("scheme", [{}, [], None, 3, ["keyed-aes-ml-v1"], "ldpc"])
def test_coding_scheme_not_a_known_string(marked, tmp_path, scheme):
    mesh, d = marked["laplacian"]
    for kf in (edit(d, "coding.scheme", scheme), _untagged(edit(d, "coding.scheme", scheme))):
        code, err = _cli(tmp_path, mesh, kf)
        assert code == 2 and "coding scheme must be one of" in err and "(coding.scheme)" in err, err


@pytest.mark.parametrize("field", ["params.thesis_exact", "side_info.lo", "side_info.hi", "params.eps", "params.K"])
@pytest.mark.parametrize("version", [1, 2])
def test_untagged_missing_laplacian_field(marked, tmp_path, field, version):
    mesh, d = marked["laplacian"]
    code, err = _cli(tmp_path, mesh, _untagged(edit(d, field, KeyError), version))
    assert code == 2 and f"{field} is missing" in err, err


@pytest.mark.parametrize("method,missing", [("radial", "params.origin_mode"), ("cho-mean", "params.alpha"),
                                            ("cho-variance", "params.alpha")])
def test_untagged_method_switched(marked, tmp_path, method, missing):
    """A laplacian keyfile relabelled as another method: its parameters are not that method's."""
    mesh, d = marked["laplacian"]
    code, err = _cli(tmp_path, mesh, _untagged({**d, "method": method}))
    assert code == 2 and "is not a field of a " + method in err, err
    # with the foreign parameters removed, the first one the method needs is named
    p = {"K": d["params"]["K"]}
    code, err = _cli(tmp_path, mesh, _untagged({**d, "method": method, "params": p}))
    assert code == 2 and (f"{missing} is missing" in err or "is missing (the" in err), err
    # a radial or cho keyfile relabelled as laplacian: no bin range
    mesh2, d2 = marked[method]
    code, err = _cli(tmp_path, mesh2, _untagged({**d2, "method": "laplacian"}))
    assert code == 2 and ("is not a field of a laplacian" in err or "is missing" in err), err


@pytest.mark.parametrize("lo_hi", ["swap", "equal", "close"])
def test_lo_above_hi_is_an_input_error(marked, tmp_path, lo_hi):
    mesh, d = marked["laplacian"]
    lo, hi = d["side_info"]["lo"], d["side_info"]["hi"]
    new = {"swap": (hi, lo), "equal": (hi, hi), "close": (hi * (1 - 1e-13), hi)}[lo_hi]
    kf = _untagged(edit(edit(d, "side_info.lo", new[0]), "side_info.hi", new[1]))
    code, err = _cli(tmp_path, mesh, kf)
    assert code == 2 and "side_info.lo" in err and "side_info.hi" in err, err


def test_carriers_beyond_the_methods_bins(marked, tmp_path):
    """Laplacian and radial carry one bit per bin pair ((K - 2) // 2 of them), Cho one per bin."""
    for method, (mesh, d) in marked.items():
        K = d["params"]["K"]
        high = K if method.startswith("cho") else (K - 2) // 2
        ids = d["side_info"]["carriers"]
        kf = _untagged(edit(d, "side_info.carriers", [high] + ids[1:]))
        code, err = _cli(tmp_path, mesh, kf)
        assert code == 2 and f"side_info.carriers[0] must be an integer in 0..{high - 1}, got {high}" in err, (method, err)


def test_method_rules(marked):
    _, d = marked["laplacian"]
    with pytest.raises(MeshError, match="params.thesis_exact is true but params.carrier is 'local'"):
        validate_keyfile_dict(edit(d, "params.thesis_exact", True))
    with pytest.raises(MeshError, match="params.carrier must be one of"):
        validate_keyfile_dict(edit(d, "params.carrier", "nope"))
    with pytest.raises(MeshError, match=r"params.bins is not a field of a laplacian keyfile's params"):
        validate_keyfile_dict(edit(d, "params.bins", 3))
    _, c = marked["cho-variance"]
    with pytest.raises(MeshError, match=r"params.alpha must be a finite number in \(0, 0.333333\)"):
        validate_keyfile_dict(edit(c, "params.alpha", 0.4))
    validate_keyfile_dict(edit(marked["cho-mean"][1], "params.alpha", 0.4))  # below 1/2: fine for cho-mean
    with pytest.raises(MeshError, match="params.thesis_exact is true but params.guard"):
        validate_keyfile_dict(edit(c, "params.thesis_exact", True))
    with pytest.raises(MeshError, match="payload.bits of a text payload must be whole bytes, got 7 bits"):
        bits = "1111111"
        import hashlib
        validate_keyfile_dict(edit(edit(edit(d, "payload.bits", bits), "payload.n_bits", 7), "payload.sha256",
                                    hashlib.sha256(bits.encode()).hexdigest()))


def test_keyfile_objects_are_validated_too(marked):
    """A Keyfile built or changed in the process goes through the same schema before extraction."""
    mesh = meshmark.read_mesh(shared_mesh("classic/cow.obj"))
    r = W.embed(mesh, payload="h", key="ownerA")
    kf = r.keyfile
    assert W.extract(r.V, mesh.F, keyfile=kf).detected
    kf.side_info = {**kf.side_info, "lo": kf.side_info["hi"] + 1}
    with pytest.raises(MeshError, match=r"side_info.lo \(.*\) must be below side_info.hi"):
        W.extract(r.V, mesh.F, keyfile=kf)
    with pytest.raises(MeshError, match="field 'key' is not valid UTF-8"):
        load_keyfile(W.keyfile.Keyfile(**{**{f: getattr(r.keyfile, f) for f in ("method", "params", "payload",
                     "coding", "side_info", "mesh")}, "key": "k\udcff"}))
