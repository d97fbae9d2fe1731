"""The add-on examples (examples/blender_*.py, one per operator) run in background Blender (the bpy
module), each in its own process as a user runs them, chained as a user would: embed saves a .blend
that verify and the deformation study open."""
import json
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def _run(script, *args):
    p = subprocess.run([sys.executable, os.path.join(ROOT, "examples", script), *map(str, args)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300)
    out = p.stdout + p.stderr
    assert p.returncode == 0, out[-3000:]
    lines = [l for l in out.splitlines() if l.startswith("meshmark example: ")]
    return json.loads(lines[-1].split(": ", 1)[1]), out


def test_capacity_example():
    # the thesis parameters' 24 carriers hold no letter with the keyed check (42 needed) ...
    r, out = _run("blender_capacity.py", "--params", "thesis")
    assert (r["operator"], r["n_vertices"], r["capacity"], r["max_text_bytes"]) == ("meshmark.capacity", 20482, 24, 0)
    assert r["params"]["K"] == 293  # ceil(20482 / 70)
    # ... the automatic choice (what Embed uses, by default) takes the 8-byte message 'meshmark': 64 data
    # bits need 126 carriers (docs/coding.md), the first rung that offers as many has 164, and the
    # longest text over the ladder is the 31-byte cap
    r, out = _run("blender_capacity.py")
    assert (r["capacity"], r["max_text_bytes"], r["params_mode"]) == (164, 31, "auto") and r["capacity"] >= 126
    r, _ = _run("blender_capacity.py", "--method", "radial")
    assert r["method"] == "radial" and r["capacity"] > 24


def test_embed_verify_and_study_examples(tmp_path):
    kf, blend = tmp_path / "k.json", tmp_path / "marked.blend"
    r, out = _run("blender_embed.py", "--keyfile", kf, "--out", blend, "--message", "M")
    assert (r["operator"], r["capacity"], r["stored_cdr"]) == ("meshmark.embed", 82, 1.0)  # automatic: 42 needed; the first rung offers 82 (carrier "local")
    assert kf.is_file() and blend.is_file() and "Marked 'Mesh' with 'M'" in out
    assert "example-key" not in blend.read_bytes().decode("latin-1")  # the key is in the keyfile, not the .blend
    r, out = _run("blender_verify.py", "--blend", blend, "--keyfile", kf)
    assert (r["operator"], r["detected"], r["cdr"], r["message"]) == ("meshmark.verify", True, 1.0, "M")
    r, out = _run("blender_deformation_study.py", "--blend", blend, "--keyfile", kf, "--out", tmp_path)
    s = r["summary"]
    assert (s["frames"], s["detected_frames"], s["message_frames"]) == (10, 10, 10)
    assert s["max_disp_rel"] > 0.05  # it did bend
    assert os.path.isfile(r["csv"]) and "mark found on 10/10 frames" in out
