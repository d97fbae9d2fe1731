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
    # Blender's Python (Debian's 3.11) sees the meshmark package and pyarrow, which Run study needs;
    # the study runs in Blender's own interpreter (/usr/bin/python3.11 for Debian's build), no override
    pp = tmp_path / "pythonpath"
    pp.mkdir()
    os.symlink(os.path.dirname(meshmark.__file__), pp / "meshmark")
    import pyarrow
    os.symlink(os.path.dirname(pyarrow.__file__), pp / "pyarrow")
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "MESHMARK_PYTHON")}
    env.update(PYTHONPATH=str(pp), BLENDER_USER_SCRIPTS=str(tmp_path / "user"))
    out = tmp_path / "ui.json"
    shots = tmp_path / "shots"
    shots.mkdir()
    p = subprocess.run([xvfb, "-a", "-s", "-screen 0 1280x1024x24", blender, "--factory-startup",
                        "--enable-event-simulate", "--python", os.path.join(ROOT, "tools", "blender_ui.py"), "--",
                        zip_path, str(out), str(shots)], cwd=ROOT, env=env, capture_output=True, text=True,
                       timeout=900)
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

    # the tab opened (by clicks on it) at the default sidebar width; Watermark open, the rest closed
    opened = steps["open"]
    assert opened["region"][2] == 229 and r["tab_clicks"] < 80
    assert set(opened["panels"]) == {"Meshmark", "Watermark"}, set(opened["panels"])
    for s in steps.values():
        for name, d in s["panels"].items():
            assert d["count"] >= 1 and d["region_width"] == 229, (s["step"], name)
            assert d["truncated"] == [], (s["step"], name, d["truncated"])  # nothing wider than its place
    drawn = set().union(*(s["panels"] for s in steps.values()))
    assert drawn == {"Meshmark", "Watermark", "Trace copies", "Steganography", "Analysis", "Steganalysis", "Study"}
    labels = {k: [i[1] for i in d["items"]] for k, d in opened["panels"].items()}
    assert {"Method", "Message", "Key", "Automatic settings", "Embed", "Verify", "Check as posed"} <= set(labels["Watermark"])
    assert labels["Meshmark"].count("Keyfile") == 1

    # Embed, Verify and Capacity pressed in the sidebar (modal jobs): the panel's values, the result
    w = steps["watermark"]
    # automatic settings: the first rung's 82 carriers (carrier "local") for 'M' (42 needed with the
    # keyed check, docs/coding.md); Capacity reports the same choice
    assert (w["embed"], w["verify"], w["stored_cdr"], w["capacity"]) == (["RUNNING_MODAL"], ["RUNNING_MODAL"], 1.0, 82)
    assert (w["detected"], w["cdr"], w["message"], w["keyfile_written"], w["capacity_plan"]) == (True, 1.0, "M", True, 82)
    assert {"Mark found", "Bits matching 100%", "Message: M"} <= {i[1] for i in w["panels"]["Watermark"]["items"]}
    auto = [i[1] for i in steps["watermark_auto"]["panels"]["Watermark"]["items"]]
    assert "Embed will use:" in auto and "Bins 293" in auto  # ceil(20482 / 70), what Embed used
    adv = [i[1] for i in steps["watermark_advanced"]["panels"]["Watermark"]["items"]]
    assert {"Auto", "Custom", "Bins 293", "Min. pair size 46", "Lightness 5", "Solver", "Iterative",
            "Weld split vertices"} <= set(adv) and not any(t.startswith("Stability") for t in adv)
    # Embed into the existing keyfile asks, naming the file and the mark it holds; Esc changes nothing
    dlg = steps["embed_replace_dialog"]
    assert dlg["result"] == ["RUNNING_MODAL"] and r["replace_dialog_cancel_kept_mesh"] is True
    assert [t for k, t in dlg["dialog"]["items"]][:2] == ["'arm.json' holds the mark in Arm (message 'M').",
                                                          "Without it that mark can no longer be read:"]
    assert dlg["dialog"]["truncated"] == []
    # the frame check takes the frames of the armature's action
    study = steps["study"]
    assert study["result"] == ["RUNNING_MODAL"] and study["summary"]["detected_frames"] == study["summary"]["frames"] == 5
    assert study["frames_from"] == "the action 'RigAction'" and study["summary"]["max_disp_rel"] > 0.1
    study_texts = [i[1] for i in study["panels"]["Study"]["items"]]
    assert {"Found on 5/5 frames", "Frames 1 to 5"} <= set(study_texts)
    assert "from the action 'RigAction'" in " ".join(study_texts)  # wrapped to the sidebar's width

    # another selection: the arm's result is not shown for the camera
    cam = steps["camera_selected"]
    texts = [i[1] for d in cam["panels"].values() for i in d["items"]]
    assert cam["last_result_object"] == "Arm" and "Select a mesh object" in texts
    assert not any(t.startswith(("Mark found", "Found on", "Bits matching")) for t in texts)
    # one part of a two-part character: said, with the button that selects the rest
    one = [i[1] for i in steps["one_part_selected"]["panels"]["Meshmark"]["items"]]
    assert "1 of 2 parts selected" in one and "Select all 2 parts" in one
    assert steps["parts_selected"]["selected"] == ["Char_Legs", "Char_Torso"]

    # Trace copies: Issue (one copy per step) and Trace
    assert steps["issue"]["result"] == ["RUNNING_MODAL"] and steps["issue"]["copies"] == ["0001", "0002", "0003"]
    tr = steps["trace_copies"]
    assert tr["copy"] is None and tr["n_copies"] == 3  # the original is none of its copies
    tr_texts = [i[1] for i in tr["panels"]["Trace copies"]["items"]]
    assert {"Issue", "Trace", "3 copies compared"} <= set(tr_texts)
    assert "None of the issued copies" in " ".join(tr_texts)  # wrapped to the sidebar's width
    # Steganography: Hide asks on the watermarked arm (Esc: unchanged); hides and reveals in the stone
    st = steps["stego"]
    assert st["ask"] == ["RUNNING_MODAL"] and st["ask_kept_mesh"] is True
    assert (st["hide"], st["reveal"], st["read_back"], st["text"]) == (["RUNNING_MODAL"], ["RUNNING_MODAL"], True,
                                                                      "Hello from the sidebar")
    assert st["save"] == st["load"] == ["FINISHED"]
    assert {"Found 22 bytes", "Text: Hello from the"} <= {i[1] for i in st["panels"]["Steganography"]["items"]}
    # Analysis: the heat map, and the viewport shows it (Solid, coloured by attribute: VERTEX in 3.4)
    an = steps["analysis"]
    assert an["result"] == ["RUNNING_MODAL"] and an["active_color"] == "Meshmark precision"
    assert an["shading"] == ["SOLID", "VERTEX"]
    assert f"Bits needed: {an['level_min']} to {an['level_max']}" in [i[1] for i in an["panels"]["Analysis"]["items"]]
    # Steganalysis: three states, in words
    det = steps["steganalysis"]
    assert det["result"] == ["RUNNING_MODAL"] and det["state"] in ("marked", "clean") and 0 <= det["probability"] <= 1
    words = {"marked": "Something is probably hidden", "clean": "No sign of hidden data"}[det["state"]]
    assert words in [i[1] for i in det["panels"]["Steganalysis"]["items"]]
    tiny = steps["steganalysis_cannot_judge"]
    assert (tiny["state"], tiny["why"]) == ("cannot_judge", "too_small")
    assert "Cannot judge this mesh" in " ".join(i[1] for i in tiny["panels"]["Steganalysis"]["items"])  # wrapped
    # Run study: Blender's own Python, progress while it runs, every task done; Esc stops it
    run = steps["study_running"]
    assert run["result"] == ["RUNNING_MODAL"] and run["running"] is True and run["python"] == "/usr/bin/python3.11"
    assert "Esc stops the study" in [i[1] for i in run["panels"]["Study"]["items"]]
    done = steps["study_spec"]["last_result"]
    assert done["ok"] and done["operator"] == "meshmark.study" and done["summary"]["ok"] == done["planned"] == 12
    assert any(i[1] == "12 of 12 tasks ran" for i in steps["study_spec"]["panels"]["Study"]["items"])
    stop = steps["study_stopped"]  # Esc, pressed in the window, stopped the study's process
    assert stop["running"] is False and stop["returncode"] is not None
    assert 0 <= stop["done"] < stop["todo"] == 1200
    assert stop["last_result"]["ok"] is False and stop["last_result"]["error"].startswith("Study stopped at")

    # a cube: the user's words, in the report and in the panel, and no file browser first
    cube = steps["cube_error"]
    assert cube["error"].startswith("mesh too small to carry a mark") and "Laplacian" not in cube["error"]
    assert "Error: meshmark: mesh too small to carry a mark" in cube["result"]["RuntimeError"]
    assert cube["browser_open"] is False
    texts = [i[1] for i in cube["panels"]["Watermark"]["items"]]
    box = texts[texts.index("Check as posed") + 1:texts.index("Advanced")]  # the result box, wrapped
    assert " ".join(box) == cube["error"] and len(box) > 1

    # the Embed file browser (the .blend not saved yet): the operator's side panel is a summary, no fields
    fb = steps["embed_file_browser"]
    assert fb["result"] == ["RUNNING_MODAL"] and fb["browser_open"] is True
    assert fb["operator_panel"]["items"] == [["label", "Arm"], ["label", "Laplacian"], ["label", "1-byte message"],
                                             ["label", "Key: set"]]
    assert fb["operator_panel"]["truncated"] == []
    assert all(os.path.getsize(os.path.join(SHOTS, f"blender34_{n}.png")) > 10_000 for n in steps)

    # after Hide, Reveal and Save: neither the .blend nor the autosave holds the text, its hex or the key
    sec = r["secrets"]
    assert len(sec["files"]) == 2, sec  # the .blend and Blender's own autosave
    assert all(found == [] for found in sec["found"].values()), sec["found"]
    assert sec["message_saved"] is True and sec["session_text_kept"] is True  # the search sees saved names
