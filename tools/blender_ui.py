"""The add-on's panel in a real Blender window (Debian's 3.4 under Xvfb), driven as a user would:

    BLENDER_USER_SCRIPTS=/tmp/u PYTHONPATH=<dir with meshmark> xvfb-run -a -s "-screen 0 1280x1024x24" \\
        blender --factory-startup --enable-event-simulate --python tools/blender_ui.py -- ADDON.zip OUT.json SHOTS/

1. installs the legacy add-on zip (``addon/build_extension.py --legacy``) with Blender's own
   ``preferences.addon_install`` and enables it (``addon_utils``), checking that the package runs
   from the user scripts folder, not from the repository;
2. builds a rigged, animated arm (blender_tests/rigs.py) beside the default camera;
3. opens the sidebar and clicks its "Meshmark" tab (``Window.event_simulate``), until the panel's
   draw runs in the UI region;
4. sets the fields through the panel's own properties (``scene.meshmark``), presses Embed and
   Verify (``INVOKE_DEFAULT`` in the context of the sidebar region, as a click does), opens the
   Advanced fold, runs the study, selects the camera, presses Embed on a cube, and opens the Embed
   file browser; after each step it waits for the UI to redraw, records what every sub-panel drew
   (blender_tests/ui_layout.py: texts, the width each needs by ``blf.dimensions`` and the width its
   slot gets in the region) and takes a screenshot of the window (``screen.screenshot``).

It writes OUT.json (the region's geometry per screenshot, the drawn texts, truncated texts, results)
and exits 0 if the run went through, 1 on an exception. The test (blender_tests/test_blender_ui.py)
asserts on the JSON and crops the screenshots to the sidebar.
"""
import json
import math
import os
import sys
import tempfile
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "blender_tests"))  # rigs, ui_layout (NOT addon/: it is installed)

import bpy  # noqa: E402

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ZIP, OUT, SHOTS = args if len(args) == 3 else (None, os.path.join(tempfile.gettempdir(), "ui.json"), tempfile.mkdtemp())
RESULT = {"blender": bpy.app.version_string, "background": bpy.app.background, "steps": [], "ok": False}
TMP = tempfile.mkdtemp()
bpy.context.preferences.view.show_splash = False


def finish(code):
    RESULT["ok"] = code == 0
    with open(OUT, "w") as f:
        json.dump(RESULT, f, indent=1)
    print(f"meshmark ui: {'OK' if code == 0 else 'FAILED'} -> {OUT}", flush=True)
    os._exit(code)


def ui():
    win = bpy.context.window_manager.windows[0]
    area = next(a for a in win.screen.areas if a.type == "VIEW_3D")
    region = next(r for r in area.regions if r.type == "UI")
    return win, area, region


def ui_override():
    win, area, region = ui()
    return bpy.context.temp_override(window=win, area=area, region=region, screen=win.screen)


# -- recording the panels' draws ------------------------------------------------------------------------
DRAWN = {}  # panel bl_label -> {"count", "items", "truncated", "width"}
SHOW = {"only": None}  # a sub-panel's label: only it is shown (its screenshot), None: all


def record_draws(panels_mod, ui_layout):
    """Wrap every registered panel class's draw: forward to the real layout, record the texts (the
    panels are registered again: Blender keeps the draw function it was given at registration)."""
    panels_mod.unregister()
    def wrapper(cls, orig):
        def draw(self, context):
            rec = ui_layout.draw_recorded(type("P", (), {"draw": staticmethod(orig)}), context, self.layout, self)
            width = context.region.width - ui_layout.SIDEBAR_MARGIN * ui_layout.scale()
            items = ui_layout.measure(rec, width)
            d = DRAWN.setdefault(cls.bl_label, {"count": 0})
            d.update(count=d["count"] + 1, width=width, region_width=context.region.width,
                     items=[(i.kind, i.text, round(i.need, 1), round(i.slot, 1)) for i in items],
                     truncated=ui_layout.truncated(items))
        return draw

    def poll(cls, context):  # one sub-panel at a time for its screenshot (the sidebar is not tall enough)
        return SHOW["only"] is None or cls.bl_label == SHOW["only"]

    for cls in [panels_mod.MESHMARK_PT_sidebar, *panels_mod.SUBPANELS]:
        cls.draw = wrapper(cls, cls.draw)
        if cls is not panels_mod.MESHMARK_PT_sidebar:
            cls.poll = classmethod(poll)
    panels_mod.register()


