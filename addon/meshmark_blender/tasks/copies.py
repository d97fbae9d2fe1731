"""Copy tracing from Blender (meshmark.watermark.tracing): issue marked copies, trace a copy.

Issue writes one marked copy per recipient as a file (the objects themselves are not changed) and
records its codeword in the registry; a character of several objects is one carrier and each copy
file holds all its parts (one mesh, the parts in the target's order). It works one copy per step, so
the window stays responsive and Esc stops it: the copies issued so far stay recorded and written.
Trace reads the objects as posed now (deforming modifiers only) or their base mesh.
"""
from __future__ import annotations

import os

import meshmark
from meshmark import MeshError
from meshmark.watermark import tracing

from .. import bridge, keyfiles, session, words
from .outcome import Outcome
from .watermark import parts_note

ISSUE, TRACE = "meshmark.issue_copies", "meshmark.trace"
FORMATS = ("obj", "ply", "off", "stl")


def issue_steps(context, target, *, copies=10, key=None, registry="", output_dir="", file_format="obj",
                store_key=True, method="laplacian", params="auto"):
    if not key:
        raise MeshError("the key is empty: type a secret key")
    if not isinstance(copies, int) or copies < 1:
        raise MeshError(f"the number of copies must be 1 or more, got {copies}")
    if file_format not in FORMATS:
        raise MeshError(f"the copies' format must be one of {', '.join(FORMATS)}, got {file_format!r}")
    reg = keyfiles.resolve(registry, "registry") if registry else ""
    if not reg:
        raise MeshError("choose the registry file that records the copies (Registry)")
    if not os.path.isdir(os.path.dirname(reg)):
        raise MeshError(f"cannot write the registry '{reg}': its folder does not exist")
    out = keyfiles.resolve(output_dir, "folder for the copies") if output_dir else ""
    if not out:
        raise MeshError("choose the folder the copies go to (Copies to)")
    if not os.path.isdir(out):
        if not os.path.isdir(os.path.dirname(out.rstrip(os.sep))):
            raise MeshError(f"the folder for the copies '{out}' cannot be made: its parent does not exist")
        os.makedirs(out, exist_ok=True)
    yield 0.0, f"Reading {target.label}"
    joined = target.base()
    mesh = joined.mesh
    stem = keyfiles.shared_name(target.names)
    paths, shares = {}, []
    try:
        for j in range(copies):
            made = tracing.issue(mesh, key=key, registry=reg, n_copies=1, method=method, params=params,
                                 store_key=store_key, source_name=stem)
            shares.append(made.distortion["largest_share"])
            cid, V = made[0]
            path = os.path.join(out, f"{stem}-{cid}.{file_format}")
            meshmark.write_mesh(path, V, mesh)
            paths[cid] = path
            yield (j + 1) / copies, f"Copy {cid} ({j + 1} of {copies})"
    finally:
        if paths:
            tracing.set_paths(reg, paths)
    data = {"registry": reg, "output_dir": out, "copies": [{"id": c, "path": p} for c, p in paths.items()],
            "store_key": bool(store_key), "parts": target.names}
    beyond = sum(x > 1.0 for x in shares)
    data["copies_beyond_budget"] = beyond
    notes = [n for n in (parts_note(context, target),) if n]
    if beyond:
        notes.append(f"{words.plural(beyond, 'copy', 'copies')} of {len(shares)} change the model more than is "
                     f"invisible (up to {max(shares):.1f} times the limit): the marks may show on this model")
    text = f"Issued {words.plural(len(paths), 'copy', 'copies')} of {target.quoted} into {out}; registry {os.path.basename(reg)}"
    return Outcome(ISSUE, target.names, "WARNING" if notes else "INFO", text, data, notes)


def trace_steps(context, target, *, registry="", key=None, evaluated=True):
    reg = keyfiles.resolve(registry, "registry") if registry else ""
    if not reg:
        raise MeshError("choose the registry file of the issued copies (Registry)")
    if not os.path.isfile(reg):
        raise MeshError(f"there is no registry '{keyfiles.display(reg)}': issue copies first, or choose the registry")
    yield 0.1, f"Reading {target.label}"
    skipped = []
    if evaluated:
        with bridge.cage_only(target.objects) as skipped:
            mesh = target.evaluated(context).mesh
    else:
        mesh = target.base().mesh
    yield 0.5, f"Comparing {target.label} with the issued copies"
    try:
        r = tracing.trace(mesh, registry=reg, key=key or None)
    except MeshError as exc:
        if "does not store the key" not in str(exc) or key:
            raise
        if not session.KEY["value"]:
            raise MeshError("the registry holds no key (the copies were issued with Store key off): type the key "
                            "in the panel") from None
        r = tracing.trace(mesh, registry=reg, key=session.KEY["value"])
    data = {"registry": reg, "frame": context.scene.frame_current, "evaluated": bool(evaluated),
            "skipped_modifiers": [m for _, m in skipped], **r}
    if r["detected"]:
        text = (f"{target.quoted} is copy {r['copy']} ({r['matches']} of {r['n_carriers']} bits agree; "
                f"{words.false_alarm(r['p_false_alarm'])})")
        return Outcome(TRACE, target.names, "INFO", text, data)
    text = f"{target.quoted} is none of the {r['n_copies']} issued copies"
    note = parts_note(context, target)
    return Outcome(TRACE, target.names, "WARNING", text, data, [note] if note else [])
