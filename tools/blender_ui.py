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
   Verify (``INVOKE_DEFAULT`` in the context of the sidebar region, as a click does: modal jobs, waited
   for while the window redraws), and every other operator of every sub-panel
   (tools/blender_ui_steps.py); after each step it waits for the UI to redraw, records what every
   sub-panel drew (blender_tests/ui_layout.py: texts, the width each needs by ``blf.dimensions`` and
   the width its slot gets in the region) and takes a screenshot of the window (``screen.screenshot``);
5. at the end it saves the .blend, waits for Blender's autosave, and searches both files for the
   hidden and revealed text (UTF-8, UTF-16LE/BE, and its hex) and the key.

It writes OUT.json (the region's geometry per screenshot, the drawn texts, truncated texts, results)
and exits 0 if the run went through, 1 on an exception. The test (blender_tests/test_blender_ui.py)
asserts on the JSON and crops the screenshots to the sidebar.
"""
import json
import os
import sys
import tempfile
import traceback

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "blender_tests"))  # rigs, ui_layout (NOT addon/: it is installed)
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))  # blender_ui_steps

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


ORIGINAL_DRAW = {}


def record_draws(panels_mod, ui_layout, open_all=False):
    """Wrap every registered panel class's draw: forward to the real layout, record the texts (the
    panels are registered again: Blender keeps the draw function it was given at registration).
    ``open_all``: register the sub-panels open (no ``DEFAULT_CLOSED``), so each can be drawn."""
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
        orig = ORIGINAL_DRAW.setdefault(cls, cls.draw)
        cls.draw = wrapper(cls, orig)
        if cls is not panels_mod.MESHMARK_PT_sidebar:
            cls.poll = classmethod(poll)
            if open_all and "DEFAULT_CLOSED" in set(getattr(cls, "bl_options", set())):
                cls.bl_options = set(cls.bl_options) - {"DEFAULT_CLOSED"}
                # the region keeps a panel's collapsed state by its idname: a new idname starts open
                cls.bl_idname = cls.bl_idname + "_open"
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


def wait_job(limit=600):
    """Yield (redrawing) until the add-on's modal job has finished; True if it did."""
    from meshmark_blender import session
    for _ in range(limit):
        if session.JOB["running"] is None:
            return True
        redraw()
        yield
    raise AssertionError(f"the job '{session.JOB['running'].label}' did not finish")


def press(op, *args, **kw):
    """Run ``op`` as its button does (INVOKE_DEFAULT in the sidebar's context); its return value, or the
    error it reported as {"RuntimeError": text}."""
    with ui_override():
        try:
            return sorted(op("INVOKE_DEFAULT", True, *args, **kw))
        except RuntimeError as exc:  # an ERROR report raises when called from Python
            return {"RuntimeError": str(exc).strip()}


def main():
    import types
    import blender_ui_steps
    # this script's names, for the steps (Blender runs it as a throw-away __main__ module: pass the
    # objects themselves, not the module)
    gen = blender_ui_steps.steps(types.SimpleNamespace(**globals()))

    def tick():
        try:
            next(gen)
            return 0.15
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
