"""The analysis heat maps as Blender colour attributes, and showing them in the viewport.

``meshmark.analyze`` writes the point attributes ``meshmark_level`` (INT) and
``meshmark_curvature_change`` (FLOAT) and two colour attributes over the mesh's own range (blue few,
white, red many, as Fig. 4.7). :func:`show` makes the chosen one the active colour, and
:func:`show_in_viewports` switches the 3D views of the window to Solid shading coloured by attribute,
so the map is visible without a trip to the shading popover.
"""
from __future__ import annotations

import numpy as np

LEVEL_ATTR, CURV_ATTR = "meshmark_level", "meshmark_curvature_change"
LEVEL_COLOR, CURV_COLOR = "Meshmark precision", "Meshmark curvature change"


def heat_colors(x: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(n, 4) float32 RGBA of ``x`` on a blue (lo) - white - red (hi) ramp, like Fig. 4.7."""
    t = np.clip((np.asarray(x, np.float64) - lo) / (hi - lo), 0.0, 1.0) if hi > lo else np.zeros(len(x))
    rgba = np.empty((len(t), 4), np.float32)
    rgba[:, 0] = np.clip(2.0 * t, 0.0, 1.0)
    rgba[:, 2] = np.clip(2.0 - 2.0 * t, 0.0, 1.0)
    rgba[:, 1] = 1.0 - np.abs(2.0 * t - 1.0)
    rgba[:, 3] = 1.0
    return rgba


def point_attr(me, name, kind):
    a = me.attributes.get(name)
    if a is not None and (a.domain != "POINT" or a.data_type != kind):
        me.attributes.remove(a)
        a = None
    return a if a is not None else me.attributes.new(name, kind, "POINT")


def color_attr(me, name):
    c = me.color_attributes.get(name)
    if c is not None and (c.domain != "POINT" or c.data_type != "FLOAT_COLOR"):
        me.color_attributes.remove(c)
        c = None
    return c if c is not None else me.color_attributes.new(name, "FLOAT_COLOR", "POINT")


def show(obj, which: str) -> None:
    """Make the chosen heat map (``"LEVELS"`` or ``"CURVATURE"``) the active colour attribute."""
    me = obj.data
    c = me.color_attributes.get(LEVEL_COLOR if which == "LEVELS" else CURV_COLOR)
    if c is None:
        return
    try:
        me.color_attributes.active_color = c
    except (AttributeError, TypeError):  # pragma: no cover - older API
        pass
    if hasattr(me.color_attributes, "render_color_index"):
        try:
            me.color_attributes.render_color_index = me.color_attributes.active_color_index
        except Exception:  # pragma: no cover
            pass


def show_in_viewports(screen) -> int:
    """Solid shading coloured by attribute in every 3D view of ``screen``; returns how many were set."""
    n = 0
    for area in getattr(screen, "areas", ()) or ():
        if area.type != "VIEW_3D":
            continue
        sh = area.spaces[0].shading
        if sh.type != "SOLID":
            sh.type = "SOLID"
        names = {e.identifier for e in sh.bl_rna.properties["color_type"].enum_items}
        sh.color_type = "ATTRIBUTE" if "ATTRIBUTE" in names else "VERTEX"  # 4.0+ / 3.x
        area.tag_redraw()
        n += 1
    return n
