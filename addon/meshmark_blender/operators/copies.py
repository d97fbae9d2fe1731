"""``bpy.ops.meshmark.issue_copies`` / ``trace``: copy tracing from Blender (see :mod:`..tasks.copies`)."""
from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty

from .. import properties
from ..tasks import copies as task
from ..properties import path_property
from .base import Base


class MESHMARK_OT_issue_copies(Base, bpy.types.Operator):
    """Write marked copies of the selected mesh (or character), each with its own mark, and record them in the
    registry; the objects are not changed"""
    bl_idname = "meshmark.issue_copies"
    bl_label = "Issue copies"
    job_label = "Issue copies"

    copies: IntProperty(name="Copies", min=1, default=10, options={"SKIP_SAVE"})
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD")
    registry: path_property("FILE_PATH", name="Registry", options={"SKIP_SAVE"})
    output_dir: path_property("DIR_PATH", name="Copies to", options={"SKIP_SAVE"})
    file_format: EnumProperty(name="Format", items=properties.COPY_FORMATS, default="obj", options={"SKIP_SAVE"})
    store_key: BoolProperty(name="Store key in registry", default=True, options={"SKIP_SAVE"})

    def steps(self, context):
        return task.issue_steps(context, self.target(context), copies=self.arg(context, "copies"),
                                key=self.arg(context, "key"), registry=self.arg(context, "registry"),
                                output_dir=self.arg(context, "output_dir", "copies_dir"),
                                file_format=self.arg(context, "file_format", "copies_format"),
                                store_key=self.arg(context, "store_key"))


class MESHMARK_OT_trace(Base, bpy.types.Operator):
    """Which issued copy is the selected mesh (or character)? Names it only when an unmarked mesh could not read
    like this, else none"""
    bl_idname = "meshmark.trace"
    bl_label = "Trace"
    job_label = "Trace"

    registry: path_property("FILE_PATH", name="Registry", options={"SKIP_SAVE"})
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD",
                        description="The owner's key (empty: the registry's)")
    evaluated: BoolProperty(name="Check as posed", default=True, options={"SKIP_SAVE"})

    def steps(self, context):
        key = self.key if self.given("key") and self.key else None
        return task.trace_steps(context, self.target(context), registry=self.arg(context, "registry"), key=key,
                                evaluated=self.arg(context, "evaluated"))


CLASSES = (MESHMARK_OT_issue_copies, MESHMARK_OT_trace)
