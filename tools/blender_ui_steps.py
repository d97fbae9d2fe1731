"""The steps of the real-UI run (tools/blender_ui.py drives them, one per timer tick): every operator of
every sub-panel pressed as its button does, a screenshot and a record of every sub-panel's draw after
each, and at the end the search of the saved .blend and the autosave for hidden data.

``steps(ui)`` is a generator; ``ui`` is the driver module (snapshot, press, wait_job, redraw, ...).
"""
import glob
import json
import math
import os
import time

import bpy

STUDY_NOISE = ['name = "noise"\ngrid = { strength = [0.001, 0.002, 0.003] }']  # with "none": 4 settings
SECRET_TEXT = "Hello from the sidebar"
SECRET_KEY = "sidebar-k3y-81"


def _coords(obj):
    import numpy as np
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co


def _build_scene(rigs):
    """The arm (rigged, animated over 5 frames), a two-part character, a stone for hiding, the camera.
    Built before the add-on is enabled (3.4 crashed in bone heat with it enabled)."""
    bpy.data.objects.remove(bpy.data.objects["Cube"], do_unlink=True)
    bpy.context.view_layer.update()
    arm = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    skel = rigs.chain_armature("Rig", [(0, 0, 0), (0, 0, 1), (0, 0, 2)])
    rigs.rig_auto(arm, skel)
    pb = skel.pose.bones["b1"]
    pb.rotation_mode = "XYZ"
    for f, deg in ((1, 0), (5, 30)):
        pb.rotation_euler = (math.radians(deg), 0, 0)
        pb.keyframe_insert("rotation_euler", frame=f)
    from meshmark.shapes import cylinder
    rig2 = rigs.chain_armature("Rig2", [(4, 0, 0), (4, 0, 1), (4, 0, 2)])
    for name, z0 in (("Char_Legs", 0.0), ("Char_Torso", 1.0)):
        m = cylinder(segments=24, rings=60)
        V = m.V * [1, 1, 0.5] + [4, 0, z0]
        part = rigs.mesh_object(name, mesh=m.with_vertices(V))
        rigs.rig_auto(part, rig2)
    bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=5, location=(-4, 0, 1))
    bpy.context.active_object.name = "Stone"
    return arm


