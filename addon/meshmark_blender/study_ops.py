"""``bpy.ops.meshmark.study``: run a study spec (meshmark.study) in the background.

From the panel (``INVOKE_DEFAULT``) the operator is modal: it starts :mod:`.study_runner` in its own
Python process, and a window-manager timer reads the runner's progress lines, shows them in the
status bar and the panel (``scene.meshmark.study_progress``) and never blocks the UI; Esc stops the
process. From a script (``EXEC_DEFAULT``, e.g. background Blender) it runs the same process and
waits. Either way the result (the output folder, the engine's summary) is JSON in ``last_result``.

The Python that runs the study: ``$MESHMARK_PYTHON`` if set, else Blender's ``sys.executable`` when
it is a Python interpreter (the bpy module; Blender 4+ ships one), else ``python3``. It needs the
study's dependencies (pyarrow); the add-on puts its own ``meshmark`` first on the path.
"""
from __future__ import annotations

import json
import os
import queue
import subprocess
import sys
import threading
import time

import bpy
from bpy.props import StringProperty

import meshmark
from meshmark import MeshError

from .operators import _Base, _abspath

RUNNER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "study_runner.py")
STATE = {"running": None}  # the running study (one at a time), for the panel


def python_executable() -> str:
    env = os.environ.get("MESHMARK_PYTHON")
    if env:
        return env
    exe = sys.executable or ""
    return exe if os.path.basename(exe).startswith("python") else "python3"


class StudyRun:
    """The study process and a thread turning its stdout lines into messages on a queue."""

    def __init__(self, spec: str, out: str):
        env = dict(os.environ)
        pkg_parent = os.path.dirname(os.path.dirname(os.path.abspath(meshmark.__file__)))
        env["PYTHONPATH"] = os.pathsep.join([pkg_parent] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p])
        self.spec, self.out = spec, out
        self.proc = subprocess.Popen([python_executable(), RUNNER, spec, out], stdout=subprocess.PIPE,
                                     stderr=subprocess.PIPE, text=True, env=env, cwd=os.path.dirname(spec))
        self.q: queue.Queue = queue.Queue()
        self.planned = self.todo = self.done = 0
        self.summary = self.error = None
        self.stderr = ""
        self.t0 = time.monotonic()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self):
        for line in self.proc.stdout:
            try:
                self.q.put(json.loads(line))
            except ValueError:
                pass
        self.stderr = self.proc.stderr.read()[-2000:]
        self.q.put(None)  # end of output

    def poll(self) -> bool:
        """Take in what the process said; True once it has finished."""
        finished = False
        while True:
            try:
                d = self.q.get_nowait()
            except queue.Empty:
                break
            if d is None:
                finished = True
                continue
            if "planned" in d:
                self.planned, self.todo = d["planned"], d["todo"]
            self.done = d.get("done", self.done)
            self.summary = d.get("summary", self.summary)
            self.error = d.get("error", self.error)
        if finished:
            self.proc.wait()
            if self.summary is None and self.error is None:
                self.error = f"the study process stopped (exit {self.proc.returncode}): {self.stderr.strip()[-300:]}"
        return finished

    @property
    def fraction(self) -> float:
        return self.done / self.todo if self.todo else (1.0 if self.summary is not None else 0.0)

    def text(self) -> str:
        return f"Study: {self.done}/{self.todo} tasks ({100 * self.fraction:.0f} %), Esc to stop"

    def cancel(self):
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(5)
            except subprocess.TimeoutExpired:  # pragma: no cover
                self.proc.kill()


