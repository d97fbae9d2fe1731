"""The "Meshmark" tab of the 3D View sidebar (N panel).

A parent panel (the active object, the one keyfile field every task shares) and one sub-panel per
task, each a class listed once in :data:`SUBPANELS`. A sub-panel whose operators are not registered
(``needs``) is not registered either, so a task appears when its feature lands:

* Watermark (embed, verify, capacity) with its "Advanced" fold (``scene.meshmark.show_advanced``;
  settings Auto or Custom, only the chosen method's, plus welding);
* Trace copies (``meshmark.issue_copies`` / ``meshmark.trace``, not in this version);
* Steganography (``meshmark.stego_embed`` / ``stego_extract``), Analysis (``meshmark.analyze``, the
  heat maps), Steganalysis (``meshmark.steganalysis_detect``), each with its "Advanced" fold where
  it has settings (Auto by default);
* Study (the deformation study, and ``meshmark.study``: a study spec run in the background).

Every text fits the default sidebar width: fields are drawn as a label column and a value column
(:func:`field`), long texts (results, errors) are wrapped to the region's width (:func:`wrapped`),
and a result is shown only while the object it describes is the active one.
"""
from __future__ import annotations

import json

import bpy

from . import messages, operators, properties
from . import params as _params

# The panel computes the capacity itself only for meshes up to this size (cached per mesh and
# parameters); larger meshes show the last result of the Capacity button.
AUTO_CAPACITY_MAX_VERTICES = 50_000
# Horizontal space the sidebar takes from its region beyond a panel's content (category tabs and
# panel margins), in pixels at UI scale 1 (Blender 3.4: a 229 px region holds 172 px of content).
SIDEBAR_MARGIN = 60
BOX_MARGIN = 12
DEFAULT_REGION_WIDTH = 229  # the sidebar's width in a new window (no region in background mode)
LABEL_FACTOR = 0.35  # label column of a field


# -- text measuring and wrapping --------------------------------------------------------------------
def ui_scale() -> float:
    """Pixels per UI unit pixel (preferences' resolution scale and the display's DPI)."""
    dpi = getattr(bpy.context.preferences.system, "dpi", 72) or 72
    return dpi / 72.0


def text_width(text: str) -> float:
    """Width in pixels of ``text`` in the UI's widget font (``blf``), at the current UI scale."""
    import blf
    points = bpy.context.preferences.ui_styles[0].widget.points or 11
    if bpy.app.version < (4, 0, 0):
        blf.size(0, points, int(round(72 * ui_scale())))
    else:
        blf.size(0, points * ui_scale())
    return blf.dimensions(0, text)[0]


def content_width(context) -> float:
    region = getattr(context, "region", None)
    width = region.width if region is not None and region.type == "UI" else DEFAULT_REGION_WIDTH * ui_scale()
    return width - SIDEBAR_MARGIN * ui_scale()


def wrap(text: str, width: float) -> list:
    """``text`` split at spaces into lines no wider than ``width`` pixels (a word longer than a line
    is cut)."""
    lines, cur = [], ""
    for word in text.split():
        cand = f"{cur} {word}" if cur else word
        if cur and text_width(cand) > width:
            lines.append(cur)
            cur = word
        else:
            cur = cand
        while text_width(cur) > width and len(cur) > 1:  # a single over-long word (a path)
            cut = len(cur)
            while cut > 1 and text_width(cur[:cut]) > width:
                cut -= 1
            lines.append(cur[:cut])
            cur = cur[cut:]
    if cur:
        lines.append(cur)
    return lines or [""]


def wrapped(layout, context, text: str, icon: str = "NONE", inset: float = 0.0) -> None:
    """``text`` as labels wrapped to the panel's width (the icon on the first line)."""
    col = layout.column(align=True)
    icon_w = 20 * ui_scale() if icon != "NONE" else 0
    for i, line in enumerate(wrap(text, content_width(context) - inset - icon_w - 8 * ui_scale())):
        col.label(text=line, icon=icon if i == 0 else "BLANK1" if icon != "NONE" else "NONE")


def field(layout, data, prop: str, label: str | None = None):
    """A property as a label column (35 %) and a value column, so that neither is truncated."""
    split = layout.split(factor=LABEL_FACTOR, align=True)
    split.label(text=label if label is not None else data.bl_rna.properties[prop].name)
    split.prop(data, prop, text="")
    return split


