"""The command line reads well: every command's one-line summary is a phrase (not "Ch."), `python -m
meshmark` is the program, shell completion answers, and a binary stego message never goes to a
terminal (issue 26, "small CLI gaps")."""
import os
import pathlib
import pty
import subprocess
import sys

import click
import numpy as np

import meshmark
from meshmark.cli import main as cli

sys.path.insert(0, str(pathlib.Path(__file__).parent))
from conftest import shared_mesh  # noqa: E402


def _commands(group: click.Group, prefix: str = ""):
    for name, cmd in group.commands.items():
        yield f"{prefix}{name}", cmd
        if isinstance(cmd, click.Group):
            yield from _commands(cmd, f"{prefix}{name} ")


def test_every_command_summary_is_a_phrase():
    """click cuts the summary at the first '. ': a docstring opening with 'Ch. 3:' showed as 'Ch.'."""
    names = dict(_commands(cli))
    assert {"analyze degradation", "analyze quantize", "stego extract", "trace"} <= set(names)
    for name, cmd in names.items():
        short = cmd.get_short_help_str(limit=300)
        words = short.rstrip(".").split()
        assert len(words) >= 3, f"{name}: summary {short!r}"
        assert not short.lower().startswith(("ch.", "eq.", "§")), f"{name}: summary {short!r}"


def test_python_dash_m_is_the_program():
    r = subprocess.run([sys.executable, "-m", "meshmark", "--version"], capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and meshmark.__version__ in r.stdout


def test_shell_completion_answers_commands_and_options():
    env = dict(os.environ, _MESHMARK_COMPLETE="bash_complete", COMP_WORDS="meshmark ana", COMP_CWORD="1")
    r = subprocess.run([sys.executable, "-m", "meshmark"], env=env, capture_output=True, text=True, timeout=60)
    assert r.returncode == 0 and "plain,analyze" in r.stdout.splitlines(), r.stdout
    env.update(COMP_WORDS="meshmark stego extract --out", COMP_CWORD="3")
    r = subprocess.run([sys.executable, "-m", "meshmark"], env=env, capture_output=True, text=True, timeout=60)
    assert "plain,--out-file" in r.stdout.splitlines(), r.stdout


def _run_on_terminal(args):
    """Run the CLI with stdout on a pseudo-terminal; (exit code, bytes on the terminal, stderr)."""
    master, slave = pty.openpty()
    p = subprocess.run([sys.executable, "-m", "meshmark", *args], stdout=slave, stderr=subprocess.PIPE, timeout=300)
    os.close(slave)
    out = b""
    try:
        while chunk := os.read(master, 65536):
            out += chunk
    except OSError:  # EIO once the terminal's other side is closed and drained
        pass
    os.close(master)
    return p.returncode, out, p.stderr.decode()


def test_binary_stego_message_is_not_printed_to_a_terminal(tmp_path):
    payload = bytes(np.random.default_rng(3).integers(0, 256, 600, dtype=np.uint8))
    assert b"\xff" in payload or b"\xfe" in payload  # not UTF-8
    (tmp_path / "m.bin").write_bytes(payload)
    marked = tmp_path / "s.ply"
    r = subprocess.run([sys.executable, "-m", "meshmark", "stego", "embed", shared_mesh("classic/cow.obj"),
                        str(marked), "--message-file", str(tmp_path / "m.bin"), "--key", "k"],
                       capture_output=True, timeout=300)
    assert r.returncode == 0, r.stderr
    code, shown, err = _run_on_terminal(["stego", "extract", str(marked), "--key", "k"])
    assert code == 0 and shown == b"" and "600 bytes" in err and "--out-file" in err
    piped = subprocess.run([sys.executable, "-m", "meshmark", "stego", "extract", str(marked), "--key", "k"],
                           capture_output=True, timeout=300)
    assert piped.returncode == 0 and piped.stdout == payload
    code, shown, _ = _run_on_terminal(["stego", "extract", str(marked), "--key", "wrong"])
    assert code == 1 and b"no message" in shown
