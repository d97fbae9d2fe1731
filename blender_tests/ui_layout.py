"""A UILayout stand-in that records what a panel draws and checks that no text is truncated.

:class:`RecordingLayout` wraps a real ``UILayout`` (in a window: every call is forwarded, so the panel
is drawn as usual) or nothing (the bpy module has no window). It checks each call as Blender would
(``prop`` must name an RNA property, ``operator`` a registered operator) and keeps the layout tree.
:func:`measure` then gives every text its slot: a column passes its width on, a box takes its
padding off, a row shares its width among its items (an icon-only button takes one UI unit), a split
gives its first item ``factor`` of the width; and the width each text needs: ``blf.dimensions`` of the
text in the UI font at the UI scale, plus the widget's padding and icon. A text whose need exceeds
its slot would be cut with an ellipsis ("Meth…").

The paddings are Blender's (``UI_UNIT_X`` = 20 px per icon, 8 px text margin per side on buttons
and fields, 4 on labels) at UI scale 1, scaled like the fonts.
"""
from __future__ import annotations

import bpy

UNIT = 20.0
BUTTON_PAD = 8.0
LABEL_PAD = 4.0
BOX_PAD = 12.0
# What the sidebar takes from its region's width beyond a panel's content: the category tabs and the
# panel margins (measured on Blender 3.4's screenshot: a 229 px region, buttons 172 px wide).
SIDEBAR_MARGIN = 57.0


def scale() -> float:
    return (getattr(bpy.context.preferences.system, "dpi", 72) or 72) / 72.0


def text_width(text: str) -> float:
    """Pixels of ``text`` in the UI's widget font (independent of the add-on's own helper)."""
    import blf
    points = bpy.context.preferences.ui_styles[0].widget.points or 11
    if bpy.app.version < (4, 0, 0):
        blf.size(0, points, int(round(72 * scale())))
    else:
        blf.size(0, points * scale())
    return float(blf.dimensions(0, text)[0])


class Item:
    def __init__(self, kind, text, need, detail=""):
        self.kind, self.text, self.need, self.detail = kind, text, need, detail
        self.icon_only = False
        self.slot = None


def _prop_item(data, name, text, icon, expand, emboss):
    rna = data.bl_rna.properties[name]
    label = rna.name if text is None else text
    value = getattr(data, name)
    s = scale()
    icon_w = UNIT * s if icon not in (None, "NONE") else 0.0
    if rna.type == "BOOLEAN":
        box = 0.0 if icon_w else UNIT * s  # a checkbox, or the icon of a toggle
        return [Item("prop", label, text_width(label) + box + icon_w + BUTTON_PAD * s, name)]
    if rna.type == "ENUM":
        items = {e.identifier: e.name for e in rna.enum_items}
        if expand:
            return [Item("prop", items[e], text_width(items[e]) + 2 * BUTTON_PAD * s, name) for e in items]
        shown = items.get(value) or bpy.types.UILayout.enum_item_name(data, name, value) or str(value)
        lab = f"{label}: " if label else ""
        return [Item("prop", lab + shown, text_width(lab + shown) + 2 * BUTTON_PAD * s + UNIT * s, name)]
    if rna.type in ("INT", "FLOAT"):
        v = f"{value:.{rna.precision}f}" if rna.type == "FLOAT" else str(value)
        # label left, value right, the arrows' room and the margins (calibrated on 3.4: "Regularisation
        # 0.000010" is cut in a 164 px field)
        need = (text_width(label) + text_width(v) + (2 * UNIT + BUTTON_PAD) * s if label
                else text_width(v) + 2 * UNIT * s)
        return [Item("prop", f"{label} {v}".strip(), need, name)]
    # text fields: the value is the user's; the label (if any) is drawn beside it, the browse button
    # of a path takes one unit; the field itself must keep room for a few letters
    browse = UNIT * s if rna.subtype in ("FILE_PATH", "DIR_PATH") else 0.0
    need = (text_width(label) + BUTTON_PAD * s if label else 0.0) + browse + 3 * UNIT * s
    return [Item("prop", label, need, name)]