# -- results -----------------------------------------------------------------------------------------
def tied_result(context, operators_: tuple, per_object: bool = True) -> dict | None:
    """``scene.meshmark.last_result`` if one of ``operators_`` made it about the active object (any
    result of theirs if not ``per_object``: a study is about files, not an object)."""
    text = context.scene.meshmark.last_result
    if not text:
        return None
    try:
        d = json.loads(text)
    except ValueError:
        return None
    obj = context.active_object
    active = obj.name if obj is not None else None
    if operators.operator_id(d.get("operator", "")) not in operators_ or (per_object and d.get("object") != active):
        return None  # another object's (or another task's) result: stale here
    return d


def result_lines(d: dict) -> list:
    """(text, icon) lines of a result for the result box."""
    if not d.get("ok", True):
        return [(d.get("error", "error"), "ERROR")]
    special = RESULT_LINES.get(operators.operator_id(d.get("operator", "")))
    if special is not None:
        return special(d)
    if "p_false_alarm" in d and "copy" in d:  # meshmark.trace
        return [(f"Copy {d['copy']}" if d["copy"] else "No issued copy", "CHECKMARK" if d["copy"] else "CANCEL"),
                (f"P(false alarm) {d['p_false_alarm']:.2g}", "NONE")]
    if "copies" in d and "registry" in d:  # meshmark.issue_copies
        return [(f"Issued {len(d['copies'])} copies", "CHECKMARK")]
    if "summary" in d:
        s = d["summary"]
        return [(f"Found on {s['detected_frames']}/{s['frames']} frames",
                 "CHECKMARK" if s["detected_frames"] == s["frames"] else "ERROR"),
                (f"Message on {s['message_frames']} frames", "NONE"),
                (f"Bits matching {100 * s['mean_cdr']:.0f}%", "NONE")]
    if "detected" in d:
        out = [("Mark found" if d["detected"] else "No mark found", "CHECKMARK" if d["detected"] else "CANCEL"),
               (f"Bits matching {100 * d['cdr']:.1f}%", "NONE")]
        out.append((f"Message: {d['message']}" if d.get("message_ok") else "Message not recovered", "NONE"))
        return out
    if "stored_cdr" in d:
        ok = d["stored_cdr"] == 1.0 and d.get("stored_message_ok", True)
        return [("Marked" if ok else "Marked, but not every bit reads back", "CHECKMARK" if ok else "ERROR"),
                (f"{d['capacity']} bits in the mesh", "NONE")]
    return []


def _stego_lines(d):
    return [(f"Hidden: {d['bytes']} bytes", "CHECKMARK"), (f"Room for {d['max_bytes']} bytes", "NONE")]


def _reveal_lines(d):
    if not d["found"]:
        return [("Nothing found", "CANCEL"), ("Check key and settings", "NONE")]
    out = [(f"Found {d['bytes']} bytes", "CHECKMARK")]
    if d.get("text") is not None:
        out.append((f"Text: {d['text'][:200]}", "NONE"))
    if d.get("saved"):
        out.append((f"Saved to {d['saved']}", "NONE"))
    return out


def _analysis_lines(d):
    return [(f"Bits needed: {d['level_min']} to {d['level_max']}", "COLOR"),
            (f"Mean {d['level_mean']:.1f} bits", "NONE"),
            (f"Curvature change {d['curvature_change_mean']:.1e}", "NONE")]


def _detect_lines(d):
    verdict = "probably" if d["marked"] else "not found"
    out = [(f"Hidden data: {verdict}", "ERROR" if d["marked"] else "CHECKMARK"),
           (f"Score {d['probability']:.2f}, needs {d.get('threshold', 0.5):.2f}", "NONE")]
    for m, p in list(d["methods"].items())[:3]:
        base, _, variant = m.partition(":")
        label = _params.method_label(base) + (" (auto)" if variant else "")
        out.append((f"{100 * p:.0f}% {label}", "NONE"))
    return out


def _study_lines(d):
    s = d.get("summary") or {}
    return [(f"{s.get('ok', 0)} of {d.get('planned', 0)} tasks ok", "CHECKMARK"),
            (f"Results in {d['output_dir']}", "NONE")]


RESULT_LINES = {"meshmark.stego_embed": _stego_lines, "meshmark.stego_extract": _reveal_lines,
                "meshmark.analyze": _analysis_lines, "meshmark.steganalysis_detect": _detect_lines,
                "meshmark.study": _study_lines}


def draw_result(layout, context, d: dict | None) -> None:
    lines = result_lines(d) if d else []
    if not lines:
        return
    col = layout.box().column(align=True)
    for text, icon in lines:
        wrapped(col, context, text, icon, inset=BOX_MARGIN * ui_scale())


