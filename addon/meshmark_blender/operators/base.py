"""What every meshmark operator shares: arguments with panel fallbacks, reports, results, and jobs.

Every operator takes keyword arguments from scripts; an argument not given falls back to the panel's
field of the same name (``scene.meshmark``). It runs one task (:mod:`..tasks`): pressed in the panel
(``INVOKE_DEFAULT``) as a modal job, one step per timer tick, with the step in the status bar and
``Esc`` stopping it between steps; called from a script (``EXEC_DEFAULT``) at once. Its result goes to
the session (``scene.meshmark.last_result``, JSON: never saved in the .blend) and to ``self.report``;
a failure reports an error in the user's words and returns ``{'CANCELLED'}`` with the mesh untouched.

Only operators that change a mesh push an undo step (``bl_options`` with ``"UNDO"``: Embed, Hide,
Analyze, Select parts); Verify, Capacity, Trace, the studies and the rest do not, so Ctrl+Z after
Embed then Verify undoes the Embed.
"""
from __future__ import annotations

import json
import time
import traceback

from meshmark import MeshError

from .. import messages, properties, session, targets
from ..bridge import BlenderInputError
from ..tasks.outcome import failure, json_default, operator_id, run

EXPECTED = (MeshError, BlenderInputError, OSError, ValueError)
TICK_SECONDS = 0.15  # work done per timer tick before the window redraws


class Job:
    """A running modal task: its fraction done and the current step (for the status bar and panel)."""

    def __init__(self, label: str):
        self.label, self.fraction, self.text = label, 0.0, label
        self.t0 = time.monotonic()

    def status(self) -> str:
        return f"meshmark: {self.text} ({100 * self.fraction:.0f} %), Esc to stop"


class Base:
    bl_options = {"REGISTER"}
    job_label = "Working"

    # -- arguments --------------------------------------------------------------------------------
    def arg(self, context, name, field: str | None = None):
        """The operator argument if given, else the panel field ``field`` (default: the same name)."""
        if self.properties.is_property_set(name):
            return getattr(self, name)
        return getattr(context.scene.meshmark, field or name)

    def given(self, name) -> bool:
        return self.properties.is_property_set(name)

    def target(self, context):
        return targets.from_selection(context)

    def steps(self, context):
        """The task's steps (a generator returning an Outcome)."""
        raise NotImplementedError

    # -- results ----------------------------------------------------------------------------------
    def done(self, context, outcome):
        session.RESULT["json"] = outcome.to_json()
        self.report({outcome.level}, f"meshmark: {outcome.text}")
        for w in outcome.warnings:
            self.report({"WARNING"}, f"meshmark: {w}")
        return {"FINISHED"}

    def error_method(self, context):
        """The method an error message is about (to name its parameters as the panel does)."""
        try:
            return self.arg(context, "method") if "method" in self.properties.bl_rna.properties else None
        except Exception:  # pragma: no cover
            return None

    def fail(self, context, exc):
        if isinstance(exc, EXPECTED):
            msg = messages.friendly(str(exc), self.error_method(context))
        else:  # a bug: keep Blender alive, say so, and keep the traceback in the console
            traceback.print_exc()
            msg = f"internal error ({type(exc).__name__}: {exc}); the mesh was not changed"
        objs = [o.name for o in properties.current_objects(context)]
        active = getattr(context, "active_object", None)
        if not objs and active is not None:  # the error is about the active object (a camera, say)
            objs = [active.name]
        d = failure(operator_id(self.bl_idname), objs, msg)
        d.update(getattr(exc, "data", None) or {})
        d.update(ok=False, error=msg)
        session.RESULT["json"] = json.dumps(d, default=json_default)
        self.report({"ERROR"}, f"meshmark: {msg}")
        return {"CANCELLED"}

    def draw(self, context):
        """The redo panel: no second copy of the panel's fields (the operator takes its values from it)."""
        self.layout.label(text="Settings: Meshmark panel", icon="INFO")

    # -- running ----------------------------------------------------------------------------------
    def execute(self, context):
        try:
            return self.done(context, run(self.steps(context)))
        except Exception as exc:  # never let an exception reach Blender
            return self.fail(context, exc)

    def invoke(self, context, event):
        return self.start_job(context)

    def start_job(self, context):
        """Run :meth:`steps` as a modal job (a window is needed; without one, at once)."""
        if getattr(context, "window", None) is None:
            return self.execute(context)
        if session.JOB["running"] is not None:
            return self.fail(context, MeshError(f"'{session.JOB['running'].label}' is still running: wait for it, "
                                                "or press Esc to stop it"))
        try:
            self._gen = self.steps(context)
        except Exception as exc:
            return self.fail(context, exc)
        self._job = session.JOB["running"] = Job(self.job_label)
        wm = context.window_manager
        wm.progress_begin(0, 1000)
        self._timer = wm.event_timer_add(0.02, window=context.window)
        wm.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def _end(self, context):
        wm = context.window_manager
        if getattr(self, "_timer", None) is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        session.JOB["running"] = None
        if getattr(context, "workspace", None) is not None:
            context.workspace.status_text_set(None)
        for area in context.screen.areas if getattr(context, "screen", None) else ():
            area.tag_redraw()

    def modal(self, context, event):
        try:
            return self._tick(context, event)
        except Exception as exc:  # never leave a job running after an error
            self._end(context)
            return self.fail(context, exc)

    def _tick(self, context, event):
        job = self._job
        if event.type == "ESC" and event.value == "PRESS":
            self._gen.close()  # the task's clean-up runs (frames, modifiers, processes)
            self._end(context)
            self.cancelled(context, job)
            return {"CANCELLED"}
        if event.type != "TIMER":  # (any timer: Blender 3.4's events do not say which)
            return {"PASS_THROUGH"}
        until = time.monotonic() + TICK_SECONDS
        try:
            while True:
                job.fraction, job.text = next(self._gen)
                if time.monotonic() >= until:
                    break
        except StopIteration as stop:
            self._end(context)
            if stop.value is None:
                return {"CANCELLED"}
            return self.done(context, stop.value)
        context.window_manager.progress_update(int(1000 * job.fraction))
        if getattr(context, "workspace", None) is not None:
            context.workspace.status_text_set(job.status())
        for area in context.screen.areas if getattr(context, "screen", None) else ():
            if area.type in ("VIEW_3D", "STATUSBAR"):
                area.tag_redraw()
        return {"PASS_THROUGH"}

    def cancelled(self, context, job):
        msg = f"{job.label} stopped at {100 * job.fraction:.0f} % ({job.text}); nothing more was changed"
        d = failure(operator_id(self.bl_idname), [o.name for o in properties.current_objects(context)], msg)
        d["stopped"] = True
        session.RESULT["json"] = json.dumps(d)
        self.report({"WARNING"}, f"meshmark: {msg}")
