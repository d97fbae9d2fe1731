"""The result box of each sub-panel: the last result, in words, while its objects are selected.

A result (the session's ``last_result``, JSON) carries the operator and the objects it is about; a
sub-panel shows it only if one of its operators made it and the active object is one of its objects,
so another selection hides it (the JSON stays for scripts).
"""
from __future__ import annotations

import json

from .. import params as _params
from .. import session, words
from ..tasks.outcome import operator_id
from .layout import BOX_MARGIN, ui_scale, wrapped


def tied_result(context, operators_: tuple, per_object: bool = True) -> dict | None:
    """The last result if one of ``operators_`` made it about the active object (any result of theirs
    if not ``per_object``: a study is about files, not an object)."""
    text = session.RESULT["json"]
    if not text:
        return None
    try:
        d = json.loads(text)
    except ValueError:
        return None
    obj = context.active_object
    active = obj.name if obj is not None else None
    if operator_id(d.get("operator", "")) not in operators_:
        return None
    if per_object and active not in (d.get("objects") or [d.get("object")]):
        return None  # another object's result: stale here
    return d


def _embed(d):
    ok = d["stored_cdr"] == 1.0 and d.get("stored_message_ok", True)
    out = [("Marked" if ok else "Marked, but not every bit reads back", "CHECKMARK" if ok else "ERROR"),
           (f"{d['capacity']} bits in the mesh", "NONE")]
    if len(d.get("objects") or []) > 1:
        out.append((f"{len(d['objects'])} objects, one keyfile", "NONE"))
    return out


def _verify(d):
    out = [("Mark found" if d["detected"] else "No mark found", "CHECKMARK" if d["detected"] else "CANCEL"),
           (words.bits_matching(d["cdr"]), "NONE"),
           (f"Message: {d['message']}" if d.get("message_ok") else "Message not recovered", "NONE")]
    if len(d.get("objects") or []) > 1:
        out.append((f"Read {len(d['objects'])} objects as one", "NONE"))
    if d.get("missing_parts"):
        out.append((f"Missing: {words.names(d['missing_parts'])}", "ERROR"))
    if d.get("skipped_modifiers"):
        out.append((f"Read without {words.names(sorted(set(d['skipped_modifiers'])))}", "INFO"))
    return out


def _frames(d):
    s = d["summary"]
    return [(f"Found on {s['detected_frames']}/{s['frames']} frames",
             "CHECKMARK" if s["detected_frames"] == s["frames"] else "ERROR"),
            (f"Message on {s['message_frames']} frames", "NONE"),
            (words.bits_matching(s["mean_cdr"]), "NONE")]


def _trace(d):
    if d["copy"]:
        return [(f"Copy {d['copy']}", "CHECKMARK"), (f"{d['matches']} of {d['n_carriers']} bits agree", "NONE")]
    return [("None of the issued copies", "CANCEL"), (f"{d['n_copies']} copies compared", "NONE")]


def _issue(d):
    return [(f"Issued {words.plural(len(d['copies']), 'copy', 'copies')}", "CHECKMARK"),
            (f"Into {d['output_dir']}", "NONE")]


def _hide(d):
    return [(f"Hidden: {d['bytes']} bytes", "CHECKMARK"), (f"Room for {d['max_bytes']} bytes", "NONE")]


def _reveal(d):
    if not d["found"]:
        return [("Nothing found", "CANCEL"), ("Check key and settings", "NONE")]
    out = [(f"Found {d['bytes']} bytes", "CHECKMARK")]
    if d.get("text") is not None:
        out.append((f"Text: {d['text'][:200]}", "NONE"))
    if d.get("saved"):
        out.append((f"Saved to {d['saved']}", "NONE"))
    return out


def _analysis(d):
    return [(f"Bits needed: {d['level_min']} to {d['level_max']}", "COLOR"),
            (f"Mean {d['level_mean']:.1f} bits", "NONE"),
            (f"Curvature change {d['curvature_change_mean']:.1e}", "NONE")]


def _detect(d):
    state = d.get("state", "marked" if d.get("marked") else "clean")
    if state == "cannot_judge":
        why = (f"Too small: {d.get('n_vertices', 0)} vertices" if d.get("why") == "too_small"
               else "Unlike the meshes it learned from")
        return [("Cannot judge this mesh", "QUESTION"), (why, "NONE")]
    if state == "clean":
        return [("No sign of hidden data", "INFO"), (f"Score {words.score(d['probability'])}", "NONE"),
                ("Weak evidence: it misses much", "NONE")]
    out = [("Something is probably hidden", "ERROR"), (f"Score {words.score(d['probability'])}", "NONE")]
    top = next(iter(d.get("methods") or {}), None)
    if top is not None:
        base, _, variant = top.partition(":")
        out.append((f"Most like {_params.method_label(base)}" + (" (auto)" if variant else ""), "NONE"))
    return out


def _study(d):
    s = d.get("summary") or {}
    failed = s.get("failed", 0)
    out = [(f"{s.get('ok', 0)} of {d.get('planned', 0)} tasks ran", "ERROR" if failed else "CHECKMARK")]
    if failed:
        out.append((f"{failed} failed: see the results", "ERROR"))
    if s.get("mesh_error"):
        out.append((f"{s['mesh_error']} could not take it", "NONE"))
    out.append((f"Results in {d['output_dir']}", "NONE"))
    return out


RESULT_LINES = {"meshmark.embed": _embed, "meshmark.verify": _verify, "meshmark.deformation_study": _frames,
                "meshmark.trace": _trace, "meshmark.issue_copies": _issue, "meshmark.stego_embed": _hide,
                "meshmark.stego_extract": _reveal, "meshmark.analyze": _analysis,
                "meshmark.steganalysis_detect": _detect, "meshmark.study": _study}


def result_lines(d: dict) -> list:
    """(text, icon) lines of a result for the result box."""
    if not d.get("ok", True):
        return [(d.get("error", "error"), "ERROR")]
    special = RESULT_LINES.get(operator_id(d.get("operator", "")))
    return special(d) if special is not None else []


def draw_result(layout, context, d: dict | None) -> None:
    lines = result_lines(d) if d else []
    if not lines:
        return
    col = layout.box().column(align=True)
    for text, icon in lines:
        wrapped(col, context, text, icon, inset=BOX_MARGIN * ui_scale())
