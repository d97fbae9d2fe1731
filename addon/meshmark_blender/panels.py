"""The "Meshmark" tab of the 3D View sidebar (N panel)."""
from __future__ import annotations

import json

import bpy

from . import operators, properties
from . import params as _params

# The panel computes the capacity itself only for meshes up to this size (cached per mesh and
# parameters); larger meshes show the last result of the Capacity button.
AUTO_CAPACITY_MAX_VERTICES = 50_000


def capacity_line(context, obj, settings) -> str:
    """One line about the active mesh's capacity for the panel (never raises)."""
    if obj is None or obj.type != "MESH":
        return "Select a mesh object"
    try:
        method = settings.method
        p = properties.method_settings(settings, method)
        sig = operators.capacity_signature(obj, method, p, settings.weld)
        hit = operators.CAPACITY_CACHE.get(obj.name)
        if hit is None or hit[0] != sig:
            if len(obj.data.vertices) > AUTO_CAPACITY_MAX_VERTICES or obj.mode == "EDIT":
                return f"{len(obj.data.vertices):,} vertices: press Capacity"
            hit = (sig, operators.capacity_of(obj, method, p, settings.weld))
            operators.CAPACITY_CACHE[obj.name] = hit
        d = hit[1]
        return f"Capacity: {d['capacity']} bits, message up to {d['max_text_bytes']} bytes"
    except Exception as exc:  # a too-small or invalid mesh: say why, never fail drawing
        return f"Capacity: {exc}"[:120]


class MESHMARK_PT_sidebar(bpy.types.Panel):
    bl_idname = "MESHMARK_PT_sidebar"
    bl_label = "Meshmark"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Meshmark"

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        obj = context.active_object

        col = layout.column(align=True)
        col.prop(s, "method")
        group = getattr(s.params, s.method, None)
        if group is not None:
            for p in _params.method_params(s.method):
                col.prop(group, p.name)
        col.prop(s, "weld")
        layout.prop(s, "message")
        layout.prop(s, "key")
        layout.prop(s, "store_key")
        row = layout.row(align=True)
        row.label(text=capacity_line(context, obj, s), icon="INFO")
        row.operator("meshmark.capacity", text="", icon="FILE_REFRESH")

        layout.operator("meshmark.embed", icon="LOCKED")

        box = layout.box()
        box.prop(s, "keyfile")
        row = box.row(align=True)
        row.operator("meshmark.save_keyfile", icon="FILE_TICK")
        row.operator("meshmark.load_keyfile", icon="FILEBROWSER")
        row = box.row(align=True)
        row.prop(s, "evaluated")
        row.operator("meshmark.verify", icon="VIEWZOOM")
        _draw_result(box, s.last_result)

        box = layout.box()
        box.label(text="Deformation study", icon="ARMATURE_DATA")
        row = box.row(align=True)
        row.prop(s, "frame_start")
        row.prop(s, "frame_end")
        row.prop(s, "frame_step")
        box.prop(s, "output_dir")
        box.operator("meshmark.deformation_study", icon="GRAPH")


def _draw_result(layout, text: str) -> None:
    if not text:
        return
    try:
        d = json.loads(text)
    except ValueError:
        return
    if not d.get("ok", True):
        layout.label(text=d.get("error", "error")[:120], icon="ERROR")
    elif "detected" in d:
        layout.label(text=("Detected" if d["detected"] else "Not detected")
                     + f"  NC {d['nc']:.3f}  CDR {d['cdr']:.3f}", icon="CHECKMARK" if d["detected"] else "CANCEL")
        if d.get("message_ok"):
            layout.label(text=f"Message: {d['message']}")
    elif "summary" in d:
        s = d["summary"]
        layout.label(text=f"{s['detected_frames']}/{s['frames']} frames detected, mean CDR {s['mean_cdr']:.3f}")


classes = (MESHMARK_PT_sidebar,)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
