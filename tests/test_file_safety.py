"""Files on disk (issue 23): keyfiles private (0600) whatever the umask, nothing overwritten without
--force (exit 2 before any work), a marked mesh never at its path without its keyfile even after
SIGKILL, and no temporary left by SIGINT/SIGTERM or after the next run."""
import os
import pathlib
import signal
import stat
import subprocess
import sys

import pytest

import meshmark
from meshmark import MeshError, atomic
from meshmark.shapes import torus

sys.path.insert(0, str(pathlib.Path(__file__).parent))
import kill_embed  # noqa: E402  (the SIGKILL loop, also run by bench/kill_embed.py)
from kill_embed import PY, run, temps  # noqa: E402


def mode(p) -> int:
    return stat.S_IMODE(os.stat(p).st_mode)


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    d = tmp_path_factory.mktemp("small")
    p = d / "t.ply"
    meshmark.write_mesh(p, torus(140, 100))
    return p


# --- private files ------------------------------------------------------------------------------

@pytest.mark.parametrize("umask", [0o022, 0o000])
def test_embed_keyfile_is_0600_under_any_umask(small, tmp_path, umask):
    r = run(["embed", small, tmp_path / "o.ply", "--keyfile", tmp_path / "k.json", "--key", "a", "--message", "m"],
            umask=umask)
    assert r.returncode == 0, r.stderr
    assert mode(tmp_path / "k.json") == 0o600
    assert mode(tmp_path / "o.ply") == 0o666 & ~umask  # the mesh keeps the usual mode
    assert temps(tmp_path) == []


def test_create_private_and_save_keyfile_ignore_the_umask(tmp_path):
    old = os.umask(0o000)
    try:
        fd = atomic.create_private(tmp_path / "r.db")
        os.close(fd)
        assert mode(tmp_path / "r.db") == 0o600
        with pytest.raises(FileExistsError):  # never replaces a file
            atomic.create_private(tmp_path / "r.db")
        os.umask(0o277)  # would give 0400
        os.close(atomic.create_private(tmp_path / "s.db"))
        assert mode(tmp_path / "s.db") == 0o600
        os.umask(0o000)
        from meshmark.watermark import embed, save_keyfile
        res = embed(torus(140, 100), payload="m", key="k")
        save_keyfile(res.keyfile, tmp_path / "k.json")
        assert mode(tmp_path / "k.json") == 0o600
        (tmp_path / "old.json").write_text("{}")
        os.chmod(tmp_path / "old.json", 0o644)
        save_keyfile(res.keyfile, tmp_path / "old.json", overwrite=True)  # a replaced keyfile is private too
        assert mode(tmp_path / "old.json") == 0o600
        atomic.write_text(tmp_path / "plain.txt", "x")
        assert mode(tmp_path / "plain.txt") == 0o666
    finally:
        os.umask(old)


def test_temporaries_are_private_from_creation(tmp_path):
    seen = []
    old = os.umask(0o000)
    try:
        atomic.write_all([(tmp_path / "k.json", lambda t: seen.append(mode(t)) or atomic.text_writer("{}")(t))],
                         private=[True])
    finally:
        os.umask(old)
    assert seen == [0o600] and mode(tmp_path / "k.json") == 0o600


# --- nothing overwritten without --force ------------------------------------------------------------

def _stego_mesh(tmp_path, small):
    out = tmp_path / "s.ply"
    r = run(["stego", "embed", small, out, "--message", "first", "--key", "k"])
    assert r.returncode == 0, r.stderr
    return out


def _refused(r, path):
    assert r.returncode == 2, (r.returncode, r.stderr)
    assert str(path) in r.stderr and "--force" in r.stderr and "internal error" not in r.stderr, r.stderr


def test_embed_refuses_an_existing_mesh_or_keyfile(small, tmp_path):
    out, kf = tmp_path / "o.ply", tmp_path / "k.json"
    out.write_bytes(b"precious")
    r = run(["embed", small, out, "--keyfile", kf, "--key", "a", "--message", "m"])
    _refused(r, out)
    assert out.read_bytes() == b"precious" and not kf.exists()
    out.unlink()
    kf.write_bytes(b"{}")
    _refused(run(["embed", small, out, "--keyfile", kf, "--key", "a", "--message", "m"]), kf)
    assert not out.exists() and kf.read_bytes() == b"{}"
    r = run(["embed", small, kf, "--keyfile", kf, "--key", "a", "--message", "m", "--force"])
    assert r.returncode == 2 and "same file" in r.stderr
    out.write_bytes(b"precious")
    r = run(["embed", small, out, "--keyfile", kf, "--key", "a", "--message", "m", "--force"])
    assert r.returncode == 0, r.stderr
    r = run(["extract", out, "--keyfile", kf])
    assert r.returncode == 0, r.stdout + r.stderr


