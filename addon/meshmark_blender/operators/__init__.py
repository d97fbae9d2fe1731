"""The ``bpy.ops.meshmark.*`` operators, one module per task (each a thin layer over :mod:`..tasks`).

:mod:`.base` holds what they share (arguments with panel fallbacks, reports, modal jobs with
progress in the status bar and Esc). :func:`register` registers them all; the add-on's ``__init__``
calls it.
"""
from __future__ import annotations

import bpy

from . import copies, hiding, inspect_ops, keyfile_ops, study_ops, watermark

CLASSES = (*watermark.CLASSES, *keyfile_ops.CLASSES, *copies.CLASSES, *hiding.CLASSES, *inspect_ops.CLASSES,
           *study_ops.CLASSES)


def register():
    for c in watermark.WITH_METHOD_PARAMS:
        watermark.add_method_params(c)
    for c in CLASSES:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(CLASSES):
        bpy.utils.unregister_class(c)