class RecordingLayout:
    """See the module docstring. ``node``: (kind, factor, children) of this layout."""

    def __init__(self, real=None, kind="column", factor=None):
        object.__setattr__(self, "_real", real)
        object.__setattr__(self, "kind", kind)
        object.__setattr__(self, "factor", factor)
        object.__setattr__(self, "children", [])

    # attributes such as enabled, active, alignment go to the real layout
    def __setattr__(self, name, value):
        if self._real is not None:
            setattr(self._real, name, value)
        object.__setattr__(self, name, value)

    def _child(self, kind, method, *a, **kw):
        real = getattr(self._real, method)(*a, **kw) if self._real is not None else None
        c = RecordingLayout(real, kind, kw.get("factor", 0.5) if kind == "split" else None)
        self.children.append(c)
        return c

    def row(self, *a, **kw):
        return self._child("row", "row", *a, **kw)

    def column(self, *a, **kw):
        return self._child("column", "column", *a, **kw)

    def box(self, *a, **kw):
        return self._child("box", "box", *a, **kw)

    def split(self, *a, **kw):
        return self._child("split", "split", *a, **kw)

    def prop(self, data, name, text=None, icon="NONE", expand=False, emboss=True, **kw):
        assert name in data.bl_rna.properties, f"{data} has no property {name!r}"
        items = _prop_item(data, name, text, icon, expand, emboss)
        if expand:  # an expanded enum is a row of buttons
            row = RecordingLayout(None, "row")
            row.children.extend(items)
            self.children.append(row)
        else:
            self.children.extend(items)
        if self._real is not None:
            args = {k: v for k, v in dict(text=text, icon=icon, expand=expand, emboss=emboss, **kw).items()
                    if v is not None}
            self._real.prop(data, name, **args)

    def operator(self, idname, text=None, icon="NONE", **kw):
        mod, op = idname.split(".")
        rna = getattr(getattr(bpy.ops, mod), op).get_rna_type()  # KeyError if not registered
        label = rna.name if text is None else text
        s = scale()
        icon_w = UNIT * s if icon != "NONE" else 0.0
        it = Item("operator", label, (text_width(label) + 2 * BUTTON_PAD * s if label else 0.0) + icon_w, idname)
        it.icon_only = not label
        self.children.append(it)
        if self._real is not None:
            return self._real.operator(idname, text=label, icon=icon, **kw)
        return None

    def label(self, text="", icon="NONE", **kw):
        assert isinstance(text, str)
        s = scale()
        icon_w = UNIT * s if icon != "NONE" else 0.0
        it = Item("label", text, (text_width(text) + 2 * LABEL_PAD * s if text else 0.0) + icon_w, icon)
        it.icon_only = not text
        self.children.append(it)
        if self._real is not None:
            self._real.label(text=text, icon=icon, **kw)

    def separator(self, *a, **kw):
        if self._real is not None:
            self._real.separator(*a, **kw)


def measure(layout: RecordingLayout, width: float) -> list:
    """Every Item under ``layout`` with its ``slot`` (pixels) set; ``width``: the content width."""
    out = []
    s = scale()

    def walk(node, w):
        if isinstance(node, Item):
            node.slot = w
            out.append(node)
            return
        kids = node.children
        if node.kind == "box":
            for k in kids:
                walk(k, w - BOX_PAD * s)
        elif node.kind == "row" and kids:
            fixed = [k for k in kids if isinstance(k, Item) and k.icon_only]
            rest = [k for k in kids if k not in fixed]
            free = w - UNIT * s * len(fixed)
            for k in kids:
                walk(k, UNIT * s if k in fixed else free / max(len(rest), 1))
        elif node.kind == "split" and kids:
            f = node.factor
            for i, k in enumerate(kids):
                walk(k, w * f if i == 0 else w * (1 - f) / max(len(kids) - 1, 1))
        else:
            for k in kids:
                walk(k, w)

    walk(layout, width)
    return out


def truncated(items: list) -> list:
    """The items whose text needs more than its slot: (text, need, slot)."""
    return [(i.text, round(i.need, 1), round(i.slot, 1)) for i in items if i.text and i.need > i.slot + 0.5]


class PanelSelf:
    """Stands for a Panel instance in ``Panel.draw(self, context)``, with a recording layout."""

    def __init__(self, panel, layout: RecordingLayout):
        object.__setattr__(self, "_panel", panel)
        object.__setattr__(self, "layout", layout)

    def __getattr__(self, name):
        return getattr(self._panel, name)


def draw_recorded(cls, context, real_layout=None, panel=None) -> RecordingLayout:
    """Run ``cls.draw`` into a recording layout (forwarding to ``real_layout`` if given)."""
    rec = RecordingLayout(real_layout)
    cls.draw(PanelSelf(panel if panel is not None else cls, rec), context)
    return rec