def test_stego_refuses_to_destroy_a_hidden_message(small, tmp_path):
    out = _stego_mesh(tmp_path, small)
    before = out.read_bytes()
    _refused(run(["stego", "embed", small, out, "--message", "second", "--key", "k"]), out)
    assert out.read_bytes() == before
    r = run(["stego", "extract", out, "--key", "k"])
    assert r.returncode == 0 and r.stdout.strip() == "first"
    msg = tmp_path / "m.txt"
    msg.write_bytes(b"keep")
    _refused(run(["stego", "extract", out, "--key", "k", "--out-file", msg]), msg)
    assert msg.read_bytes() == b"keep"
    r = run(["stego", "extract", out, "--key", "k", "--out-file", msg, "--force"])
    assert r.returncode == 0 and msg.read_bytes() == b"first"
    r = run(["stego", "embed", small, out, "--message", "second", "--key", "k", "--force"])
    assert r.returncode == 0, r.stderr
    assert temps(tmp_path) == []


def test_stego_into_a_missing_folder_is_exit_2(small, tmp_path):
    out = _stego_mesh(tmp_path, small)
    for args in (["stego", "embed", small, tmp_path / "no" / "s.ply", "--message", "x", "--key", "k"],
                 ["stego", "extract", out, "--key", "k", "--out-file", tmp_path / "no" / "m.bin"]):
        r = run(args)
        assert r.returncode == 2 and "does not exist" in r.stderr, (args, r.returncode, r.stderr)


def test_attack_train_evaluate_plot_issue_refuse_existing_outputs(small, tmp_path):
    out = tmp_path / "a.ply"
    out.write_bytes(b"x")
    _refused(run(["attack", small, out, "--type", "noise", "--strength", "0.001"]), out)
    assert out.read_bytes() == b"x"
    assert run(["attack", small, out, "--type", "noise", "--strength", "0.001", "--force"]).returncode == 0
    model = tmp_path / "m.npz"
    model.write_bytes(b"x")
    r = run(["steganalysis", "train", small, "--out", model])
    _refused(r, model)
    csv = tmp_path / "e.csv"
    csv.write_bytes(b"x")
    _refused(run(["steganalysis", "evaluate", small, "--csv", csv]), csv)
    plots = tmp_path / "res" / "plots"
    plots.mkdir(parents=True)
    (plots / "summary.csv").write_text("x")
    _refused(run(["study", "plot", tmp_path / "res"]), plots)
    copies = tmp_path / "copies"
    copies.mkdir()
    (copies / "t-0001.ply").write_bytes(b"x")
    r = run(["issue", small, copies, "--copies", "1", "--key", "k", "--registry", tmp_path / "r.db"])
    assert r.returncode == 2 and "--force" in r.stderr, r.stderr
    assert (copies / "t-0001.ply").read_bytes() == b"x"


def test_api_defaults_refuse_too(tmp_path):
    from meshmark.stego.cli import write_verified
    p = tmp_path / "x.ply"
    p.write_bytes(b"x")
    m = torus()
    with pytest.raises(MeshError, match="--force"):
        write_verified(str(p), m, m.V, "float64", lambda back: True)
    with pytest.raises(MeshError, match="already exists"):
        atomic.write_all([(p, lambda t: None)], overwrite=False)
    assert p.read_bytes() == b"x"


# --- stale temporaries, signals ------------------------------------------------------------------

def test_clean_stale_removes_only_dead_processes_temporaries(tmp_path):
    dead = subprocess.run([PY, "-c", "import os; print(os.getpid())"], capture_output=True, text=True).stdout.strip()
    names = [f".meshmark-tmp-{dead}-0123abcd-o.ply", f"..meshmark-tmp-{dead}-0123abcd-o.ply.meshmark-tmp-{dead}.ply",
             f".k.json.meshmark-tmp-{dead}-89abcdef.json"]
    live = [f".meshmark-tmp-{os.getpid()}-0123abcd-o.ply", f".meshmark-tmp-1-0123abcd-o.ply"]  # us, init
    for n in names + live + [".meshmark-notes", "meshmark-tmp-5-0123abcd"]:
        (tmp_path / n).write_bytes(b"k")
    (tmp_path / f".meshmark-tmp-{dead}-fedcba98-d").mkdir()
    removed = atomic.clean_stale(tmp_path, force=True)
    assert sorted(removed) == sorted(names + [f".meshmark-tmp-{dead}-fedcba98-d"])
    assert sorted(os.listdir(tmp_path)) == sorted(live + [".meshmark-notes", "meshmark-tmp-5-0123abcd"])


