"""A small Python API for pipelines: the add-on's tasks on Blender objects, without operators.

Each function takes the objects (``bpy.types.Object`` or their names; None: the selection with the
active object), the options the CLI and the operators take (same names, same defaults), and returns
an :class:`~.tasks.outcome.Outcome`: ``.ok``, ``.text`` (a sentence), ``.warnings``, ``.data`` (the
figures, also readable as attributes: ``r.detected``, ``r.keyfile``) and ``.to_dict()``. A refusal
(bad input, a mesh too small, an existing keyfile without ``overwrite=True``) raises
``meshmark.MeshError`` and changes nothing. ``progress(fraction, text)`` is called between steps.

    import bpy
    from meshmark_blender import api   # the extension: from bl_ext.user_default.meshmark import api
    parts = [o for o in bpy.data.objects if o.type == "MESH" and o.modifiers.get("Armature")]
    r = api.embed(parts, message="ACME", key="s3cret")        # one mark, one keyfile: //Knight.meshmark.json
    v = api.verify(parts[:1])                                 # any part reads the whole character
    print(r.keyfile, r.capacity, v.detected, v.message)

Keyfile paths may start with ``//`` (beside the .blend) or ``~``.
"""
from __future__ import annotations

import bpy

from . import targets
from .tasks import copies as _copies, frames as _frames, hiding as _hiding, inspect as _inspect
from .tasks import study as _study, watermark as _wm
from .tasks.outcome import Outcome, run

__all__ = ["embed", "verify", "capacity", "check_frames", "issue", "trace", "hide", "reveal", "analyze", "detect",
           "run_study", "Outcome"]


def _ctx(context):
    return context or bpy.context


def _target(context, objects):
    return targets.from_selection(_ctx(context), objects)


def _one(context, obj):
    t = _target(context, obj)
    if len(t.objects) != 1:
        raise targets.BlenderInputError(f"this works on one object, got {len(t.objects)}")
    return t.objects[0]


def embed(objects=None, *, message=None, bits=None, key, keyfile="", method="laplacian", params="auto", weld=True,
          store_key=True, overwrite=False, progress=None, context=None, **method_params) -> Outcome:
    """Mark the objects as one carrier and write the keyfile (default ``//<name>.meshmark.json``)."""
    c = _ctx(context)
    return run(_wm.embed_steps(c, _target(c, objects), message=message, bits=bits, key=key, keyfile=keyfile,
                               method=method, params=params, weld=weld, store_key=store_key, overwrite=overwrite,
                               method_params=method_params), progress)


def verify(objects=None, *, keyfile="", key=None, evaluated=True, progress=None, context=None) -> Outcome:
    """Look for the keyfile's mark (as posed now unless ``evaluated=False``); ``.detected``, ``.message``."""
    c = _ctx(context)
    return run(_wm.verify_steps(c, _target(c, objects), keyfile=keyfile, key=key, evaluated=evaluated), progress)


def capacity(objects=None, *, method="laplacian", message=None, bits=None, params="auto", weld=True, context=None,
             **method_params) -> Outcome:
    """What Embed would use for this message (``.params``, ``.capacity``) and the longest text that fits."""
    c = _ctx(context)
    return run(_wm.capacity_steps(c, _target(c, objects), method, message, bits, params, weld, method_params))


def check_frames(objects=None, *, keyfile="", frame_start=None, frame_end=None, frame_step=1, output_dir,
                 plot=True, progress=None, context=None) -> Outcome:
    """Verify on every ``frame_step``-th frame (default: the animation's range); CSV (and plot) in ``output_dir``."""
    c = _ctx(context)
    return run(_frames.frames_steps(c, _target(c, objects), keyfile=keyfile, frame_start=frame_start,
                                    frame_end=frame_end, frame_step=frame_step, output_dir=output_dir, plot=plot),
               progress)


def issue(objects=None, *, copies, key, registry, output_dir, file_format="obj", store_key=True, method="laplacian",
          params="auto", progress=None, context=None) -> Outcome:
    """Write ``copies`` marked copies into ``output_dir`` and record them in ``registry``."""
    c = _ctx(context)
    return run(_copies.issue_steps(c, _target(c, objects), copies=copies, key=key, registry=registry,
                                   output_dir=output_dir, file_format=file_format, store_key=store_key, method=method,
                                   params=params), progress)


def trace(objects=None, *, registry, key=None, evaluated=True, context=None) -> Outcome:
    """Which issued copy the objects are (``.copy``, None for none)."""
    c = _ctx(context)
    return run(_copies.trace_steps(c, _target(c, objects), registry=registry, key=key, evaluated=evaluated))


def hide(obj=None, *, message=None, message_file=None, key, tolerance=1.0, adaptive="triangle",
         replace_watermark=False, context=None) -> Outcome:
    """Hide a text (``message``) or a file's bytes (``message_file``) in one object."""
    c = _ctx(context)
    return run(_hiding.hide_steps(c, _one(c, obj), message=message, message_file=message_file, key=key,
                                  tolerance=tolerance, adaptive=adaptive, replace_watermark=replace_watermark))


def reveal(obj=None, *, key, tolerance=1.0, adaptive="triangle", out_file="", context=None) -> Outcome:
    """Read what is hidden in one object (``.found``, ``.text``; ``out_file``: write the bytes there)."""
    c = _ctx(context)
    return run(_hiding.reveal_steps(c, _one(c, obj), key=key, tolerance=tolerance, adaptive=adaptive,
                                    out_file=out_file))


def analyze(obj=None, *, tolerance=0.1, mode="ADAPTIVE", show="LEVELS", context=None) -> Outcome:
    """The precision heat map as attributes and colours of one object."""
    c = _ctx(context)
    return run(_inspect.analyze_steps(c, _one(c, obj), tolerance=tolerance, mode=mode, show=show))


def detect(obj=None, *, model=None, context=None) -> Outcome:
    """Steganalysis of one object: ``.state`` is "marked", "clean" or "cannot_judge"."""
    c = _ctx(context)
    return run(_inspect.detect_steps(c, _one(c, obj), model=model))


def run_study(spec, out, progress=None) -> dict:
    """Run a study file in Blender's own Python (waits); the engine's summary and the counts."""
    from .keyfiles import resolve
    spec, out = _study.study_paths(spec, out, resolve)
    return run(_study.study_steps(spec, out), progress)