class MESHMARK_OT_study(_Base, bpy.types.Operator):
    """Run a study (a .toml spec) in the background: the window stays usable, Esc stops it"""
    bl_idname = "meshmark.study"
    bl_label = "Run study"
    bl_options = {"REGISTER"}

    spec: StringProperty(name="Spec", subtype="FILE_PATH", options={"SKIP_SAVE"})
    output_dir: StringProperty(name="Folder", subtype="DIR_PATH", options={"SKIP_SAVE"})

    _run = None
    _timer = None

    def _paths(self, context):
        s = context.scene.meshmark
        spec = _abspath(self.spec if self.properties.is_property_set("spec") else s.study_spec)
        out = _abspath(self.output_dir if self.properties.is_property_set("output_dir") else s.study_out)
        if not spec:
            raise MeshError("choose the study spec (spec='/path/study.toml', or the panel's Spec field)")
        if not os.path.isfile(spec):
            raise MeshError(f"the study spec '{spec}' does not exist")
        if not out:
            raise MeshError("choose the folder for the results (output_dir=..., or the panel's Folder field)")
        if not os.path.isdir(os.path.dirname(out.rstrip(os.sep)) or "."):
            raise MeshError(f"the folder '{out}' cannot be made: its parent does not exist")
        if STATE["running"] is not None:
            raise MeshError("a study is already running: wait for it or press Esc")
        return spec, out

    def _result(self, context, run: StudyRun, cancelled=False):
        STATE["running"] = None
        context.scene.meshmark.study_progress = 100.0 * run.fraction
        if cancelled:
            d = {"operator": "meshmark.study", "ok": False, "error": f"stopped after {run.done}/{run.todo} tasks",
                 "object": None, "output_dir": run.out, "done": run.done}
            context.scene.meshmark.last_result = json.dumps(d)
            self.report({"WARNING"}, f"meshmark: study stopped after {run.done}/{run.todo} tasks (run it again to resume)")
            return {"CANCELLED"}
        if run.error is not None:
            return self.fail(context, MeshError(run.error))
        s = run.summary
        result = {"ok": True, "object": None, "spec": run.spec, "output_dir": run.out,
                  "results": os.path.join(run.out, "results"), "planned": run.planned, "done": run.done,
                  "summary": s, "seconds": time.monotonic() - run.t0}
        return self.finish(context, result, "INFO" if not s.get("failed") else "WARNING",
                           f"meshmark: study done: {s.get('ok', 0)} ok, {s.get('mesh_error', 0)} mesh errors, "
                           f"{s.get('failed', 0)} failed; results in {run.out}")

    def run(self, context):  # scripts: run and wait
        spec, out = self._paths(context)
        run = StudyRun(spec, out)
        STATE["running"] = run
        try:
            while not run.poll():
                time.sleep(0.05)
        except BaseException:
            run.cancel()
            STATE["running"] = None
            raise
        return self._result(context, run)

    def invoke(self, context, event):
        try:
            spec, out = self._paths(context)
            self._run = StudyRun(spec, out)
        except Exception as exc:
            return self.fail(context, exc)
        STATE["running"] = self._run
        context.scene.meshmark.study_progress = 0.0
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.25, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 1000)
        return {"RUNNING_MODAL"}

    def _end(self, context):
        wm = context.window_manager
        if self._timer is not None:
            wm.event_timer_remove(self._timer)
            self._timer = None
        wm.progress_end()
        if context.workspace is not None:
            context.workspace.status_text_set(None)
        for area in context.screen.areas if context.screen else ():
            area.tag_redraw()

    def modal(self, context, event):
        run = self._run
        if event.type == "ESC":
            run.cancel()
            run.poll()
            self._end(context)
            return self._result(context, run, cancelled=True)
        if event.type != "TIMER":
            return {"PASS_THROUGH"}
        finished = run.poll()
        context.scene.meshmark.study_progress = 100.0 * run.fraction
        context.window_manager.progress_update(int(1000 * run.fraction))
        if context.workspace is not None:
            context.workspace.status_text_set(run.text())
        for area in context.screen.areas if context.screen else ():
            if area.type == "VIEW_3D":
                area.tag_redraw()
        if not finished:
            return {"PASS_THROUGH"}
        self._end(context)
        return self._result(context, run)


classes = (MESHMARK_OT_study,)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    r = STATE["running"]
    if r is not None:
        r.cancel()
        STATE["running"] = None
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