_HOLD = """
import os, sys, time
from meshmark import atomic
with atomic.Staged([sys.argv[1], sys.argv[2]], private=[True, False]) as st:
    atomic.text_writer('{"key": "secret"}')(st.temps[0])
    with atomic.temp_folder(sys.argv[2]) as d:
        print(len(os.listdir(os.path.dirname(sys.argv[1]))), flush=True)
        time.sleep(60)
"""


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_sigint_sigterm_remove_temporaries(tmp_path, sig):
    p = subprocess.Popen([PY, "-c", _HOLD, str(tmp_path / "k.json"), str(tmp_path / "o.ply")],
                         stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "3"  # two temporary files and a temporary folder
    p.send_signal(sig)
    assert p.wait(timeout=30) == -sig  # ended by the signal: 130 / 143 in a shell
    assert os.listdir(tmp_path) == []


def test_sigkill_never_leaves_a_new_mesh_without_its_keyfile(small, tmp_path):
    src = tmp_path / "in.ply"
    meshmark.write_mesh(src, torus(200, 150))  # 30,000 vertices: a run takes about a second here
    seen, full = kill_embed.kill_run(src, tmp_path / "o.ply", tmp_path / "k.json", ["a", "b"], n_kills=40, seed=1,
                          full_every=8)
    assert seen["full runs clean"] == 5
    assert seen["new"] + seen["old mesh + new keyfile"] >= 1, seen  # some kills did land in the write phase
    r = run(["extract", tmp_path / "o.ply", "--keyfile", tmp_path / "k.json"])
    assert r.returncode == 0 and "DETECTED" in r.stdout


_KILL_AT_RENAME = """
import os, signal, sys
when, n, sig = sys.argv[1], int(sys.argv[2]), getattr(signal, sys.argv[3])
real, count = os.replace, [0]
def replace(a, b):
    count[0] += 1
    if when == "before" and count[0] == n:
        os.kill(os.getpid(), sig)
    real(a, b)
    if when == "after" and count[0] == n:
        os.kill(os.getpid(), sig)
os.replace = replace
from meshmark.cli import main
main(sys.argv[4:])
"""


@pytest.mark.parametrize("when,n,expect,sig", [("before", 1, "old", "SIGKILL"),
                                               ("after", 1, "old mesh + new keyfile", "SIGKILL"),
                                               ("after", 2, "new", "SIGKILL"),
                                               ("before", 1, "old", "SIGTERM"),
                                               ("after", 1, "old mesh + new keyfile", "SIGINT")])
def test_signal_at_each_rename(small, tmp_path, when, n, expect, sig):
    """The signal lands exactly before the first rename, between the two, or after the second: the
    keyfile is always renamed first (a random kill rarely hits the gap between the renames); SIGTERM
    and SIGINT remove the temporaries themselves and end the process by the signal."""
    out, kf = tmp_path / "o.ply", tmp_path / "k.json"
    assert run(["embed", small, out, "--keyfile", kf, "--key", "a", "--message", "m"]).returncode == 0
    old_mesh = out.read_bytes()
    args = ["embed", str(small), str(out), "--keyfile", str(kf), "--key", "b", "--message", "m", "--force"]
    p = subprocess.run([PY, "-c", _KILL_AT_RENAME, when, str(n), sig] + args, capture_output=True)
    assert p.returncode == -getattr(signal, sig), p.stderr
    key = kill_embed._keyfile_key(kf)
    got = {("old", "a"): "old", ("new", "b"): "new", ("old", "b"): "old mesh + new keyfile"}.get(
        ("old" if out.read_bytes() == old_mesh else "new", key), f"new mesh beside the keyfile of {key!r}")
    assert got == expect
    if sig != "SIGKILL":
        assert temps(tmp_path) == []  # removed by the signal handler
        return
    assert temps(tmp_path) != [] or expect == "new"
    assert run(args).returncode == 0 and temps(tmp_path) == []  # the next run removes what the kill left
