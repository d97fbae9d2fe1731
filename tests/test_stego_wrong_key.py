"""Issue 23: a wrong key answers a stego mesh exactly as it answers a clean one (docs/stego.md §5,
"What an observer learns without the key"). The 100 + 100 measurement with timings is
bench/stego_wrong_key.py."""
import numpy as np
import pytest
from click.testing import CliRunner

import meshmark
from meshmark import shapes, stego
from meshmark.cli import main as cli
from meshmark.stego import crypto, lsb
from meshmark.stego.cli import write_verified

from conftest import shared_mesh

RIGHT, WRONG = "the right key", "not the key"
SHARED = ["classic/spot.obj", "classic/suzanne.obj", "classic/fandisk.obj", "corpus/libigl_bumpy.off",
          "corpus/vhacd_eight.off", "corpus/libigl_decimated-knight.off", "corpus/libigl_halftunnel.off",
          "corpus/c3d_woody.obj"]
EXT = {"fixed32": ".obj", "float32": ".ply"}


def _bases():
    """8 shared meshes and 12 generated ones (noisy tori and cylinders, seeded)."""
    rng = np.random.default_rng(23)
    out = [meshmark.read_mesh(shared_mesh(p)) for p in SHARED]
    for i in range(12):
        m = (shapes.torus(int(rng.integers(24, 60)), int(rng.integers(12, 30))) if i % 2 else
             shapes.cylinder(int(rng.integers(16, 48)), int(rng.integers(16, 60))))
        out.append(m.with_vertices(m.V + rng.normal(scale=0.002, size=m.V.shape)))
    return out


@pytest.mark.parametrize("precision", ["fixed32", "float32"])
def test_wrong_key_same_answer_for_stego_and_clean(tmp_path, precision):
    """20 stego and 20 clean files per precision through `stego extract` with a wrong key: one
    message, one exit code; the right key still finds every message."""
    runner = CliRunner()
    answers = {}
    for j, m in enumerate(_bases()):
        msg = f"message {j}".encode()
        res = stego.embed(m, msg, RIGHT, precision=precision)
        sp, cp = tmp_path / f"s{j}{EXT[precision]}", tmp_path / f"c{j}{EXT[precision]}"
        write_verified(str(sp), m, res.V, precision,
                       lambda back: stego.extract(back, RIGHT, precision=precision).message == msg)
        meshmark.write_mesh(str(cp), m, binary=True, float32=precision == "float32", precision=17)
        for kind, p in (("stego", sp), ("clean", cp)):
            r = runner.invoke(cli, ["stego", "extract", str(p), "--key", WRONG, "--precision", precision])
            answers.setdefault((r.exit_code, r.output.replace(str(p), "FILE").strip()), []).append(kind)
        if j % 5 == 0:  # the right key on the file (the CLI answer), a few per precision
            r = runner.invoke(cli, ["stego", "extract", str(sp), "--key", RIGHT, "--precision", precision])
            assert r.exit_code == 0 and r.output.strip() == msg.decode()
    assert list(answers) == [(1, "FILE: no message (no message for this key)")], answers
    kinds = next(iter(answers.values()))
    assert kinds.count("stego") == 20 and kinds.count("clean") == 20


def test_every_failure_takes_the_same_steps(bunny, monkeypatch):
    """A stego mesh, a clean mesh that is not made of carrier words, and a clean float32 one: the same
    reason, one scrypt derivation and one header check each (the work the timing depends on)."""
    res = stego.embed(bunny, b"hidden", RIGHT, tolerance=1.0)
    calls = []
    derive, check = crypto.derive, crypto.open_header_with
    monkeypatch.setattr(crypto, "derive", lambda *a: calls.append("derive") or derive(*a))
    monkeypatch.setattr(crypto, "open_header_with", lambda *a: calls.append("header") or check(*a))
    f32 = bunny.with_vertices(bunny.V.astype(np.float32).astype(np.float64))
    for m, prec in ((bunny.with_vertices(res.V), "fixed32"), (bunny, "fixed32"), (f32, "float32"), (bunny, "float64")):
        calls.clear()
        r = stego.extract(m, WRONG, tolerance=1.0, precision=prec)
        assert (r.found, r.message, r.reason) == (False, None, stego.NO_MESSAGE)
        assert calls == ["derive", "header"]
    calls.clear()
    assert stego.extract(bunny.with_vertices(res.V), RIGHT, tolerance=1.0).message == b"hidden"
    assert calls == ["derive", "header"]


def test_lsb_stream_is_encrypted(bunny):
    """The corrective vector's stream is salt | AES-CTR(length | deflate(e)): read without the key, its
    length field is not a length that fits (it was the plain length before)."""
    import struct
    res = stego.embed(bunny, b"hidden", RIGHT, tolerance=1.0)
    marked = bunny.with_vertices(res.V)
    fr, V = lsb._frame(res.V, "fixed32")
    t2, order2, first2, _ = lsb._marked_order(V, marked, lsb.level_function(1.0), "fixed32", fr)
    slots = int(meshmark._core.stego_lsb_capacity(V, "fixed32", *fr, order2, first2))
    raw = meshmark._core.stego_read_lsb(V, "fixed32", *fr, order2, first2, 8 * (crypto.SALT + 4))
    (plain_len,) = struct.unpack(">I", raw[crypto.SALT:])
    assert plain_len != res.e_stream_bytes - crypto.SALT - 4  # a reader without the key sees no length
    dkey = crypto.derive(RIGHT, raw[:crypto.SALT])
    (ln,) = struct.unpack(">I", crypto.mask(dkey, raw[crypto.SALT:]))
    assert ln == res.e_stream_bytes - crypto.SALT - 4 and 8 * res.e_stream_bytes <= slots
    t, reason, _ = lsb._read_e(V, marked, lsb.level_function(1.0), "fixed32", fr, RIGHT)
    assert reason == "" and np.array_equal(t, res.t)
    assert lsb._read_e(V, marked, lsb.level_function(1.0), "fixed32", fr, WRONG)[1] == "no corrective vector"


def test_too_small_is_a_property_of_the_file():
    """A mesh with fewer LSB slots than the stream's salt and length: the one other answer, the same
    with any key (no embedding can write there)."""
    m = meshmark.Mesh(np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1.0]]),
                      np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]))
    with pytest.raises(meshmark.MeshError):
        stego.embed(m, b"x", RIGHT)
    for k in (RIGHT, WRONG):
        assert stego.extract(m, k).reason == stego.TOO_SMALL
