"""The "Meshmark" tab of the 3D View sidebar (N panel).

A parent panel (the objects the tasks work on, the keyfile they share) and one sub-panel per task,
each a class listed once in :data:`SUBPANELS`; a sub-panel whose operators are not registered
(``needs``) is not registered either. Watermark is open, the others are collapsed until opened.

* :mod:`.layout`: fields, wrapped texts and folds that fit the default sidebar width;
* :mod:`.results`: each task's result box, in words;
* :mod:`.watermark`: the parent panel and Watermark (capacity and the Auto line: what Embed will use);
* :mod:`.tasks`: Trace copies, Steganography, Analysis, Steganalysis, Study.
"""
from __future__ import annotations

import bpy

from .layout import DEFAULT_REGION_WIDTH, SIDEBAR_MARGIN  # noqa: F401  (tests measure with them)
from .tasks import (MESHMARK_PT_analysis, MESHMARK_PT_steganalysis, MESHMARK_PT_stego, MESHMARK_PT_study,
                    MESHMARK_PT_trace, operator_registered)
from .watermark import MESHMARK_PT_sidebar, MESHMARK_PT_watermark

# Every sub-panel, in one place.
SUBPANELS = (MESHMARK_PT_watermark, MESHMARK_PT_trace, MESHMARK_PT_stego, MESHMARK_PT_analysis,
             MESHMARK_PT_steganalysis, MESHMARK_PT_study)
_registered = []


def available(cls) -> bool:
    return all(operator_registered(op) for op in cls.needs)


def register():
    _registered[:] = [MESHMARK_PT_sidebar] + [c for c in SUBPANELS if available(c)]
    for c in _registered:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(_registered):
        bpy.utils.unregister_class(c)
    _registered.clear()
