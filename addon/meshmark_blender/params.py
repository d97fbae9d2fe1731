"""Method parameters as the panel and the operators see them (bpy-free).

Each method in ``meshmark.watermark.METHODS`` has its defaults in a ``DEFAULTS`` dict (its module, or
an attribute) or a ``defaults`` attribute. A default of ``None`` means "computed from the mesh" (e.g.
the Laplacian method's number of bins): the UI shows it as a number where 0 means automatic.

Labels and tooltips are in an artist's words; the parameter each label stands for, and the thesis
equation behind it, are listed in docs/blender.md ("The panel").
"""
from __future__ import annotations

import sys

from meshmark.watermark import METHODS

# (label, tooltip) per parameter name; METHOD_DESCRIPTIONS overrides them for one method.
DESCRIPTIONS = {
    "K": ("Bins", "How finely the mesh's detail is sorted. More bins make room for a longer message, "
                  "but each bit is easier to break. 0 = chosen from the mesh size"),
    "n_thr": ("Min. pair size", "Fewest vertices a pair of bins needs to carry a bit. Lower it to fit "
                                "more on a small mesh; higher is sturdier"),
    "n_robust": ("Lightness", "How lightly each bit touches the mesh: higher moves it less, but the mark "
                              "breaks more easily when the mesh is posed. 1 is the sturdiest"),
    "eps": ("Stability", "A tiny safety term in the maths behind the mark. Leave it as it is"),
    "thesis_exact": ("As published", "Run the algorithm exactly as published, without meshmark's "
                                     "robustness fixes (for comparisons: the mark breaks more easily)"),
    "solver": ("Solver", "How the marked shape is computed"),
    "carrier": ("Carrier", "Which detail of the surface holds the mark. Local survives posing best"),
    "alpha": ("Strength", "How far each bit is pushed: higher survives more, but moves the mesh more"),
    "delta_k": ("Search step", "Step of the search for each bit's shape change: smaller is finer but "
                               "slower"),
    "guard": ("Edge guard", "Keeps moved vertices off the bin edges so that every bit reads back. "
                            "0 = automatic"),
    "center_iters": ("Re-centre passes", "Extra passes that keep the mesh's centre where it was before "
                                         "marking. 0 = automatic"),
    "origin_mode": ("Centre", "Which centre the distances are measured from"),
    "origin_iters": ("Re-centre passes", "Extra passes that keep the centre where it was before "
                                         "marking (0 = none)"),
}
METHOD_DESCRIPTIONS = {
    ("radial", "K"): ("Bins", "How many distance rings the mesh is sorted into. More rings make room for "
                              "a longer message, but each bit is easier to break"),
    ("radial", "n_thr"): ("Strength", "How many vertices change ring for each bit: higher survives more, "
                                      "but moves the mesh more. 0 = chosen from the mesh size"),
}
# Every choice is a menu: (identifier the method takes, label, tooltip).
CHOICES = {
    "carrier": [("local", "Local", "Detail measured against each vertex's own edges: survives posing "
                                   "(the default)"),
                ("thesis", "As published", "Detail measured against the mesh's mean edge length"),
                ("normal", "Normal", "Signed detail along the surface normal"),
                ("normal_global", "Normal, global", "Signed detail along the normal, mean edge length"),
                ("cot_local", "Cotangent", "Cotangent-weighted detail, local edges"),
                ("cot_normal", "Cotangent normal", "Cotangent-weighted detail along the normal")],
    "solver": [("iterative", "Iterative", "Refine until every bit holds (fast, the default)"),
               ("direct", "Direct", "One exact solve (slower on large meshes)")],
    "origin_mode": [("axis", "Main axis", "A point on the mesh's main axis: the mark survives a twist "
                                         "around it"),
                    ("vertices", "Vertices", "The mean of the vertices on one side of the mesh")],
}
# Parameters kept out of the panel (scripts can still pass them): nothing an artist should tune.
HIDDEN = {"eps"}
# Kind of a parameter whose default is None ("automatic"); int unless listed.
AUTO_KINDS = {"guard": "float"}

# The method menu, in the order shown, with its tooltips.
METHOD_INFO = {
    "laplacian": ("Laplacian", "Survives posing, skinning and re-export: the method for characters"),
    "radial": ("Radial", "Distances from a centre on the main axis: survives moving, scaling and twisting, "
                         "not bending"),
    "cho-mean": ("Cho mean", "Distances from the centre (Cho et al., mean): lost when the mesh is posed"),
    "cho-variance": ("Cho variance", "Distances from the centre (Cho et al., variance): lost when the mesh is "
                                     "posed"),
}


def method_label(name: str) -> str:
    return METHOD_INFO.get(name, (name.replace("-", " ").capitalize(), ""))[0]


def method_items() -> list:
    """(identifier, label, tooltip) of every registered method, the known ones first."""
    names = [n for n in METHOD_INFO if n in METHODS] + [n for n in METHODS if n not in METHOD_INFO]
    return [(n, method_label(n), METHOD_INFO.get(n, ("", f"The {n} watermark"))[1]) for n in names]


def describe(method: str | None, name: str) -> tuple:
    """(label, tooltip) of parameter ``name`` for ``method``."""
    return METHOD_DESCRIPTIONS.get((method, name)) or DESCRIPTIONS.get(name, (name, name))


class Param:
    """One method parameter: ``name``, ``kind`` ('int', 'float', 'bool', 'enum', 'str'), UI
    ``default``, ``auto`` (a None default: 0 in the UI means 'let the method choose')."""

    def __init__(self, name, default, method: str | None = None):
        self.name = name
        self.auto = default is None
        kind = AUTO_KINDS.get(name, "int") if default is None else None
        if isinstance(default, bool):
            self.kind, self.default = "bool", default
        elif kind == "float" or isinstance(default, float):
            self.kind, self.default = "float", 0.0 if default is None else float(default)
        elif default is None or isinstance(default, int):
            self.kind, self.default = "int", 0 if default is None else int(default)
        elif name in CHOICES:
            self.kind, self.default = "enum", str(default)
        else:
            self.kind, self.default = "str", str(default)
        self.label, self.description = describe(method, name)
        self.items = CHOICES.get(name)

    def to_method(self, value):
        """The value the method receives (None for 'automatic')."""
        if self.auto and not value:
            return None
        if self.kind == "float" and abs(value - self.default) <= 1e-6 * abs(self.default):
            return self.default  # Blender stores floats as float32: keep the exact default (1e-5)
        return {"int": int, "float": float, "bool": bool, "str": str, "enum": str}[self.kind](value)


def method_defaults(name: str) -> dict:
    m = METHODS[name]
    d = getattr(m, "DEFAULTS", None) or getattr(m, "defaults", None)
    if d is None:
        d = getattr(sys.modules[type(m).__module__], "DEFAULTS", {})
    return dict(d)


def method_params(name: str) -> list:
    return [Param(k, v, name) for k, v in method_defaults(name).items()]


def panel_params(name: str) -> list:
    """The parameters the panel shows for method ``name`` (not :data:`HIDDEN`)."""
    return [p for p in method_params(name) if p.name not in HIDDEN]


def labels(method: str | None) -> dict:
    """parameter name -> the label the panel shows, for ``method`` (every method's if None)."""
    names = method_defaults(method) if method in METHODS else {n: None for m in METHODS for n in method_defaults(m)}
    return {n: describe(method, n)[0] for n in names}


def all_params() -> dict:
    """name -> Param over every method (the first method defining a name wins)."""
    out = {}
    for name in METHODS:
        for p in method_params(name):
            out.setdefault(p.name, p)
    return out
