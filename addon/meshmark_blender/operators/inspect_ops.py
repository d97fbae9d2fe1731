"""``bpy.ops.meshmark.analyze`` (the precision heat map) and ``steganalysis_detect``: see :mod:`..tasks.inspect`."""
from __future__ import annotations

import bpy
from bpy.props import EnumProperty, FloatProperty, StringProperty

from meshmark import MeshError

from .. import bridge, properties
from ..tasks import inspect as task
from .base import Base


class MESHMARK_OT_analyze(Base, bpy.types.Operator):
    """Colour the active mesh by how many bits each vertex needs, and by how much rounding them moves the curvature"""
    bl_idname = "meshmark.analyze"
    bl_label = "Analyze"
    bl_options = {"REGISTER", "UNDO"}
    job_label = "Analyze"

    tolerance: FloatProperty(name="Shading change", min=0.0, options={"SKIP_SAVE"},
                             description="How far the shading may turn, in degrees")
    mode: EnumProperty(name="Levels", options={"SKIP_SAVE"},
                       items=[("ADAPTIVE", "Per vertex", "Each vertex its own precision, by curvature (Fig. 4.7)"),
                              ("GLOBAL", "One for the mesh", "One precision for the whole mesh")])
    show: EnumProperty(name="Show", items=properties.ANALYSIS_SHOW, options={"SKIP_SAVE"})

    def steps(self, context):
        s = context.scene.meshmark
        tol = self.tolerance if self.given("tolerance") else (
            s.analysis_tolerance if s.analysis_mode == "CUSTOM" else properties.ANALYSIS_TOLERANCE)
        return task.analyze_steps(context, bridge.active_mesh_object(context), tolerance=tol,
                                  mode=self.mode if self.given("mode") else "ADAPTIVE",
                                  show=self.arg(context, "show", "analysis_show"))


class MESHMARK_OT_steganalysis_detect(Base, bpy.types.Operator):
    """How likely it is that something is hidden in the active mesh (or: why the detector cannot judge it)"""
    bl_idname = "meshmark.steganalysis_detect"
    bl_label = "Check"
    job_label = "Steganalysis"

    model: StringProperty(name="Detector file", subtype="FILE_PATH", options={"SKIP_SAVE"},
                          description="A detector file (empty: the built-in one)")

    def steps(self, context):
        s = context.scene.meshmark
        if self.given("model"):
            path = self.model or None
        else:
            path = s.model_file if s.model_source == "FILE" else None
            if s.model_source == "FILE" and not path:
                raise MeshError("choose the detector file (or Detector: Built-in)")
        return task.detect_steps(context, bridge.active_mesh_object(context), model=path)


CLASSES = (MESHMARK_OT_analyze, MESHMARK_OT_steganalysis_detect)
