"""README's commands work as written: the command-line session and the Python example are run in a
folder that holds the shared Bunny as `bunny.obj` (and the Knight as `hero.glb`), and every command's exit status is checked (0
unless its comment says `exit N`). ./demo.sh and ./test.sh are run by CI itself."""
import os
import pathlib
import re
import shutil
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from conftest import shared_mesh  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def _blocks(lang: str) -> list:
    return re.findall(rf"^```{lang}\n(.*?)^```$", README, flags=re.S | re.M)


def _session() -> list:
    """The CLI session: the bash block that defines `mm=`, as (command, expected exit) pairs."""
    block = next(b for b in _blocks("bash") if re.search(r"^mm=", b, re.M))
    cmds = []
    for line in block.splitlines():
        if not line.startswith("$mm "):
            continue
        cmd, _, comment = line.partition("  #")
        codes = re.findall(r"\bexit (\d)\b", comment)
        assert len(codes) <= 1, f"README: one exit status per command: {line}"
        cmds.append((cmd.strip(), int(codes[0]) if codes else 0))
    return cmds


def test_the_session_covers_the_commands():
    names = {c.split()[1] for c, _ in _session()}
    assert {"info", "capacity", "embed", "extract", "attack", "compare", "steganalysis", "issue", "trace"} <= names


def test_cli_session(tmp_path):
    """Every `$mm` line of the session, in order, in one folder (later commands read earlier outputs)."""
    shutil.copy(shared_mesh("classic/bunny.obj"), tmp_path / "bunny.obj")
    shutil.copy(shared_mesh("rigged/Knight.glb"), tmp_path / "hero.glb")
    env = {**os.environ, "mm": str(pathlib.Path(sys.executable).with_name("meshmark"))}
    for cmd, want in _session():
        r = subprocess.run(["bash", "-c", cmd], cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
        assert r.returncode == want, (f"README: `{cmd}` exited {r.returncode}, the README says {want}:\n"
                                      f"{r.stdout[-2000:]}{r.stderr[-2000:]}")
        assert "internal error" not in r.stderr, r.stderr
        if cmd.split()[1] == "trace":
            assert re.search(r"bunny-(\d+)\.obj", cmd).group(1) in r.stdout, r.stdout


def test_python_example(tmp_path):
    code = next(b for b in _blocks("python") if "read_mesh" in b)
    shutil.copy(shared_mesh("classic/bunny.obj"), tmp_path / "bunny.obj")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "detected=True" in r.stdout and "message='ACME'" in r.stdout, r.stdout
