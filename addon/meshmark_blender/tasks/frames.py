"""Verify over the frames of the animation (the deformation study): a CSV table, a plot, a summary.

The frames default to those of the action playing on the objects' armature, else the scene's range.
Every frame is read as Verify reads it (the posed base mesh, through the deforming modifiers only, all
parts of the keyfile's character joined); the scene goes back to its frame afterwards, also when the
run is stopped (Esc).
"""
from __future__ import annotations

import math

import bpy
import numpy as np

from meshmark import MeshError
from meshmark.watermark import extract as wm_extract

from .. import bridge, keyfiles, study, targets, words
from .outcome import Outcome
from .watermark import read_keyfile

STUDY = "meshmark.deformation_study"


def animation_range(context, objects) -> tuple:
    """(start, end, where from): the frame range of the action on the objects' armature (or on the
    objects), else the scene's."""
    for o in objects:
        for holder in [*targets.armatures_of(o), o]:
            ad = getattr(holder, "animation_data", None)
            act = ad.action if ad is not None else None
            if act is not None:
                s, e = (int(round(x)) for x in act.frame_range)
                return s, e, f"the action '{act.name}'"
    sc = context.scene
    return sc.frame_start, sc.frame_end, "the scene"


def frames_steps(context, chosen, *, keyfile="", frame_start=None, frame_end=None, frame_step=1, output_dir="",
                 plot=True):
    """Verify at frames ``frame_start..frame_end`` every ``frame_step`` (None: the animation's range);
    the table always, the plot unless ``plot=False``."""
    path = keyfiles.resolve(keyfile or keyfiles.for_objects(chosen.objects))
    kf = read_keyfile(path)
    target, parts = targets.for_keyfile(context, kf, chosen)
    s0, e0, source = animation_range(context, target.objects)
    start = s0 if frame_start is None else int(frame_start)
    end = e0 if frame_end is None else int(frame_end)
    step = int(frame_step)
    if end < start or step < 1:
        raise MeshError(f"no frames to check: from {start} to {end} every {step}")
    out = keyfiles.resolve(output_dir, "folder for the table") if output_dir else ""
    if not out:
        raise MeshError("choose the folder for the table and plot (Save table to)")
    scene = context.scene
    rest = target.base()
    diag = max(bridge.bbox_diagonal(rest.mesh.V), 1e-300)
    frames = list(range(start, end + 1, step))
    rows, old = [], scene.frame_current
    try:
        with bridge.cage_only(target.objects) as skipped:
            for i, f in enumerate(frames):
                scene.frame_set(f)
                m = target.evaluated(context).mesh
                disp = (float(np.linalg.norm(m.V - rest.mesh.V, axis=1).max()) / diag
                        if m.n_vertices == rest.mesh.n_vertices else math.nan)  # Blender's vertex order
                r = wm_extract(m, keyfile=kf)
                rows.append({"frame": f, "nc": r.nc, "cdr": r.cdr, "matches": r.matches, "bits": r.n_bits,
                             "detected": r.detected, "message_ok": r.message_ok, "message": r.message,
                             "max_disp_rel": disp, "n_vertices": r.n_vertices})
                yield (i + 1) / len(frames), f"Frame {f} ({i + 1} of {len(frames)})"
    finally:
        scene.frame_set(old)
    stem = f"meshmark_study_{bpy.path.clean_name(keyfiles.shared_name(target.names))}"
    csv_path, png_path = study.output_paths(out, stem)
    study.write_csv(rows, csv_path)
    why = (study.write_plot(rows, png_path, f"{target.label}: {kf.method} watermark, frames {start}-{end}")
           if plot else "no plot (not asked for)")
    s = study.summarize(rows)
    data = {"keyfile": path, "csv": csv_path, "plot": None if why else png_path, "summary": s, "rows": rows,
            "frames_from": source if frame_start is None and frame_end is None else "the given range",
            "skipped_modifiers": [m for _, m in skipped], "missing_parts": parts["missing"]}
    warnings = [why] if why and plot else []
    if parts["missing"]:
        warnings.append(f"{words.names(parts['missing'])} not in the scene: read without")
    level = "INFO" if s["detected_frames"] == s["frames"] else "WARNING"
    text = (f"Mark found on {s['detected_frames']} of {s['frames']} frames of {target.quoted}, message on "
            f"{s['message_frames']}; largest movement {100 * s['max_disp_rel']:.0f} % of its size; table {csv_path}")
    return Outcome(STUDY, target.names, level, text, data, warnings)