def snapshot(name, window=None, **extra):
    """Screenshot of the main window (cropped later to the sidebar), or of ``window`` (whole)."""
    win, area, region = ui()
    path = os.path.join(SHOTS, f"{name}.png")
    if window is not None:
        win, area = window, window.screen.areas[0]
        rect = [0, 0, win.width, win.height]
    else:
        rect = [region.x, region.y, region.width, region.height]
    with bpy.context.temp_override(window=win, area=area, screen=win.screen):
        bpy.ops.screen.screenshot(filepath=path)
    step = {"step": name, "screenshot": path, "window": [win.width, win.height], "region": rect,
            "panels": json.loads(json.dumps(DRAWN)), **extra}
    RESULT["steps"].append(step)
    print(f"meshmark ui: {name} {extra}", flush=True)
    DRAWN.clear()


# -- the run, one step per timer tick (the UI redraws between ticks) -------------------------------------
def redraw():
    win, area, region = ui()
    for a in win.screen.areas:
        a.tag_redraw()


def steps():
    """A generator: each yield gives the UI a few redraws before the next step."""
    import rigs
    sys.path[:] = [p for p in sys.path if p != os.path.join(ROOT, "addon")]  # rigs put it there: the add-on
    # must come from the installed zip (the user scripts folder), not from the repository
    # scene (built first): the default camera and light, no cube; the rigged arm, animated over 5 frames
    bpy.data.objects.remove(bpy.data.objects["Cube"], do_unlink=True)
    bpy.context.view_layer.update()
    arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    skel = rigs.chain_armature("Rig", [(0, 0, 0), (0, 0, 1), (0, 0, 2)])
    rigs.rig_auto(arm, skel)  # before the add-on is enabled (3.4 crashed in bone heat with it enabled)
    pb = skel.pose.bones["b1"]
    pb.rotation_mode = "XYZ"
    for f, deg in ((1, 0), (5, 30)):
        pb.rotation_euler = (math.radians(deg), 0, 0)
        pb.keyframe_insert("rotation_euler", frame=f)
    import addon_utils
    assert bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True) == {"FINISHED"}
    addon_utils.enable("meshmark_blender", default_set=True, handle_error=None)
    import meshmark_blender
    from meshmark_blender import panels
    import ui_layout
    RESULT["addon_file"] = meshmark_blender.__file__
    RESULT["user_scripts"] = bpy.utils.user_resource("SCRIPTS")
    record_draws(panels, ui_layout)
    s = bpy.context.scene.meshmark

    bpy.context.scene.frame_set(1)
    rigs.select_only(arm)
    win, area, region = ui()
    area.spaces[0].show_region_ui = True
    yield

    # open the Meshmark tab: click down the tab column until the panel draws
    win, area, region = ui()
    for i in range(80):
        if "Meshmark" in DRAWN:
            break
        x, y = region.x + region.width - 8, region.y + region.height - 12 - 8 * i
        win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
        DRAWN.clear()
        yield
    RESULT["tab_clicks"] = i
    # park the mouse over the viewport, away from the sidebar (no hover highlight in the shots)
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=region.x - 300, y=region.y + 300)
    redraw()
    yield
    snapshot("open", region_ui_width=region.width)

    # the fields, through the panel's properties; Embed and Verify as the buttons call them
    s.method, s.message, s.key, s.keyfile = "laplacian", "M", "arm", os.path.join(TMP, "arm.json")
    with ui_override():
        r_embed = bpy.ops.meshmark.embed("INVOKE_DEFAULT", True)
        embed = json.loads(s.last_result)
        r_verify = bpy.ops.meshmark.verify("INVOKE_DEFAULT", True)
        verify = json.loads(s.last_result)
    redraw()
    yield
    snapshot("watermark", embed=sorted(r_embed), verify=sorted(r_verify), stored_cdr=embed.get("stored_cdr"),
             capacity=embed.get("capacity"), detected=verify.get("detected"), cdr=verify.get("cdr"),
             message=verify.get("message"), keyfile_written=os.path.isfile(s.keyfile))

    s.show_advanced, s.param_mode = True, "CUSTOM"
    redraw()
    yield
    snapshot("watermark_advanced")
    s.show_advanced = False

    s.frame_start, s.frame_end, s.frame_step, s.output_dir = 1, 5, 1, TMP
    with ui_override():
        r_study = bpy.ops.meshmark.deformation_study("INVOKE_DEFAULT", True)
        study = json.loads(s.last_result)
    redraw()
    yield
    snapshot("study", result=sorted(r_study), summary=study.get("summary"))

    # the selection changes: the arm's result is not shown for the camera
    rigs.select_only(bpy.data.objects["Camera"])
    redraw()
    yield
    snapshot("camera_selected", last_result_object=json.loads(s.last_result).get("object"))

    # the new sub-panels, one at a time: Steganography (Hide, Reveal), Analysis (the heat map),
    # Steganalysis (Check), Study (a spec run in the background: the modal operator's progress)
    rigs.select_only(arm)
    SHOW["only"] = "Trace copies"  # its own screenshot (Issue / Trace are pressed in the bpy tests)
    redraw()
    yield
    snapshot("trace_copies")

    SHOW["only"] = "Steganography"
    s.stego_source, s.stego_text = "TEXT", "Hello from the sidebar"
    with ui_override():
        r_hide = bpy.ops.meshmark.stego_embed("INVOKE_DEFAULT", True)
        hide = json.loads(s.last_result)
        r_reveal = bpy.ops.meshmark.stego_extract("INVOKE_DEFAULT", True)
        reveal = json.loads(s.last_result)
    redraw()
    yield
    snapshot("stego", hide=sorted(r_hide), reveal=sorted(r_reveal), read_back=hide.get("read_back"),
             text=reveal.get("text"))

    SHOW["only"] = "Analysis"
    with ui_override():
        r_an = bpy.ops.meshmark.analyze("INVOKE_DEFAULT", True)
        an = json.loads(s.last_result)
    area.spaces[0].shading.type = "SOLID"
    sh = area.spaces[0].shading  # "Attribute" colouring: VERTEX in 3.4, ATTRIBUTE in 4+
    sh.color_type = "ATTRIBUTE" if "ATTRIBUTE" in {e.identifier for e in sh.bl_rna.properties["color_type"].enum_items} else "VERTEX"
    redraw()
    yield
    snapshot("analysis", result=sorted(r_an), level_min=an.get("level_min"), level_max=an.get("level_max"),
             active_color=arm.data.color_attributes.active_color.name)
    win, area, region = ui()
    main = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=win, area=area, region=main, screen=win.screen):
        bpy.ops.view3d.view_selected()  # frame the arm so that its heat map fills the view
    redraw()
    yield
    snapshot("analysis_viewport", window=win)

    SHOW["only"] = "Steganalysis"
    with ui_override():
        r_det = bpy.ops.meshmark.steganalysis_detect("INVOKE_DEFAULT", True)
        det = json.loads(s.last_result)
    redraw()
    yield
    snapshot("steganalysis", result=sorted(r_det), probability=det.get("probability"))

    SHOW["only"] = "Study"
    spec = os.path.join(TMP, "study.toml")
    with open(spec, "w") as f:
        f.write(rigs.study_spec(rigs.shared_mesh("classic/fandisk.obj"), seeds=(0, 1, 2), attacks=STUDY_NOISE, name="ui"))
    s.study_spec, s.study_out = spec, os.path.join(TMP, "study_out")
    from meshmark_blender import study_ops
    with ui_override():
        r_run = bpy.ops.meshmark.study("INVOKE_DEFAULT", True)
    redraw()
    yield
    running = study_ops.STATE["running"] is not None
    snapshot("study_running", result=sorted(r_run), running=running, progress=s.study_progress)
    for _ in range(400):  # the UI keeps drawing while the study runs
        if study_ops.STATE["running"] is None:
            break
        redraw()
        yield
    redraw()
    yield
    done = json.loads(s.last_result)
    snapshot("study_spec", last_result=done)

    # Esc stops a running study: a long spec, Esc pressed through the window's event queue
    with open(spec, "w") as f:
        f.write(rigs.study_spec(rigs.shared_mesh("classic/bunny.obj"), seeds=range(300), attacks=STUDY_NOISE, name="ui"))
    s.study_out = os.path.join(TMP, "study_out_stopped")
    with ui_override():
        bpy.ops.meshmark.study("INVOKE_DEFAULT", True)
    stopped = study_ops.STATE["running"]
    for _ in range(200):  # until the process has planned its tasks
        redraw()
        yield
        if stopped is None or stopped.todo > 0:
            break
    win, area, region = ui()
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    for _ in range(20):
        redraw()
        yield
        if study_ops.STATE["running"] is None:
            break
    res = json.loads(s.last_result)
    snapshot("study_stopped", last_result=res, running=study_ops.STATE["running"] is not None,
             returncode=None if stopped is None else stopped.proc.returncode,
             done=None if stopped is None else stopped.done, todo=None if stopped is None else stopped.todo)
    SHOW["only"] = None

    # a cube: Embed reports in the user's words, in the panel and the report
    bpy.ops.mesh.primitive_cube_add(location=(3, 0, 0))
    cube = bpy.context.active_object
    rigs.select_only(cube)
    with ui_override():
        try:
            r = bpy.ops.meshmark.embed("INVOKE_DEFAULT", True)
        except RuntimeError as exc:  # an ERROR report raises when called from Python
            r = {"RuntimeError": str(exc).strip()}
        err = json.loads(s.last_result)
    redraw()
    yield
    snapshot("cube_error", result=r, error=err.get("error"))

    # the Embed file browser (no keyfile yet): its side panel is the operator's draw
    rigs.select_only(bpy.data.objects["Arm"])
    s.keyfile = ""
    op_drawn = {}
    cls = bpy.types.MESHMARK_OT_embed
    orig = cls.draw

    def op_draw(self, context):
        rec = ui_layout.draw_recorded(type("P", (), {"draw": staticmethod(orig)}), context, self.layout, self)
        items = ui_layout.measure(rec, context.region.width - 2 * ui_layout.BOX_PAD * ui_layout.scale())
        op_drawn.update(items=[(i.kind, i.text) for i in items], truncated=ui_layout.truncated(items),
                        region_width=context.region.width)
    bpy.utils.unregister_class(cls)
    cls.draw = op_draw
    bpy.utils.register_class(cls)
    with ui_override():
        r_browse = bpy.ops.meshmark.embed("INVOKE_DEFAULT", True)
    redraw()
    for _ in range(3):
        yield
    browser = bpy.context.window_manager.windows[-1]
    snapshot("embed_file_browser", window=browser, result=sorted(r_browse), operator_panel=dict(op_drawn),
             browser_open=any(a.type == "FILE_BROWSER" for w in bpy.context.window_manager.windows
                              for a in w.screen.areas))
    win = bpy.context.window_manager.windows[-1]
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    yield


STUDY_NOISE = ['name = "noise"\ngrid = { strength = [0.001, 0.002, 0.003] }']  # with "none": 4 settings


def main():
    gen = steps()

    def tick():
        try:
            next(gen)
            return 0.3
        except StopIteration:
            finish(0)
        except Exception as exc:
            traceback.print_exc()
            RESULT["error"] = f"{type(exc).__name__}: {exc}"
            finish(1)
    bpy.app.timers.register(tick, first_interval=1.0)


if bpy.app.background or ZIP is None:
    RESULT["error"] = "needs the GUI (no --background) and the arguments -- ADDON.zip OUT.json SHOTS/"
    finish(1)
main()
