"""The add-on in Debian's Blender binary (3.4, a legacy add-on): the smoke subset in the background
binary, and real undo/redo in a window under Xvfb (the bpy module has no window: ed.undo never
polls there). Each runs the binary in a subprocess and asserts on what it prints or writes.

Both need Debian's ``blender`` and ``xvfb-run`` (tools/bootstrap.sh installs them): a missing binary
is a failure, not a skip. meshmark is handed to Blender's own Python (Debian's 3.11 with its numpy)
through a directory that holds nothing but a link to the meshmark package this test imports.
"""
import json
import os
import shutil
import subprocess

import pytest

import meshmark

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLENDER = "/usr/bin/blender"


def _binaries():
    missing = [p for p in (BLENDER, shutil.which("xvfb-run") or "xvfb-run") if not os.path.isfile(p)]
    assert not missing, f"missing {', '.join(missing)}: install the Debian packages blender, xvfb and xauth (tools/bootstrap.sh)"
    return BLENDER, shutil.which("xvfb-run")


@pytest.fixture(scope="module")
def env(tmp_path_factory):
    """The environment for Blender's Python: PYTHONPATH with only the meshmark package on it."""
    d = tmp_path_factory.mktemp("pythonpath")
    os.symlink(os.path.dirname(meshmark.__file__), d / "meshmark")
    e = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    e["PYTHONPATH"] = str(d)
    return e


def _run(cmd, env, timeout=600):
    p = subprocess.run(cmd, cwd=ROOT, env=env, capture_output=True, text=True, timeout=timeout)
    return p.returncode, p.stdout + p.stderr


def test_smoke_in_debian_blender_background(env):
    blender, _ = _binaries()
    rc, out = _run([blender, "--background", "--factory-startup", "--python-exit-code", "1",
                    "--python", os.path.join(ROOT, "tools", "blender_smoke.py")], env)
    lines = [l for l in out.splitlines() if l.startswith("meshmark smoke:")]
    assert rc == 0 and lines[-1] == "meshmark smoke: OK", out[-3000:]
    assert lines[0] == "meshmark smoke: Blender 3.4.1"
    text = "\n".join(lines)
    for deg in (0, 30, 60):
        assert f"bend {deg:2d} deg  NC 1.000  CDR 1.000  message 'M'" in text
    assert "'detected_frames': 5" in text
    assert "error reported as expected: Error: meshmark: message too long: 40 bytes" in text
    # the Fox carries one bit (32 carriers at K=100, n_thr=1): a letter needs 42 with the keyed check
    assert "Fox 1728 vertices welded to 290, 32 carriers" in text
    assert "Fox at rest  CDR 1.000  message '1'  welded 1438 copies" in text


def test_embed_is_one_undo_step_in_a_window(env, tmp_path):
    blender, xvfb = _binaries()
    out_json = tmp_path / "undo.json"
    rc, out = _run([xvfb, "-a", blender, "--factory-startup", "--python", os.path.join(ROOT, "tools", "blender_undo.py"),
                    "--", str(out_json)], env)
    assert out_json.is_file(), f"exit {rc}, no result written:\n{out[-3000:]}"
    r = json.loads(out_json.read_text())
    assert rc == 0 and r["ok"], (rc, r, out[-3000:])
    assert r["blender"] == "3.4.1" and r["background"] is False
    steps = {s["step"]: s for s in r["steps"]}
    assert steps["setup"]["n_vertices"] == 20482
    # embed changed nearly every coordinate of the arm (61,440 of 3 x 20,482 with the iterative
    # reconstruction; all 61,446 with solver='direct') and stored a readable mark
    # (automatic parameters: the first rung's 82 carriers with the carrier "local" for 'M', which needs 42 with the keyed check)
    assert 61000 <= steps["embed"]["changed"] <= 61446 and steps["embed"]["capacity"] == 82 and steps["embed"]["stored_cdr"] == 1.0
    assert "at most 31 bytes fit" in steps["failing embed"]["error"]
    assert steps["failing embed"]["identical_to_embedded"] is True  # a failure leaves the mesh bit-identical
    assert steps["undo"]["identical_to_unmarked"] is True  # one undo: embed is one step, the failure none
    assert steps["redo"]["identical_to_embedded"] is True
    assert steps["undo again"]["identical_to_unmarked"] is True
    assert (steps["verify after redo"]["detected"], steps["verify after redo"]["cdr"]) == (True, 1.0)
    # Embed then Verify, one Ctrl+Z: the unmarked mesh bit for bit (Verify pushes no undo step); the
    # Key and Keyfile fields are the same after undo and redo; two objects marked one after the other
    # have two keyfiles, and both verify
    u = steps["embed, verify, undo once"]
    assert u["verified"] is True and u["identical_to_unmarked"] is True and u["differs_from_marked"] > 60000
    assert u["fields_before"] == u["fields_after_undo"] == ["undo-key", "//HeroB.meshmark.json"]
    two = steps["two objects, two keyfiles"]
    assert two["files"] == ["HeroA.meshmark.json", "HeroB.meshmark.json"]
    assert two["verified"] == {"HeroA": [True, "U"], "HeroB": [True, "U"]}
