"""Drawing helpers that keep every text inside the default sidebar width.

Fields are drawn as a label column and a value column (:func:`field`), long texts (results, errors)
are wrapped to the region's width measured with ``blf`` (:func:`wrapped`), disclosure rows with
:func:`fold`.
"""
from __future__ import annotations

import bpy

# Horizontal space the sidebar takes from its region beyond a panel's content (category tabs and
# panel margins), in pixels at UI scale 1 (Blender 3.4: a 229 px region holds 172 px of content).
SIDEBAR_MARGIN = 60
BOX_MARGIN = 12
DEFAULT_REGION_WIDTH = 229  # the sidebar's width in a new window (no region in background mode)
LABEL_FACTOR = 0.35  # label column of a field


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


def path_field(layout, data, prop: str, label: str):
    """A path as a label line ("Save the results to:") above a full-width field."""
    col = layout.column(align=True)
    col.label(text=label)
    col.prop(data, prop, text="")
    return col


def fold(layout, s, prop: str) -> bool:
    """The "Advanced" disclosure row; True when open."""
    row = layout.row()
    row.alignment = "LEFT"
    row.prop(s, prop, icon="TRIA_DOWN" if getattr(s, prop) else "TRIA_RIGHT", emboss=False)
    return getattr(s, prop)
