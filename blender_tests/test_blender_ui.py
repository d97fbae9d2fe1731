"""The panel in a real window: Debian's Blender 3.4 under Xvfb, with the legacy add-on zip installed
by Blender's own add-on installer (tools/blender_ui.py drives it; see its docstring).

Asserts that the Meshmark tab opens and its panels are drawn by the UI, that the fields exist, that
Embed and Verify pressed in the sidebar's context take the panel's values and their results appear
(for the object they describe only), that errors read as the user's words, that the Embed file
browser's side panel repeats no field, and that no text is wider than its place at the default
sidebar width (``blf.dimensions`` in the UI font against the region width). The screenshots, cropped
to the sidebar, go to build/screenshots/ (a CI artifact).

Needs Debian's ``blender`` and ``xvfb-run`` (tools/bootstrap.sh installs them): a missing binary is a
failure, not a skip. Blender 5.0 (the bpy module, no window) is covered by test_addon_ui.py: the same
recording layout measures the same draw() code with its blf.
"""
import json
import os
import shutil
import subprocess
import sys

import meshmark

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BLENDER = "/usr/bin/blender"
SHOTS = os.path.join(ROOT, "build", "screenshots")


def _binaries():
    xvfb = shutil.which("xvfb-run") or "xvfb-run"
    missing = [p for p in (BLENDER, xvfb) if not os.path.isfile(p)]
    assert not missing, f"missing {', '.join(missing)}: install the Debian packages blender, xvfb and xauth (tools/bootstrap.sh)"
    return BLENDER, xvfb


def _crop(step, out):
    from PIL import Image
    x, y, w, h = step["region"]
    W, H = step["window"]
    Image.open(step["screenshot"]).crop((x, H - (y + h), x + w, H - y)).save(out)


