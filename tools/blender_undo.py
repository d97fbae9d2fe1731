"""Undo and redo of the add-on's operators in a real Blender window (Debian's 3.4, under Xvfb):

    PYTHONPATH=src xvfb-run -a blender --factory-startup --python tools/blender_undo.py -- OUT.json

The bpy module has no window, so ``ed.undo`` never polls there; this script runs in the GUI binary.
It registers addon/meshmark_blender (as tools/blender_smoke.py does), builds the jittered arm, and,
once the window is up (a ``bpy.app.timers`` callback, with a window/area/region override for the
``ed.*`` operators):

1. pushes an undo step for the unmarked arm (V0);
2. ``meshmark.embed`` called as a panel button calls it (with an undo push) -> coordinates changed (V1);
3. a failing ``meshmark.embed`` (message too long) -> coordinates still V1, bit for bit;
4. ``ed.undo`` once -> V0 bit for bit: embed is a single undo step and the failure added none;
5. ``ed.redo`` -> V1 bit for bit; ``ed.undo`` -> V0 again;
6. Embed, then Verify (as its button runs it), then ``ed.undo`` once -> V0 bit for bit (Verify pushes no
   undo step); the Key field and each object's Keyfile field are the same after undo and redo (they
   are session state, not scene data), and two objects marked one after the other keep their own
   keyfiles (both verify).

It writes the results as JSON to OUT.json and exits with status 0 if every check held, else 1.
"""
import json
import os
import sys
import tempfile
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "blender_tests"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

OUT = sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else os.path.join(tempfile.gettempdir(), "undo.json")
RESULT = {"blender": bpy.app.version_string, "background": bpy.app.background, "steps": [], "ok": False}


def coords(name):
    me = bpy.data.objects[name].data  # looked up again after every undo: undo reloads the data
    co = np.empty(3 * len(me.vertices), np.float32)
    me.vertices.foreach_get("co", co)
    return co


def gui_context():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "WINDOW")
    return bpy.context.temp_override(window=win, area=area, region=region, screen=win.screen)


def step(name, **figures):
    RESULT["steps"].append({"step": name, **figures})
    print(f"meshmark undo: {name} {figures}", flush=True)


def finish(code):
    RESULT["ok"] = code == 0
    with open(OUT, "w") as f:
        json.dump(RESULT, f, indent=1)
    print(f"meshmark undo: {'OK' if code == 0 else 'FAILED'} -> {OUT}", flush=True)
    os._exit(code)  # leave at once with the status (wm.quit_blender returns 0 whatever happened)


