"""Embed, verify and capacity on a :class:`~meshmark_blender.targets.Target`, and the automatic choice.

Embed computes everything and checks the float32 result (what Blender stores) and writes the keyfile
before it writes a single coordinate; a failure leaves every object bit-identical. The keyfile records
the objects it covers (``mesh.parts``). Verify reads the objects as posed now through their deforming
modifiers only (:func:`~meshmark_blender.bridge.cage_only`): the mark is in the base mesh, a live
Subdivision is left out of the check and named.
"""
from __future__ import annotations

import os
import time

import numpy as np

import meshmark
from meshmark import MeshError
from meshmark.watermark import METHODS, embed as wm_embed, extract as wm_extract, load_keyfile, save_keyfile
from meshmark.watermark.auto import choose, longest_payload_bits
from meshmark.watermark.coding import max_data_bits, min_carriers
from meshmark.watermark.framework import MIN_CARRIERS, check_detectable
from meshmark.watermark.keyfile import KeyRequired
from meshmark.watermark.payload import MAX_DATA_BITS, Payload

from .. import bridge, keyfiles, session, targets, words
from .outcome import Outcome

EMBED, VERIFY, CAPACITY = "meshmark.embed", "meshmark.verify", "meshmark.capacity"


def payload_of(message: str | None, bits: str | None):
    """The payload (a Payload, or the text) and a short description of it."""
    if bits:
        return Payload.from_bits(bits), f"{len(bits)} bits"
    if not message:
        raise MeshError("the message is empty: type a message to hide")
    return message, f"'{message}'"


def payload_bits(message: str | None, bits: str | None = None) -> int:
    """Bits of the payload Embed would hide (8, one letter, while the message is empty)."""
    try:
        return int(Payload.coerce(Payload.from_bits(bits) if bits else (message or "m")).data.size)
    except (MeshError, ValueError):
        return 8


def read_keyfile(path: str, key: str | None = None):
    """Load a keyfile; one written without its key takes ``key`` or the panel's key."""
    try:
        return load_keyfile(path, key=key)
    except KeyRequired:
        key = key or session.KEY["value"]
        if not key:
            raise MeshError(f"the keyfile '{os.path.basename(path)}' holds no key (it was written with Store key "
                            "off): type the key in the panel") from None
        return load_keyfile(path, key=key)


def modifier_notes(target) -> list:
    """Sentences about live modifiers that Verify leaves out (the mark is in the base mesh)."""
    out = []
    for o in target.objects:
        mods = [m.name for m in bridge.reshaping_modifiers(o)]
        if mods:
            out.append(f"{words.names(mods)} on '{o.name}' is not applied: the mark goes into its "
                       f"{len(o.data.vertices)} base vertices, and Verify reads them posed, without {words.names(mods)}")
    return out


def parts_note(context, target) -> str | None:
    """A warning when the target is part of a character whose other parts are left out."""
    rest = targets.left_out(context, target)
    if not rest:
        return None
    n = len(rest) + len(target.objects)
    return (f"{target.quoted} {'is' if len(target.objects) == 1 else 'are'} only part of a character of {n} skinned "
            f"objects ({words.names(rest)} left out): the mark then lives in fewer vertices and is read less "
            "reliably once posed. Select all its parts (the button below the object's name) to mark the character as one")


def welded(mesh, weld: bool):
    return meshmark.weld_vertices(mesh).mesh if weld else mesh


