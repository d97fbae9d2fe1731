"""The sub-panels beside Watermark: Trace copies, Steganography, Analysis, Steganalysis, Study.

Each is collapsed until opened (``DEFAULT_CLOSED``); each shows its result while its objects are
selected, and the progress of a running job with "Esc stops it".
"""
from __future__ import annotations

import bpy

from .. import properties, session
from ..tasks import frames as frames_task
from .layout import field, fold, path_field, wrapped
from .results import draw_result, tied_result
from .watermark import Sidebar


def draw_running(layout, s, label: str) -> bool:
    """The progress of a running job called ``label`` (True if one is running)."""
    job = session.JOB["running"]
    if job is None or job.label != label:
        return False
    layout.prop(s, "study_progress", slider=True)
    layout.label(text=job.text)
    layout.label(text=f"Esc stops the {label.lower()}", icon="INFO")
    return True


class MESHMARK_PT_trace(Sidebar, bpy.types.Panel):
    """Give each recipient a copy with its own mark, and find whose copy a file is"""
    bl_idname = "MESHMARK_PT_trace"
    bl_label = "Trace copies"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 1
    bl_options = {"DEFAULT_CLOSED"}
    needs = ("meshmark.issue_copies", "meshmark.trace")

    def draw(self, context):
        s = context.scene.meshmark
        layout = self.layout
        field(layout, s, "registry")
        path_field(layout, s, "copies_dir", "Write the copies to:")
        layout.prop(s, "copies")
        field(layout, s, "copies_format")
        if not draw_running(layout, s, "Issue copies"):
            row = layout.row(align=True)
            row.operator("meshmark.issue_copies", text="Issue", icon="DUPLICATE")
            row.operator("meshmark.trace", text="Trace", icon="VIEWZOOM")
        draw_result(layout, context, tied_result(context, self.needs))


class MESHMARK_PT_stego(Sidebar, bpy.types.Panel):
    """Hide a text or a file in the mesh, readable only with the key"""
    bl_idname = "MESHMARK_PT_stego"
    bl_label = "Steganography"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 2
    bl_options = {"DEFAULT_CLOSED"}
    needs = ("meshmark.stego_embed", "meshmark.stego_extract")

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        layout.row().prop(s, "stego_source", expand=True)
        col = layout.column()
        field(col, s, "stego_text" if s.stego_source == "TEXT" else "stego_file")
        field(col, s, "key")
        row = layout.row(align=True)
        row.operator("meshmark.stego_embed", text="Hide", icon="HIDE_ON")
        row.operator("meshmark.stego_extract", text="Reveal", icon="HIDE_OFF")
        draw_result(layout, context, tied_result(context, self.needs))
        if fold(layout, s, "stego_show_advanced"):
            box = layout.box()
            box.row().prop(s, "stego_mode", expand=True)
            if s.stego_mode == "AUTO":
                box.label(text=f"Shading change {properties.STEGO_TOLERANCE:g} deg")
                box.label(text="Spread: Even")
            else:
                col = box.column(align=True)
                col.prop(s, "stego_tolerance", text="Shading")
                field(col, s, "stego_spread")
            field(box, s, "stego_save")


class MESHMARK_PT_analysis(Sidebar, bpy.types.Panel):
    """Colour the mesh by the precision each vertex needs and how rounding moves its curvature"""
    bl_idname = "MESHMARK_PT_analysis"
    bl_label = "Analysis"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 3
    bl_options = {"DEFAULT_CLOSED"}
    needs = ("meshmark.analyze",)

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        field(layout, s, "analysis_show")
        layout.operator("meshmark.analyze", text="Analyze", icon="COLOR")
        draw_result(layout, context, tied_result(context, self.needs))
        if fold(layout, s, "analysis_show_advanced"):
            box = layout.box()
            box.row().prop(s, "analysis_mode", expand=True)
            if s.analysis_mode == "AUTO":
                box.label(text=f"Shading change {properties.ANALYSIS_TOLERANCE:g} deg")
            else:
                box.prop(s, "analysis_tolerance", text="Shading")


class MESHMARK_PT_steganalysis(Sidebar, bpy.types.Panel):
    """How likely it is that the mesh hides something"""
    bl_idname = "MESHMARK_PT_steganalysis"
    bl_label = "Steganalysis"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 4
    bl_options = {"DEFAULT_CLOSED"}
    needs = ("meshmark.steganalysis_detect",)

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        field(layout, s, "model_source")
        if s.model_source == "FILE":
            field(layout, s, "model_file")
        layout.operator("meshmark.steganalysis_detect", text="Check", icon="VIEWZOOM")
        draw_result(layout, context, tied_result(context, self.needs))


class MESHMARK_PT_study(Sidebar, bpy.types.Panel):
    """Check the mark on the animation's frames; run a study file in the background"""
    bl_idname = "MESHMARK_PT_study"
    bl_label = "Study"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 5
    bl_options = {"DEFAULT_CLOSED"}
    needs = ("meshmark.deformation_study",)

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        layout.prop(s, "frames_auto")
        col = layout.column(align=True)
        if s.frames_auto:
            objs = properties.current_objects(context)
            start, end, source = frames_task.animation_range(context, objs) if objs else (
                context.scene.frame_start, context.scene.frame_end, "the scene")
            col.label(text=f"Frames {start} to {end}", icon="TIME")
            wrapped(col, context, f"from {source}", icon="BLANK1")  # an action's name can be long
        else:
            col.prop(s, "frame_start")
            col.prop(s, "frame_end")
        col.prop(s, "frame_step")
        path_field(layout, s, "output_dir", "Save the table and plot to:")
        if not draw_running(layout, s, "Check frames"):
            layout.operator("meshmark.deformation_study", text="Check frames", icon="GRAPH")
        draw_result(layout, context, tied_result(context, ("meshmark.deformation_study",)))
        if not operator_registered("meshmark.study"):
            return
        layout.separator()
        field(layout, s, "study_spec")
        path_field(layout, s, "study_out", "Save the results to:")
        if not draw_running(layout, s, "Study"):
            layout.operator("meshmark.study", text="Run study", icon="PLAY")
        draw_result(layout, context, tied_result(context, ("meshmark.study",), per_object=False))


def operator_registered(idname: str) -> bool:
    mod, name = idname.split(".")
    try:
        getattr(getattr(bpy.ops, mod), name).get_rna_type()
        return True
    except (AttributeError, KeyError):
        return False