def steps(ui):
    """A generator: each yield gives the UI a few redraws before the next step."""
    import rigs
    import sys
    sys.path[:] = [p for p in sys.path if p != os.path.join(ui.ROOT, "addon")]  # rigs put it there: the add-on
    # must come from the installed zip (the user scripts folder), not from the repository
    arm = _build_scene(rigs)
    autosave = _start_autosave(ui)  # its timer runs while the steps do (the search waits for a later one)
    import addon_utils
    assert bpy.ops.preferences.addon_install(filepath=ui.ZIP, overwrite=True) == {"FINISHED"}
    addon_utils.enable("meshmark_blender", default_set=True, handle_error=None)
    import meshmark_blender
    from meshmark_blender import panels, session
    from meshmark_blender.tasks import study as study_task
    import ui_layout
    ui.RESULT["addon_file"] = meshmark_blender.__file__
    ui.record_draws(panels, ui_layout)  # as shipped: the sub-panels other than Watermark closed
    s = bpy.context.scene.meshmark
    TMP = ui.TMP
    bpy.context.scene.frame_set(1)
    rigs.select_only(arm)
    win, area, region = ui.ui()
    area.spaces[0].show_region_ui = True
    yield

    # open the Meshmark tab: click down the tab column until the panel draws
    win, area, region = ui.ui()
    for i in range(80):
        if "Meshmark" in ui.DRAWN:
            break
        x, y = region.x + region.width - 8, region.y + region.height - 12 - 8 * i
        win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="PRESS", x=x, y=y)
        win.event_simulate(type="LEFTMOUSE", value="RELEASE", x=x, y=y)
        ui.DRAWN.clear()
        yield
    ui.RESULT["tab_clicks"] = i
    win.event_simulate(type="MOUSEMOVE", value="NOTHING", x=region.x - 300, y=region.y + 300)  # off the sidebar
    ui.redraw()
    yield
    ui.snapshot("open", region_ui_width=region.width)  # the sub-panels other than Watermark: closed
    ui.record_draws(panels, ui_layout, open_all=True)  # from here on every sub-panel is open, one at a time
    ui.redraw()
    yield

    # the fields, through the panel's properties; Embed and Verify as the buttons run them (modal jobs)
    s.method, s.message, s.key = "laplacian", "M", SECRET_KEY
    s.keyfile = os.path.join(TMP, "arm.json")
    r_embed = ui.press(bpy.ops.meshmark.embed)
    yield from ui.wait_job()
    embed = json.loads(s.last_result)
    r_cap = ui.press(bpy.ops.meshmark.capacity)  # before Verify: the panel shows the last result (Verify's)
    cap = json.loads(s.last_result)
    r_verify = ui.press(bpy.ops.meshmark.verify)
    yield from ui.wait_job()
    verify = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("watermark", embed=r_embed, verify=r_verify, capacity_op=r_cap, stored_cdr=embed.get("stored_cdr"),
                capacity=embed.get("capacity"), capacity_plan=cap.get("capacity"), detected=verify.get("detected"),
                cdr=verify.get("cdr"), message=verify.get("message"), keyfile_written=os.path.isfile(s.keyfile))

    s.show_advanced, s.param_mode = True, "AUTO"
    ui.redraw()
    yield
    ui.snapshot("watermark_auto")  # the Auto line: what Embed will use
    s.param_mode = "CUSTOM"
    ui.redraw()
    yield
    ui.snapshot("watermark_advanced")
    s.show_advanced, s.param_mode = False, "AUTO"

    # Embed again into the existing keyfile: the dialog names the file and what is lost
    op_drawn = {}
    cls = bpy.types.MESHMARK_OT_embed
    orig = cls.draw

    def op_draw(self, context):  # the replace dialog (420 px wide) or the file browser's side panel
        rec = ui_layout.draw_recorded(type("P", (), {"draw": staticmethod(orig)}), context, self.layout, self)
        width = 420 if self.confirm else context.region.width
        items = ui_layout.measure(rec, (width - 2 * ui_layout.BOX_PAD) * ui_layout.scale())
        op_drawn.update(items=[(i.kind, i.text) for i in items], truncated=ui_layout.truncated(items))
    bpy.utils.unregister_class(cls)
    cls.draw = op_draw
    bpy.utils.register_class(cls)
    before = _coords(arm)
    r_again = ui.press(bpy.ops.meshmark.embed)
    for _ in range(3):
        ui.redraw()
        yield
    ui.snapshot("embed_replace_dialog", window=bpy.context.window_manager.windows[0], result=r_again,
                dialog=dict(op_drawn))
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    yield
    ui.RESULT["replace_dialog_cancel_kept_mesh"] = bool((_coords(arm) == before).all())

    # the frame check: the frames of the armature's action
    ui.SHOW["only"] = "Study"
    s.output_dir = TMP
    r_study = ui.press(bpy.ops.meshmark.deformation_study)
    yield from ui.wait_job()
    study = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("study", result=r_study, summary=study.get("summary"), frames_from=study.get("frames_from"))

    # the selection changes: the arm's result is not shown for the camera
    ui.SHOW["only"] = None
    rigs.select_only(bpy.data.objects["Camera"])
    ui.redraw()
    yield
    ui.snapshot("camera_selected", last_result_object=json.loads(s.last_result).get("object"))

    # one part of the two-part character: the hint and its button; Select parts
    rigs.select_only(bpy.data.objects["Char_Legs"])
    ui.redraw()
    yield
    ui.snapshot("one_part_selected")
    r_parts = ui.press(bpy.ops.meshmark.select_parts)
    ui.redraw()
    yield
    ui.snapshot("parts_selected", result=r_parts,
                selected=sorted(o.name for o in bpy.context.selected_objects if o.type == "MESH"))

    # Trace copies: Issue (a modal job, one copy per step) and Trace
    rigs.select_only(arm)
    ui.SHOW["only"] = "Trace copies"
    s.registry, s.copies_dir, s.copies = os.path.join(TMP, "copies.sqlite"), os.path.join(TMP, "copies"), 3
    r_issue = ui.press(bpy.ops.meshmark.issue_copies)
    yield from ui.wait_job()
    issued = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("issue", result=r_issue, copies=[c["id"] for c in issued.get("copies", [])])
    r_trace = ui.press(bpy.ops.meshmark.trace)
    yield from ui.wait_job()
    traced = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("trace_copies", result=r_trace, copy=traced.get("copy"), n_copies=traced.get("n_copies"))

    # keyfile Save and Load (their file browsers are Blender's; here with the file name given)
    with ui.ui_override():
        r_save = sorted(bpy.ops.meshmark.save_keyfile(filepath=os.path.join(TMP, "arm-copy.json")))
        r_load = sorted(bpy.ops.meshmark.load_keyfile(filepath=os.path.join(TMP, "arm-copy.json")))
    s.keyfile, s.param_mode = os.path.join(TMP, "arm.json"), "AUTO"  # Load showed the keyfile's settings

    # Steganography: Hide on the watermarked arm asks first (Esc: nothing changed); on the stone it hides
    ui.SHOW["only"] = "Steganography"
    s.stego_source, s.stego_text = "TEXT", SECRET_TEXT
    before = _coords(arm)
    r_ask = ui.press(bpy.ops.meshmark.stego_embed)
    for _ in range(3):
        ui.redraw()
        yield
    ui.snapshot("stego_ask", window=bpy.context.window_manager.windows[0], result=r_ask)
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    yield
    asked_kept = bool((_coords(arm) == before).all())
    stone = bpy.data.objects["Stone"]
    rigs.select_only(stone)
    r_hide = ui.press(bpy.ops.meshmark.stego_embed)
    yield from ui.wait_job()
    hide = json.loads(s.last_result)
    r_reveal = ui.press(bpy.ops.meshmark.stego_extract)
    yield from ui.wait_job()
    reveal = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("stego", hide=r_hide, reveal=r_reveal, read_back=hide.get("read_back"), text=reveal.get("text"),
                ask=r_ask, ask_kept_mesh=asked_kept, save=r_save, load=r_load)
    stego_done = time.time()  # the session now holds the hidden text: an autosave after this is searched

    # Analysis: the heat map, and the viewport switched to show it
    ui.SHOW["only"] = "Analysis"
    rigs.select_only(arm)
    r_an = ui.press(bpy.ops.meshmark.analyze)
    yield from ui.wait_job()
    an = json.loads(s.last_result)
    ui.redraw()
    yield
    sh = area.spaces[0].shading
    ui.snapshot("analysis", result=r_an, level_min=an.get("level_min"), level_max=an.get("level_max"),
                active_color=arm.data.color_attributes.active_color.name, shading=[sh.type, sh.color_type])
    win, area, region = ui.ui()
    main = next(r for r in area.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=win, area=area, region=main, screen=win.screen):
        bpy.ops.view3d.view_selected()  # frame the arm so that its heat map fills the view
    ui.redraw()
    yield
    ui.snapshot("analysis_viewport", window=win)

    # Steganalysis: the stone with data hidden in it, and a cube too small to judge
    ui.SHOW["only"] = "Steganalysis"
    rigs.select_only(stone)
    r_det = ui.press(bpy.ops.meshmark.steganalysis_detect)
    yield from ui.wait_job()
    det = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("steganalysis", result=r_det, state=det.get("state"), probability=det.get("probability"))
    bpy.ops.mesh.primitive_cube_add(location=(0, 4, 0))
    small = bpy.context.active_object
    rigs.select_only(small)
    ui.press(bpy.ops.meshmark.steganalysis_detect)
    yield from ui.wait_job()
    tiny = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("steganalysis_cannot_judge", state=tiny.get("state"), why=tiny.get("why"))

    # Study: a study file run in Blender's own Python, in the background (progress, then done)
    ui.SHOW["only"] = "Study"
    spec = os.path.join(TMP, "study.toml")
    with open(spec, "w") as f:
        f.write(rigs.study_spec(rigs.shared_mesh("classic/fandisk.obj"), seeds=(0, 1, 2), attacks=STUDY_NOISE, name="ui"))
    s.study_spec, s.study_out = spec, os.path.join(TMP, "study_out")
    r_run = ui.press(bpy.ops.meshmark.study)
    ui.redraw()
    yield
    ui.snapshot("study_running", result=r_run, running=session.JOB["running"] is not None,
                python=study_task.python_executable())
    yield from ui.wait_job(limit=1200)
    ui.redraw()
    yield
    ui.snapshot("study_spec", last_result=json.loads(s.last_result))

    # Esc stops a running study: a long spec, Esc pressed through the window's event queue
    with open(spec, "w") as f:
        f.write(rigs.study_spec(rigs.shared_mesh("classic/bunny.obj"), seeds=range(300), attacks=STUDY_NOISE, name="ui"))
    s.study_out = os.path.join(TMP, "study_out_stopped")
    ui.press(bpy.ops.meshmark.study)
    for _ in range(200):  # until the process has planned its tasks
        ui.redraw()
        yield
        run = study_task.CURRENT["run"]
        if run is not None and run.todo > 0:
            break
    win, area, region = ui.ui()
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    for _ in range(20):
        ui.redraw()
        yield
        if session.JOB["running"] is None:
            break
    run = study_task.CURRENT["run"]
    ui.snapshot("study_stopped", last_result=json.loads(s.last_result), running=session.JOB["running"] is not None,
                returncode=None if run is None else run.proc.returncode, done=None if run is None else run.done,
                todo=None if run is None else run.todo)
    ui.SHOW["only"] = None

    # a cube: Embed refuses in the user's words, before any file browser, in the panel and the report
    bpy.ops.mesh.primitive_cube_add(location=(3, 0, 0))
    cube = bpy.context.active_object
    rigs.select_only(cube)
    r = ui.press(bpy.ops.meshmark.embed)
    err = json.loads(s.last_result)
    ui.redraw()
    yield
    ui.snapshot("cube_error", result=r, error=err.get("error"),
                browser_open=any(a.type == "FILE_BROWSER" for w in bpy.context.window_manager.windows
                                 for a in w.screen.areas))

    # the Embed file browser (the .blend not saved: no folder for '//'): its side panel is a summary
    rigs.select_only(bpy.data.objects["Arm"])
    op_drawn.clear()
    s.keyfile = ""  # back to the default, //Arm.meshmark.json, which has no folder yet
    r_browse = ui.press(bpy.ops.meshmark.embed)
    ui.redraw()
    for _ in range(3):
        yield
    browser = bpy.context.window_manager.windows[-1]
    ui.snapshot("embed_file_browser", window=browser, result=r_browse, operator_panel=dict(op_drawn),
                browser_open=any(a.type == "FILE_BROWSER" for w in bpy.context.window_manager.windows
                                 for a in w.screen.areas))
    win = bpy.context.window_manager.windows[-1]
    win.event_simulate(type="ESC", value="PRESS")
    win.event_simulate(type="ESC", value="RELEASE")
    yield
    yield from _secrets_out_of_the_files(ui, s, autosave, stego_done)