# -- capacity ----------------------------------------------------------------------------------------
def capacity_of_active(obj, settings):
    """(capacity dict or None, text to show instead): never raises."""
    if obj is None or obj.type != "MESH":
        return None, "Select a mesh object"
    try:
        method = settings.method
        p = properties.method_settings(settings, method)
        sig = operators.capacity_signature(obj, method, p, settings.weld)
        hit = operators.CAPACITY_CACHE.get(obj.name)
        if hit is None or hit[0] != sig:
            if len(obj.data.vertices) > AUTO_CAPACITY_MAX_VERTICES or obj.mode == "EDIT":
                return None, "Capacity not counted"
            hit = (sig, operators.capacity_of(obj, method, p, settings.weld))
            operators.CAPACITY_CACHE[obj.name] = hit
        return hit[1], ""
    except Exception as exc:  # a too-small or invalid mesh: say why (in short), never fail drawing
        text = messages.friendly(str(exc), settings.method)
        return None, "Mesh too small to carry a mark" if text.startswith(messages.TOO_SMALL) else text


def capacity_lines(obj, settings) -> list:
    d, why = capacity_of_active(obj, settings)
    if d is None:
        return [why]
    if settings.param_mode == "AUTO":  # the automatic choice: the longest text over its ladder
        fit = d.get("auto_max_text_bytes", d["max_text_bytes"])
        text = f"Fits {fit} byte{'s' if fit > 1 else ''} of text" if fit else "No text fits"
        return ["Automatic settings", text]
    fit = d["max_text_bytes"]
    text = f"Fits {fit} byte{'s' if fit > 1 else ''} of text" if fit else "No text fits"
    return [f"Capacity {d['capacity']} bits", text]


def capacity_line(context, obj, settings) -> str:
    """The capacity as one sentence (scripts, tests)."""
    return ", ".join(capacity_lines(obj, settings))


# -- panels ------------------------------------------------------------------------------------------
class _Sidebar:
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "Meshmark"
    needs: tuple = ()  # operators this panel's task needs (registered only when all are)


class MESHMARK_PT_sidebar(_Sidebar, bpy.types.Panel):
    """The tab's top: the object the tasks work on and the keyfile they share"""
    bl_idname = "MESHMARK_PT_sidebar"
    bl_label = "Meshmark"

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        obj = context.active_object
        if obj is not None and obj.type == "MESH":
            layout.label(text=obj.name, icon="MESH_DATA")
        else:
            layout.label(text="Select a mesh object", icon="INFO")
        field(layout, s, "keyfile")
        row = layout.row(align=True)
        row.operator("meshmark.load_keyfile", text="Load", icon="FILEBROWSER")
        row.operator("meshmark.save_keyfile", text="Save", icon="FILE_TICK")
        d = tied_result(context, ("meshmark.load_keyfile", "meshmark.save_keyfile"))
        if d is not None and not d.get("ok", True):
            draw_result(layout, context, d)


class MESHMARK_PT_watermark(_Sidebar, bpy.types.Panel):
    """Hide a message in the active mesh and check it"""
    bl_idname = "MESHMARK_PT_watermark"
    bl_label = "Watermark"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 0
    needs = ("meshmark.embed", "meshmark.verify", "meshmark.capacity")

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        obj = context.active_object
        col = layout.column()
        field(col, s, "method")
        field(col, s, "message")
        field(col, s, "key")
        col.prop(s, "store_key")
        row = layout.row()
        lines = capacity_lines(obj, s)
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
        row = layout.row()
        row.alignment = "LEFT"
        row.prop(s, "show_advanced", icon="TRIA_DOWN" if s.show_advanced else "TRIA_RIGHT", emboss=False)
        if s.show_advanced:
            draw_advanced(layout.box(), context, s)


def draw_advanced(layout, context, s) -> None:
    """The "Advanced" fold: the chosen method's settings (Auto: chosen for the mesh) and welding."""
    layout.row().prop(s, "param_mode", expand=True)
    if s.param_mode == "AUTO":
        d, _ = capacity_of_active(context.active_object, s)
        if d is not None:
            names = _params.labels(s.method)
            shown = [f"{names[k]} {v:g}" if isinstance(v, float) else f"{names[k]} {v}"
                     for k, v in d["params"].items() if k in names and not isinstance(v, (bool, str))]
            wrapped(layout, context, "Chosen: " + ", ".join(shown), inset=BOX_MARGIN * ui_scale())
    else:
        group = getattr(s.params, s.method, None)
        col = layout.column(align=True)
        for p in _params.method_params(s.method) if group is not None else ():
            if p.kind in ("enum", "str"):
                field(col, group, p.name)
            else:
                col.prop(group, p.name)
    layout.prop(s, "weld")