def run():
    import meshmark_blender
    import rigs
    meshmark_blender.register()
    arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    rigs.select_only(arm)
    kf = os.path.join(tempfile.mkdtemp(), "k.json")
    with gui_context():
        bpy.ops.ed.undo_push(message="meshmark test: unmarked arm")
        V0 = coords("Arm")
        step("setup", n_vertices=int(V0.size // 3))
        # 'EXEC_DEFAULT', True: run it as a panel button does, with an undo push (a bpy.ops call from a
        # script pushes none by default: the calling script's own operator would)
        assert bpy.ops.meshmark.embed("EXEC_DEFAULT", True, method="laplacian", message="M", key="arm",
                                      keyfile=kf) == {"FINISHED"}
        V1 = coords("Arm")
        r = json.loads(bpy.context.scene.meshmark.last_result)
        step("embed", changed=int((V1 != V0).sum()), max_abs_change=float(np.abs(V1 - V0).max()),
             capacity=r["capacity"], stored_cdr=r["stored_cdr"])
        assert (V1 != V0).any()
        assert bpy.ops.ed.undo.poll(), "ed.undo does not poll in the window"
        try:
            bpy.ops.meshmark.embed("EXEC_DEFAULT", True, method="laplacian", message="M" * 40, key="arm", keyfile=kf,
                                   overwrite=True)  # consent given: the failure is the message's length
            raise AssertionError("a 40-byte message was accepted")
        except RuntimeError as exc:
            failed_error = str(exc).strip()
        V2 = coords("Arm")
        step("failing embed", error=failed_error[:120], identical_to_embedded=bool(np.array_equal(V2, V1)))
        assert np.array_equal(V2, V1)
        assert bpy.ops.ed.undo() == {"FINISHED"}
        V3 = coords("Arm")
        step("undo", identical_to_unmarked=bool(np.array_equal(V3, V0)), differs_from_marked=int((V3 != V1).sum()))
        assert np.array_equal(V3, V0), "one undo did not restore the unmarked arm"
        assert bpy.ops.ed.redo() == {"FINISHED"}
        V4 = coords("Arm")
        step("redo", identical_to_embedded=bool(np.array_equal(V4, V1)))
        assert np.array_equal(V4, V1), "redo did not restore the marked arm"
        assert bpy.ops.ed.undo() == {"FINISHED"}
        V5 = coords("Arm")
        step("undo again", identical_to_unmarked=bool(np.array_equal(V5, V0)))
        assert np.array_equal(V5, V0)
    rigs.select_only(bpy.data.objects["Arm"])  # after undo the add-on still verifies the restored mark
    with gui_context():
        bpy.ops.ed.redo()
    bpy.ops.meshmark.verify(keyfile=kf, evaluated=False)
    r = json.loads(bpy.context.scene.meshmark.last_result)
    step("verify after redo", detected=r["detected"], cdr=r["cdr"], message=r["message"])
    assert r["detected"] and r["cdr"] == 1.0 and r["message"] == "M"
    verify_then_undo()


def verify_then_undo():
    """Embed then Verify, one Ctrl+Z: the unmarked mesh; fields kept; two objects, two keyfiles."""
    import rigs
    folder = tempfile.mkdtemp()
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "undo.blend"))  # '//' is this folder
    def S():  # looked up again after every undo (undo reloads the scene)
        return bpy.context.scene.meshmark
    S().key, S().message = "undo-key", "U"
    a = rigs.mesh_object("HeroA", mesh=rigs.jittered_arm(5))
    b = rigs.mesh_object("HeroB", mesh=rigs.jittered_arm(6))
    with gui_context():
        bpy.ops.ed.undo_push(message="meshmark test: two unmarked heroes")
        rigs.select_only(bpy.data.objects["HeroA"])
        A0 = coords("HeroA")
        assert bpy.ops.meshmark.embed("EXEC_DEFAULT", True) == {"FINISHED"}
        rigs.select_only(bpy.data.objects["HeroB"])
        B0 = coords("HeroB")
        assert bpy.ops.meshmark.embed("EXEC_DEFAULT", True) == {"FINISHED"}
        B1 = coords("HeroB")
        assert bpy.ops.meshmark.verify("EXEC_DEFAULT", True) == {"FINISHED"}  # as its button runs it
        verified = json.loads(S().last_result)["detected"]
        fields = (S().key, S().keyfile)
        assert bpy.ops.ed.undo() == {"FINISHED"}  # once: the Verify added no step, this undoes B's Embed
        rigs.select_only(bpy.data.objects["HeroB"])
        after = (S().key, S().keyfile)
        B2 = coords("HeroB")
        step("embed, verify, undo once", verified=verified, identical_to_unmarked=bool(np.array_equal(B2, B0)),
             differs_from_marked=int((B2 != B1).sum()), fields_before=list(fields), fields_after_undo=list(after))
        assert np.array_equal(B2, B0), "one undo after Embed then Verify did not restore the unmarked mesh"
        assert after == fields == ("undo-key", "//HeroB.meshmark.json")
        assert bpy.ops.ed.redo() == {"FINISHED"}
        rigs.select_only(bpy.data.objects["HeroB"])
        assert np.array_equal(coords("HeroB"), B1) and (S().key, S().keyfile) == fields
    files = sorted(f for f in os.listdir(folder) if f.endswith(".meshmark.json"))
    got = {}
    for name in ("HeroA", "HeroB"):
        rigs.select_only(bpy.data.objects[name])
        assert S().keyfile == f"//{name}.meshmark.json"
        bpy.ops.meshmark.verify()
        r = json.loads(S().last_result)
        got[name] = (r["detected"], r["message"])
    step("two objects, two keyfiles", files=files, verified=got, a_marked=bool((coords("HeroA") != A0).any()))
    assert files == ["HeroA.meshmark.json", "HeroB.meshmark.json"] and got == {"HeroA": (True, "U"), "HeroB": (True, "U")}


def timer():
    try:
        run()
    except Exception as exc:
        traceback.print_exc()
        RESULT["error"] = f"{type(exc).__name__}: {exc}"
        finish(1)
    finish(0)


if bpy.app.background:
    RESULT["error"] = "needs the GUI (run without --background, e.g. under xvfb-run)"
    finish(1)
bpy.app.timers.register(timer, first_interval=1.0)