def plan(target, method: str, message=None, bits=None, params="auto", weld: bool = True, method_params=None) -> dict:
    """What Embed will use for this message: the parameters ``meshmark.watermark.embed`` chooses
    (the same :func:`meshmark.watermark.auto.choose` call on the same welded, joined mesh), its
    capacity, and the longest message that fits in this mode."""
    if method not in METHODS:
        raise MeshError(f"unknown method {method!r}")
    joined = target.base()
    mesh = welded(joined.mesh, weld)
    given = dict(method_params or {})
    p, ids, _, choice = choose(mesh, METHODS[method], params, given, payload_bits(message, bits))
    if params == "auto":
        longest = longest_payload_bits(mesh, METHODS[method], {k: v for k, v in given.items() if v is not None})
    else:
        longest = max_data_bits(len(ids))
    fit = min(longest, MAX_DATA_BITS)
    return {"method": method, "params": p, "choice": choice, "capacity": int(len(ids)), "n_vertices": mesh.n_vertices,
            "n_input_vertices": joined.mesh.n_vertices, "weld": bool(weld), "max_message_bits": fit,
            "max_text_bytes": fit // 8, "params_mode": params if isinstance(params, str) else "custom"}


def precheck(target, method, message=None, bits=None, params="auto", weld=True, method_params=None) -> dict:
    """The refusals Embed would make about the mesh and the message (too small, too long), found
    without embedding (before a file browser or a dialog opens); returns the :func:`plan`."""
    payload_of(message, bits)
    d = plan(target, method, message, bits, params, weld, method_params)
    cap, m = d["capacity"], METHODS[method]
    what = f"the {method} method with {m.describe(d['params'])}"
    if cap < MIN_CARRIERS:
        raise MeshError(f"the mesh offers only {cap} carrier bits to {what}; at least {MIN_CARRIERS} are needed")
    check_detectable(cap, what)
    n = payload_bits(message, bits)
    if min_carriers(n) > cap:
        raise MeshError(f"the message needs {min_carriers(n)} carrier bits ({n} data + check bits) but the mesh offers "
                        f"{cap} with the {method} method ({m.describe(d['params'])}); at most {max_data_bits(cap)} "
                        "payload bits fit")
    return d


def capacity_steps(context, target, method, message=None, bits=None, params="auto", weld=True, method_params=None):
    yield 0.1, f"Counting the room in {target.label}"
    d = plan(target, method, message, bits, params, weld, method_params)
    room = (f"up to {d['max_text_bytes']} bytes of text fit" if d["max_text_bytes"] else "not even one letter fits")
    text = f"{target.quoted} can carry {d['capacity']} bits with the {method} method: {room}"
    return Outcome(CAPACITY, target.names, "INFO", text, d, modifier_notes(target))


def embed_steps(context, target, *, message=None, bits=None, key=None, keyfile="", method="laplacian", params="auto",
                weld=True, store_key=True, overwrite=False, method_params=None, dry=False):
    """Embed (see the module doc); ``dry``: compute and check everything, write nothing."""
    payload, what = payload_of(message, bits)
    if not key:
        raise MeshError("the key is empty: type a secret key")
    shown = keyfile or keyfiles.for_objects(target.objects)
    path = keyfiles.abspath(shown) if dry else keyfiles.resolve(shown)  # a dry run checks the mesh first
    if path is not None and not os.path.isdir(os.path.dirname(path)):
        raise MeshError(f"cannot write the keyfile '{path}': the folder does not exist")
    if path is not None and os.path.exists(path) and not overwrite and not dry:
        raise MeshError(f"the keyfile '{os.path.basename(path)}' already exists: "
                        + " ".join(keyfiles.what_is_lost(path, key)) + " Confirm to replace it, or choose another keyfile")
    notes = modifier_notes(target)
    part = parts_note(context, target)
    yield 0.05, f"Reading {target.label}"
    joined = target.base()
    mesh = joined.mesh
    yield 0.15, f"Marking {target.label}"
    t0 = time.perf_counter()
    res = wm_embed(mesh, payload=payload, key=key, method=method, weld=weld, params=params, store_key=store_key,
                   **(method_params or {}))
    t_native = time.perf_counter() - t0
    D = res.V - mesh.V
    stored = (mesh.V + D).astype(np.float32).astype(np.float64)  # what Blender will store, checked first
    check = wm_extract(mesh.with_vertices(stored), keyfile=res.keyfile)
    if dry:
        return None
    yield 0.9, "Writing the keyfile"
    res.keyfile.mesh["parts"] = target.record(joined)
    save_keyfile(res.keyfile, path, overwrite=overwrite)  # may fail: the objects are still untouched
    for obj, d in zip(target.objects, joined.split(D)):
        bridge.apply_displacement(obj, d)  # the only writes
    keyfiles.remember(target.objects, keyfiles.display(path))
    session.LAST["keyfile"] = res.keyfile
    disp = float(np.linalg.norm(D, axis=1).max()) / max(bridge.bbox_diagonal(mesh.V), 1e-300)
    data = {"keyfile": path, "n_vertices": mesh.n_vertices, **res.to_dict(), "stored_cdr": check.cdr,
            "stored_message_ok": check.message_ok, "max_disp_rel": disp, "seconds_native": t_native,
            "parts": target.record(joined)}
    ok = check.message_ok and check.cdr == 1.0
    text = (f"Marked {target.quoted} with {what} ({res.capacity} bits in the mesh"
            + ("" if ok else f", {words.percent(check.cdr)} read back as stored") + f"); keyfile {keyfiles.display(path)}")
    return Outcome(EMBED, target.names, "INFO" if ok and not part else "WARNING", text, data,
                   notes + ([part] if part else []))


def verify_steps(context, chosen, *, keyfile="", key=None, evaluated=True):
    path = keyfiles.resolve(keyfile or keyfiles.for_objects(chosen.objects))
    if not os.path.isfile(path):
        raise MeshError(f"there is no keyfile '{keyfiles.display(path)}': choose the keyfile of this object "
                        "(Keyfile field, or Load)")
    kf = read_keyfile(path, key)
    target, parts = targets.for_keyfile(context, kf, chosen)
    yield 0.1, f"Reading {target.label}"
    skipped = []
    t0 = time.perf_counter()
    if evaluated:
        with bridge.cage_only(target.objects) as skipped:
            joined = target.evaluated(context)
    else:
        joined = target.base()
    mesh = joined.mesh
    yield 0.4, f"Looking for the mark in {target.label}"
    res = wm_extract(mesh, keyfile=kf, key=key or None)
    t_native = time.perf_counter() - t0
    warnings = list(res.warnings)
    if skipped:
        warnings.append(f"read without {words.names(sorted({m for _, m in skipped}))} (not applied: the mark is "
                        "in the base mesh)")
    if parts["missing"]:
        warnings.append(f"{words.names(parts['missing'])} (marked with the others) "
                        f"{'is' if len(parts['missing']) == 1 else 'are'} not in the scene: read without")
    if parts["changed"]:
        warnings.append(f"changed since marking: {words.names(parts['changed'])}")
    data = {"keyfile": path, "evaluated": bool(evaluated), "frame": context.scene.frame_current,
            "n_input_vertices": mesh.n_vertices, **res.to_dict(), "welded": res.n_merged > 0,
            "seconds_native": t_native, "skipped_modifiers": [m for _, m in skipped],
            "missing_parts": parts["missing"], "changed_parts": parts["changed"]}
    if not res.detected and (not res.same_vertex_count or parts["missing"]):
        why = (f"{words.names(parts['missing'])} {'is' if len(parts['missing']) == 1 else 'are'} missing"
               if parts["missing"] else
               f"{target.quoted} {'has' if len(target.objects) == 1 else 'have'} {res.n_vertices} vertices"
               + (f" after welding ({mesh.n_vertices} as stored)" if res.n_merged else "")
               + f" but the keyfile was made for a mesh of {res.expected_vertices}")
        raise VerifyMismatch(f"{why}, and the mark is not found ({words.bits_matching(res.cdr).lower()}): Verify is "
                             "run on a different mesh, or with the wrong keyfile", data)
    if res.detected:
        msg = f"message '{res.message}'" if res.message_ok else "message not recovered"
        text = f"Mark found in {target.quoted}: {msg} ({words.false_alarm(res.p_false_alarm)})"
        return Outcome(VERIFY, target.names, "INFO", text, data, warnings)
    text = (f"No mark found in {target.quoted} with this keyfile ({words.bits_matching(res.cdr).lower()}, as for "
            "an unmarked mesh)")
    return Outcome(VERIFY, target.names, "WARNING", text, data, warnings)


class VerifyMismatch(MeshError):
    """Verify ran on a mesh that is not the keyfile's (and found no mark); ``data`` holds the figures."""

    def __init__(self, message, data):
        super().__init__(message)
        self.data = data
