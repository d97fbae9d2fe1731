"""Method parameters as the panel and the operators see them (bpy-free).

Each method in ``meshmark.watermark.METHODS`` has a ``DEFAULTS`` dict (in its module, or as an
attribute) with the thesis defaults. A default of ``None`` means "computed from the mesh" (e.g.
the Laplacian method's ``K = ceil(N/70)``): the UI shows it as an integer where 0 means automatic.
"""
from __future__ import annotations

import sys

from meshmark.watermark import METHODS

# Labels and help for known parameters; unknown ones get their name.
DESCRIPTIONS = {
    "K": ("Bins", "Number of histogram bins (0 = automatic: ceil(N/70), thesis §7.4)"),
    "n_thr": ("Min. pair size", "Minimum elements in a valid bin pair, eq. 7.1.8 (thesis: 46)"),
    "n_robust": ("Robustness", "Margin divisor of eq. 7.2.16 (thesis: 5)"),
    "eps": ("Epsilon", "Regularisation of the Kirchhoff matrix, eq. 7.1.4 (thesis: 1e-5)"),
    "thesis_exact": ("Thesis exact", "Run the thesis algorithm to the letter (no robustness fixes)"),
    "carrier": ("Carrier", "Laplacian scalar that is binned: 'local' (||L|| over the 1-ring's mean edge length, "
                           "default), 'thesis' (over the global mean edge length, eq. 7.1.5), 'normal', "
                           "'normal_global', 'cot_local', 'cot_normal' (docs/carrier.md)"),
    "solver": ("Solver", "Reconstruction: 'iterative' (PCG rounds until every carrier holds its margin) "
                         "or 'direct' (one exact sparse solve, thesis §7.2.2)"),
}


class Param:
    """One method parameter: ``name``, ``kind`` ('int', 'float', 'bool'), UI ``default``, ``auto``
    (a None default: 0 in the UI means 'let the method choose')."""

    def __init__(self, name, default):
        self.name = name
        self.auto = default is None
        if isinstance(default, bool):
            self.kind, self.default = "bool", default
        elif default is None or isinstance(default, int):
            self.kind, self.default = "int", 0 if default is None else int(default)
        elif isinstance(default, float):
            self.kind, self.default = "float", float(default)
        else:
            self.kind, self.default = "str", str(default)
        self.label, self.description = DESCRIPTIONS.get(name, (name, name))

    def to_method(self, value):
        """The value the method receives (None for 'automatic')."""
        if self.auto and not value:
            return None
        if self.kind == "float" and abs(value - self.default) <= 1e-6 * abs(self.default):
            return self.default  # Blender stores floats as float32: keep the exact default (1e-5)
        return {"int": int, "float": float, "bool": bool, "str": str}[self.kind](value)


def method_defaults(name: str) -> dict:
    m = METHODS[name]
    d = getattr(m, "DEFAULTS", None)
    if d is None:
        d = getattr(sys.modules[type(m).__module__], "DEFAULTS", {})
    return dict(d)


def method_params(name: str) -> list:
    return [Param(k, v) for k, v in method_defaults(name).items()]


def all_params() -> dict:
    """name -> Param over every method (the first method defining a name wins)."""
    out = {}
    for name in METHODS:
        for p in method_params(name):
            out.setdefault(p.name, p)
    return out