class MESHMARK_PT_trace(_Sidebar, bpy.types.Panel):
    """Give each recipient a copy with its own mark, and find whose copy a file is"""
    bl_idname = "MESHMARK_PT_trace"
    bl_label = "Trace copies"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 1
    needs = ("meshmark.issue_copies", "meshmark.trace")  # the copy-tracing operators (product)

    def draw(self, context):
        s = context.scene.meshmark
        field(self.layout, s, "registry")
        self.layout.prop(s, "copies")
        row = self.layout.row(align=True)
        row.operator("meshmark.issue_copies", text="Issue", icon="DUPLICATE")
        row.operator("meshmark.trace", text="Trace", icon="VIEWZOOM")
        draw_result(self.layout, context, tied_result(context, self.needs))


def fold(layout, s, prop: str) -> bool:
    """The "Advanced" disclosure row; True when open."""
    row = layout.row()
    row.alignment = "LEFT"
    row.prop(s, prop, icon="TRIA_DOWN" if getattr(s, prop) else "TRIA_RIGHT", emboss=False)
    return getattr(s, prop)


class MESHMARK_PT_stego(_Sidebar, bpy.types.Panel):
    """Hide a text or a file in the mesh, readable only with the key"""
    bl_idname = "MESHMARK_PT_stego"
    bl_label = "Steganography"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 2
    needs = ("meshmark.stego_embed", "meshmark.stego_extract")

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        layout.row().prop(s, "stego_source", expand=True)
        col = layout.column()
        if s.stego_source == "TEXT":
            field(col, s, "stego_text")
        else:
            field(col, s, "stego_file")
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


class MESHMARK_PT_analysis(_Sidebar, bpy.types.Panel):
    """Colour the mesh by the precision each vertex needs and how rounding moves its curvature"""
    bl_idname = "MESHMARK_PT_analysis"
    bl_label = "Analysis"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 3
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


class MESHMARK_PT_steganalysis(_Sidebar, bpy.types.Panel):
    """How likely it is that the mesh hides something"""
    bl_idname = "MESHMARK_PT_steganalysis"
    bl_label = "Steganalysis"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 4
    needs = ("meshmark.steganalysis_detect",)

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        field(layout, s, "model_source")
        if s.model_source == "FILE":
            field(layout, s, "model_file")
        layout.operator("meshmark.steganalysis_detect", text="Check", icon="VIEWZOOM")
        draw_result(layout, context, tied_result(context, self.needs))


class MESHMARK_PT_study(_Sidebar, bpy.types.Panel):
    """Check the mark on every n-th frame of the animation; run a study spec in the background"""
    bl_idname = "MESHMARK_PT_study"
    bl_label = "Study"
    bl_parent_id = "MESHMARK_PT_sidebar"
    bl_order = 5
    needs = ("meshmark.deformation_study",)

    def draw(self, context):
        layout = self.layout
        s = context.scene.meshmark
        col = layout.column(align=True)
        col.prop(s, "frame_start")
        col.prop(s, "frame_end")
        col.prop(s, "frame_step")
        field(layout, s, "output_dir")
        layout.operator("meshmark.deformation_study", text="Check frames", icon="GRAPH")
        draw_result(layout, context, tied_result(context, self.needs))
        if not _operator_registered("meshmark.study"):
            return
        layout.separator()
        field(layout, s, "study_spec")
        field(layout, s, "study_out")
        from . import study_ops
        if study_ops.STATE["running"] is not None:
            layout.prop(s, "study_progress", slider=True)
            layout.label(text="Esc stops the study", icon="INFO")
        else:
            layout.operator("meshmark.study", text="Run study", icon="PLAY")
        draw_result(layout, context, tied_result(context, ("meshmark.study",), per_object=False))


# Every sub-panel, in one place.
SUBPANELS = (MESHMARK_PT_watermark, MESHMARK_PT_trace, MESHMARK_PT_stego, MESHMARK_PT_analysis,
             MESHMARK_PT_steganalysis, MESHMARK_PT_study)
_registered = []


def _operator_registered(idname: str) -> bool:
    mod, name = idname.split(".")
    try:
        getattr(getattr(bpy.ops, mod), name).get_rna_type()
        return True
    except (AttributeError, KeyError):
        return False


def available(cls) -> bool:
    return all(_operator_registered(op) for op in cls.needs)


def register():
    _registered[:] = [MESHMARK_PT_sidebar] + [c for c in SUBPANELS if available(c)]
    for c in _registered:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(_registered):
        bpy.utils.unregister_class(c)
    _registered.clear()
