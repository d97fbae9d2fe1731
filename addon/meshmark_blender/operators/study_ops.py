"""``bpy.ops.meshmark.deformation_study`` (Verify over the animation's frames) and ``study`` (a study spec
run in Blender's own Python, in the background): see :mod:`..tasks.frames` and :mod:`..tasks.study`."""
from __future__ import annotations

import bpy
from bpy.props import IntProperty, StringProperty

from .. import keyfiles, words
from ..tasks import frames as frames_task, study as study_task
from ..tasks.outcome import Outcome
from ..properties import path_property
from .base import Base


class MESHMARK_OT_deformation_study(Base, bpy.types.Operator):
    """Check the mark on every n-th frame of the animation; write a table (CSV) and a plot"""
    bl_idname = "meshmark.deformation_study"
    bl_label = "Check frames"
    job_label = "Check frames"

    keyfile: path_property("FILE_PATH", name="Keyfile", options={"SKIP_SAVE"})
    frame_start: IntProperty(name="Start", options={"SKIP_SAVE"})
    frame_end: IntProperty(name="End", options={"SKIP_SAVE"})
    frame_step: IntProperty(name="Step", min=1, default=1, options={"SKIP_SAVE"})
    output_dir: path_property("DIR_PATH", name="Save table to", options={"SKIP_SAVE"})

    def steps(self, context):
        s = context.scene.meshmark
        if self.given("frame_start") or self.given("frame_end") or not s.frames_auto:
            start, end = self.arg(context, "frame_start"), self.arg(context, "frame_end")
        else:
            start = end = None  # the animation's range
        return frames_task.frames_steps(context, self.target(context), keyfile=self.arg(context, "keyfile"),
                                        frame_start=start, frame_end=end, frame_step=self.arg(context, "frame_step"),
                                        output_dir=self.arg(context, "output_dir"))


class MESHMARK_OT_study(Base, bpy.types.Operator):
    """Run a study (a .toml file) in the background: the window stays usable, Esc stops it (run it again to
    resume)"""
    bl_idname = "meshmark.study"
    bl_label = "Run study"
    job_label = "Study"

    spec: path_property("FILE_PATH", name="Study file", options={"SKIP_SAVE"})
    out: path_property("DIR_PATH", name="Results to", options={"SKIP_SAVE"})

    def steps(self, context):
        spec, out = study_task.study_paths(self.arg(context, "spec", "study_spec"), self.arg(context, "out", "study_out"),
                                           keyfiles.resolve)
        return self._run(spec, out, 0.0 if getattr(self, "_modal", False) else 0.05)

    @staticmethod
    def _run(spec, out, poll):
        d = yield from study_task.study_steps(spec, out, poll)
        s = d["summary"]
        ok, failed, mesh_error = s.get("ok", 0), s.get("failed", 0), s.get("mesh_error", 0)
        text = (f"Study done: {ok} of {d['planned']} tasks ran"
                + (f", {words.plural(failed, 'task')} failed" if failed else "")
                + (f", {mesh_error} could not take the method or attack" if mesh_error else "")
                + f"; results in {out}")
        return Outcome(study_task.STUDY, [], "WARNING" if failed else "INFO", text, d)

    def invoke(self, context, event):
        self._modal = True
        return self.start_job(context)


CLASSES = (MESHMARK_OT_deformation_study, MESHMARK_OT_study)