def _start_autosave(ui):
    """Turn Blender's autosave on (every minute, the shortest) at the start: its timer runs while the
    steps do. Returns the folder and the start time."""
    prefs = bpy.context.preferences.filepaths
    temp = os.path.join(ui.TMP, "autosave")
    os.makedirs(temp, exist_ok=True)
    prefs.temporary_directory = temp
    prefs.use_auto_save_temporary_files = True
    prefs.auto_save_time = 1  # minutes: the shortest
    return temp, time.monotonic()


def _secrets_out_of_the_files(ui, s, autosave_started, after):
    """Save the .blend and wait for an autosave written after ``after`` (time.time() once the text was
    hidden and revealed); search both for the hidden and revealed text."""
    temp, t0 = autosave_started
    blend = os.path.join(ui.TMP, "scene.blend")
    bpy.ops.wm.save_as_mainfile(filepath=blend, compress=False)

    def written():
        found = glob.glob(os.path.join(temp, "*autosave*.blend")) + glob.glob(os.path.join(bpy.app.tempdir,
                                                                                               "*autosave*.blend"))
        return [p for p in found if os.path.getmtime(p) > after]
    autosave = written()
    while time.monotonic() - t0 < 400 and not autosave:
        ui.redraw()
        yield
        autosave = written()
    import rigs
    needles = rigs.secret_needles(SECRET_TEXT, SECRET_KEY)
    found = {}
    for path in [blend] + autosave:
        raw = open(path, "rb").read()
        found[os.path.basename(path)] = [n for n, b in needles.items() if b in raw]
    ui.RESULT["secrets"] = {"files": [blend] + autosave, "autosave_seconds": round(time.monotonic() - t0, 1),
                            "found": found, "message_saved": b"Arm" in open(blend, "rb").read(),
                            "session_text_kept": s.stego_text == SECRET_TEXT}