def test_panel_in_a_blender_34_window(tmp_path):
    blender, xvfb = _binaries()
    sys.path.insert(0, os.path.join(ROOT, "addon"))
    import build_extension
    zip_path = build_extension.legacy_zip(str(tmp_path))
    pp = tmp_path / "pythonpath"  # Blender's Python sees only the meshmark package
    pp.mkdir()
    os.symlink(os.path.dirname(meshmark.__file__), pp / "meshmark")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV")}
    env.update(PYTHONPATH=str(pp), BLENDER_USER_SCRIPTS=str(tmp_path / "user"),
               MESHMARK_PYTHON=sys.executable)  # the study runs in this Python (pyarrow)
    out = tmp_path / "ui.json"
    shots = tmp_path / "shots"
    shots.mkdir()
    p = subprocess.run([xvfb, "-a", "-s", "-screen 0 1280x1024x24", blender, "--factory-startup",
                        "--enable-event-simulate", "--python", os.path.join(ROOT, "tools", "blender_ui.py"), "--",
                        zip_path, str(out), str(shots)], cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=600)
    log = (p.stdout + p.stderr)[-4000:]
    assert out.is_file(), f"exit {p.returncode}, no result written:\n{log}"
    r = json.loads(out.read_text())
    assert p.returncode == 0 and r["ok"], (r.get("error"), log)
    assert r["blender"] == "3.4.1" and r["background"] is False
    assert r["addon_file"].startswith(str(tmp_path / "user")), r["addon_file"]  # the installed zip, not the repo
    steps = {s["step"]: s for s in r["steps"]}

    os.makedirs(SHOTS, exist_ok=True)
    for name, s in steps.items():
        _crop(s, os.path.join(SHOTS, f"blender34_{name}.png"))

    # the tab opened (by clicks on it) at the default sidebar width, and the UI drew every panel
    opened = steps["open"]
    assert opened["region"][2] == 229 and r["tab_clicks"] < 80
    assert {"Meshmark", "Watermark", "Trace copies", "Steganography"} <= set(opened["panels"])
    for s in steps.values():
        for name, d in s["panels"].items():
            assert d["count"] >= 1 and d["region_width"] == 229, (s["step"], name)
            assert d["truncated"] == [], (s["step"], name, d["truncated"])  # nothing wider than its place
    labels = {k: [i[1] for i in d["items"]] for k, d in opened["panels"].items()}
    # Settings: Auto: the panel says how much text the automatic choice takes (docs/coding.md)
    assert {"Method", "Message", "Key", "Automatic settings", "Embed", "Verify", "Check as posed"} <= set(labels["Watermark"])
    assert {"Issue", "Trace"} <= set(labels["Trace copies"])
    assert labels["Meshmark"].count("Keyfile") == 1 and {"Start 1", "Run study"} <= set(labels["Study"])

    # Embed and Verify pressed in the sidebar: the panel's values, the result in the panel
    w = steps["watermark"]
    # automatic settings: the first rung's 82 carriers (carrier "local") for 'M' (42 needed with the
    # keyed check, docs/coding.md)
    assert (w["embed"], w["verify"], w["stored_cdr"], w["capacity"]) == (["FINISHED"], ["FINISHED"], 1.0, 82)
    assert (w["detected"], w["cdr"], w["message"], w["keyfile_written"]) == (True, 1.0, "M", True)
    assert {"Mark found", "Bits matching 100.0%", "Message: M"} <= {i[1] for i in w["panels"]["Watermark"]["items"]}

    adv = [i[1] for i in steps["watermark_advanced"]["panels"]["Watermark"]["items"]]
    assert {"Auto", "Custom", "Bins 0", "Min. pair size 46", "Subtlety 5", "Solver", "Iterative",
            "Weld split vertices"} <= set(adv)
    study = steps["study"]
    assert study["result"] == ["FINISHED"] and study["summary"]["detected_frames"] == 5
    assert study["summary"]["max_disp_rel"] > 0.1  # the arm did bend
    assert "Found on 5/5 frames" in [i[1] for i in study["panels"]["Study"]["items"]]

    # the new sub-panels, each pressed through the UI context, each with its screenshot
    tr = steps["trace_copies"]
    assert set(tr["panels"]) == {"Meshmark", "Trace copies"}
    assert {"Issue", "Trace"} <= {i[1] for i in tr["panels"]["Trace copies"]["items"]}
    st = steps["stego"]
    assert (st["hide"], st["reveal"], st["read_back"], st["text"]) == (["FINISHED"], ["FINISHED"], True,
                                                                      "Hello from the sidebar")
    assert set(st["panels"]) == {"Meshmark", "Steganography"}
    assert {"Found 22 bytes", "Text: Hello from the"} <= {i[1] for i in st["panels"]["Steganography"]["items"]}
    an = steps["analysis"]
    assert an["result"] == ["FINISHED"] and an["active_color"] == "Meshmark precision"
    assert f"Bits needed: {an['level_min']} to {an['level_max']}" in [i[1] for i in an["panels"]["Analysis"]["items"]]
    det = steps["steganalysis"]
    assert det["result"] == ["FINISHED"] and 0.0 <= det["probability"] <= 1.0
    assert any(i[1].startswith("Hidden data: ") for i in det["panels"]["Steganalysis"]["items"])
    run = steps["study_running"]
    assert run["result"] == ["RUNNING_MODAL"] and run["running"] is True  # the UI went on drawing
    assert "Esc stops the study" in [i[1] for i in run["panels"]["Study"]["items"]]
    done = steps["study_spec"]["last_result"]
    assert done["ok"] and done["operator"] == "meshmark.study" and done["summary"]["ok"] == done["planned"] == 12
    assert any(i[1] == "12 of 12 tasks ok" for i in steps["study_spec"]["panels"]["Study"]["items"])
    stop = steps["study_stopped"]  # Esc, pressed in the window, stopped the study's process
    assert stop["running"] is False and stop["returncode"] is not None
    assert 0 <= stop["done"] < stop["todo"] == 1200
    assert stop["last_result"]["ok"] is False and stop["last_result"]["error"].startswith("stopped after")

    # another selection: the arm's result is not shown for the camera
    cam = steps["camera_selected"]
    texts = [i[1] for d in cam["panels"].values() for i in d["items"]]
    assert cam["last_result_object"] == "Arm" and "Select a mesh object" in texts
    assert not any(t.startswith(("Mark found", "Found on", "Bits matching")) for t in texts)

    # a cube: the user's words, in the report and in the panel
    cube = steps["cube_error"]
    assert cube["error"].startswith("mesh too small to carry a mark") and "Laplacian" not in cube["error"]
    assert "Error: meshmark: mesh too small to carry a mark" in cube["result"]["RuntimeError"]
    texts = [i[1] for i in cube["panels"]["Watermark"]["items"]]
    box = texts[texts.index("Check as posed") + 1:texts.index("Advanced")]  # the result box, wrapped
    assert " ".join(box) == cube["error"] and len(box) > 1

    # the Embed file browser: the operator's side panel is a summary, no fields
    fb = steps["embed_file_browser"]
    assert fb["result"] == ["RUNNING_MODAL"] and fb["browser_open"] is True
    assert fb["operator_panel"]["items"] == [["label", "Arm"], ["label", "Laplacian"], ["label", "1-byte message"],
                                             ["label", "Key: set"]]
    assert fb["operator_panel"]["truncated"] == []
    assert all(os.path.getsize(os.path.join(SHOTS, f"blender34_{n}.png")) > 10_000 for n in steps)
