"""The result of a task, and running a task's steps (bpy-free)."""
from __future__ import annotations

import json
from dataclasses import dataclass, field

import numpy as np


@dataclass
class Outcome:
    """What a task did.

    ``operator``: the operator it belongs to (``"meshmark.verify"``); ``objects``: the objects it is
    about (in carrier order); ``level``: ``"INFO"`` (done, or found), ``"WARNING"`` (an answer the artist
    should look at: not found, partly done); ``text``: one sentence in words; ``data``: the figures
    (JSON-able; also readable as attributes: ``outcome.detected``); ``warnings``: further sentences.
    """
    operator: str
    objects: list
    level: str
    text: str
    data: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    ok: bool = True

    def __getattr__(self, name):
        data = self.__dict__.get("data")
        if data is not None and name in data:
            return data[name]
        raise AttributeError(name)

    def to_dict(self) -> dict:
        return {**self.data, "operator": self.operator, "ok": self.ok,
                "object": self.objects[0] if self.objects else None, "objects": list(self.objects),
                "report": self.text, "warnings": list(self.warnings)}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), default=json_default)


def failure(operator: str, objects, message: str) -> dict:
    """The result record of a failed operator (``ok: false``)."""
    objects = list(objects or [])
    return {"operator": operator, "ok": False, "error": message, "object": objects[0] if objects else None,
            "objects": objects}


def json_default(o):
    if isinstance(o, np.integer):
        return int(o)
    if isinstance(o, np.floating):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def run(steps, progress=None):
    """Run a task's steps to the end; ``progress(fraction, text)`` is called at each step. Returns the
    task's Outcome."""
    while True:
        try:
            fraction, text = next(steps)
        except StopIteration as done:
            return done.value
        if progress is not None:
            progress(fraction, text)


def operator_id(name: str) -> str:
    """``meshmark.verify`` for ``MESHMARK_OT_verify`` (Blender's internal form of an idname)."""
    if "_OT_" in name:
        mod, op = name.split("_OT_", 1)
        return f"{mod.lower()}.{op}"
    return name
