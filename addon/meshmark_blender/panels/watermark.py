"""The tab's top (the objects the tasks work on, the keyfile they share) and the Watermark sub-panel.

The capacity line and the Auto line come from :func:`..tasks.watermark.plan`, the same choice Embed
makes for the message typed (the call ``meshmark.watermark.embed`` makes), computed on the fly up to
:data:`AUTO_CAPACITY_MAX_VERTICES` vertices and kept per signature in the session.
"""
from __future__ import annotations

import json

import bpy

from .. import messages, properties, session, targets, words
from .. import params as _params
from ..tasks import watermark as wm_task
from .layout import field, fold, ui_scale, wrapped
from .results import draw_result, tied_result

# The panel computes the capacity itself only for meshes up to this size (cached per mesh and
# parameters); larger meshes show the last result of the Capacity button.
AUTO_CAPACITY_MAX_VERTICES = 50_000


class Sidebar:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Meshmark"
    needs: tuple = ()  # operators this panel's task needs (registered only when all are)


def planned(context, s):
    """(plan dict or None, text to show instead) for the current objects and panel settings; never raises."""
    objs = properties.current_objects(context)
    if not objs:
        return None, "Select a mesh object"
    try:
        target = targets.Target(objs)
        params, mp = properties.method_settings(s, s.method)
        sig = ("plan", target.signature(), s.method, wm_task.payload_bits(s.message),
               json.dumps(params, sort_keys=True, default=str), bool(s.weld))
        hit = session.CACHE.get(sig)
        if hit is None:
            done = session.CACHE.get(("capacity", s.method, tuple(target.names)))
            if sum(len(o.data.vertices) for o in objs) > AUTO_CAPACITY_MAX_VERTICES:
                return done, "" if done else "Capacity not counted"
            hit = session.remember(sig, wm_task.plan(target, s.method, s.message, None, params, s.weld, mp))
        return hit, ""
    except Exception as exc:  # a too-small or invalid mesh: say why (in short), never fail drawing
        text = messages.friendly(str(exc), s.method)
        return None, "Mesh too small to carry a mark" if text.startswith(messages.TOO_SMALL) else text


def capacity_lines(context, s) -> list:
    d, why = planned(context, s)
    if d is None:
        return [why]
    fit = d["max_text_bytes"]
    text = f"Fits {fit} byte{'s' if fit > 1 else ''} of text" if fit else "No text fits"
    return ["Automatic settings", text] if s.param_mode == "AUTO" else [f"Capacity {d['capacity']} bits", text]


class MESHMARK_PT_sidebar(Sidebar, bpy.types.Panel):
    """The tab's top: the objects the tasks work on and their keyfile"""
    bl_idname = "MESHMARK_PT_sidebar"
    bl_label = "Meshmark"

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        objs = properties.current_objects(context)
        if not objs:
            layout.label(text="Select a mesh object", icon="INFO")
        elif len(objs) == 1:
            layout.label(text=objs[0].name, icon="MESH_DATA")
        else:
            wrapped(layout, context, f"{len(objs)} objects as one: {words.names([o.name for o in objs])}", "MESH_DATA")
        rest = targets.left_out(context, targets.Target(objs)) if objs else []
        if rest:
            n = len(rest) + len(objs)
            col = layout.column(align=True)
            col.label(text=f"{len(objs)} of {n} parts selected", icon="ERROR")
            col.operator("meshmark.select_parts", text=f"Select all {n} parts", icon="RESTRICT_SELECT_OFF")
        field(layout, s, "keyfile")
        row = layout.row(align=True)
        row.operator("meshmark.load_keyfile", text="Load", icon="FILEBROWSER")
        row.operator("meshmark.save_keyfile", text="Save", icon="FILE_TICK")
        d = tied_result(context, ("meshmark.load_keyfile", "meshmark.save_keyfile"))
        if d is not None and not d.get("ok", True):
            draw_result(layout, context, d)


class MESHMARK_PT_watermark(Sidebar, bpy.types.Panel):
    """Hide a message in the selected mesh and check it"""
    bl_idname = "MESHMARK_PT_watermark"
    bl_label = "Watermark"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 0
    needs = ("meshmark.embed", "meshmark.verify", "meshmark.capacity")

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        col = layout.column()
        field(col, s, "method")
        field(col, s, "message")
        field(col, s, "key")
        col.prop(s, "store_key")
        row = layout.row()
        lines = capacity_lines(context, s)
        col = row.column(align=True)
        for i, line in enumerate(lines):
            if i == 0 and len(lines) == 1:
                wrapped(col, context, line, "INFO", inset=22 * ui_scale())
            else:
                col.label(text=line, icon="INFO" if i == 0 else "BLANK1")
        row.operator("meshmark.capacity", text="", icon="FILE_REFRESH")
        row = layout.row(align=True)
        row.operator("meshmark.embed", text="Embed", icon="LOCKED")
        row.operator("meshmark.verify", text="Verify", icon="VIEWZOOM")
        layout.prop(s, "evaluated")
        draw_result(layout, context, tied_result(context, ("meshmark.embed", "meshmark.verify", "meshmark.capacity")))
        if fold(layout, s, "show_advanced"):
            draw_advanced(layout.box(), context, s)


def draw_advanced(layout, context, s) -> None:
    """The "Advanced" fold: the chosen method's settings (Auto: what Embed will use) and welding."""
    layout.row().prop(s, "param_mode", expand=True)
    if s.param_mode == "AUTO":
        d, _ = planned(context, s)
        if d is not None:
            names = _params.labels(s.method)
            shown = [f"{names[k]} {v:g}" if isinstance(v, float) else f"{names[k]} {v}"
                     for k, v in d["params"].items()
                     if k in names and k not in _params.HIDDEN and not isinstance(v, (bool, str))]
            col = layout.column(align=True)
            col.label(text="Embed will use:")
            for line in shown:
                col.label(text=line, icon="BLANK1")
    else:
        group = getattr(s.params, s.method, None)
        col = layout.column(align=True)
        for p in _params.panel_params(s.method) if group is not None else ():
            if p.kind in ("enum", "str"):
                field(col, group, p.name)
            else:
                col.prop(group, p.name)
    layout.prop(s, "weld")
