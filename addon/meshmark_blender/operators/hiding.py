"""``bpy.ops.meshmark.stego_embed`` (Hide) / ``stego_extract`` (Reveal): see :mod:`..tasks.hiding`.

Neither is registered in Blender's operator history (no ``"REGISTER"``): the history (and the redo
panel) would keep the text to hide. Hide pushes an undo step (it changes the mesh). On a mesh that
carries a watermark the panel asks first; a script passes ``replace_watermark=True``.
"""
from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, StringProperty

from .. import bridge, properties, session
from ..tasks import hiding as task
from ..properties import path_property
from .base import Base
from .watermark import dialog


def tolerance_arg():
    return FloatProperty(name="Shading change", min=0.0, options={"SKIP_SAVE"},
                         description="How far the shading may turn, in degrees")


def adaptive_arg():
    return EnumProperty(name="Spread", items=properties.STEGO_SPREAD, options={"SKIP_SAVE"})


def settings(op, context) -> dict:
    """Shading change (degrees) and spread: the arguments, else the panel (Auto: the defaults)."""
    s = context.scene.meshmark
    custom = s.stego_mode == "CUSTOM"
    tol = op.tolerance if op.given("tolerance") else (s.stego_tolerance if custom else properties.STEGO_TOLERANCE)
    spread = op.adaptive if op.given("adaptive") else (s.stego_spread if custom else "triangle")
    return {"tolerance": float(tol), "adaptive": spread}


class MESHMARK_OT_stego_embed(Base, bpy.types.Operator):
    """Hide a text or a file in the active mesh (only someone with the key can read it)"""
    bl_idname = "meshmark.stego_embed"
    bl_label = "Hide"
    bl_options = {"UNDO"}
    job_label = "Hide"

    message: StringProperty(name="Text", options={"SKIP_SAVE"})
    message_file: path_property("FILE_PATH", name="File", options={"SKIP_SAVE"})
    key: StringProperty(name="Key", subtype="PASSWORD", options={"SKIP_SAVE"})
    tolerance: tolerance_arg()
    adaptive: adaptive_arg()
    replace_watermark: BoolProperty(name="Replace the watermark", default=False, options={"SKIP_SAVE"},
                                    description="Hide even though the mesh carries a watermark (it is erased)")

    def what(self, context) -> dict:
        s = context.scene.meshmark
        if self.given("message_file") and self.message_file:
            return {"message_file": self.message_file}
        if self.given("message"):
            return {"message": self.message}
        return {"message_file": s.stego_file} if s.stego_source == "FILE" else {"message": s.stego_text}

    def steps(self, context):
        return task.hide_steps(context, bridge.active_mesh_object(context), key=self.arg(context, "key"),
                               replace_watermark=self.replace_watermark, **self.what(context), **settings(self, context))

    def invoke(self, context, event):
        try:
            obj = bridge.active_mesh_object(context)
            marked = None if self.replace_watermark else task.watermark_on(context, obj, session.KEY["value"])
        except Exception as exc:
            return self.fail(context, exc)
        if marked:
            self.replace_watermark = True
            return dialog(context, self, "Erase the watermark?", "Hide anyway")
        return self.start_job(context)

    def draw(self, context):
        obj = context.active_object
        col = self.layout.column()
        col.label(text=f"'{obj.name if obj else ''}' carries a watermark.", icon="ERROR")
        col.label(text="Hiding data moves every vertex and erases it.", icon="BLANK1")
        col.label(text="Hide in a copy of the object to keep both.", icon="BLANK1")


class MESHMARK_OT_stego_extract(Base, bpy.types.Operator):
    """Read the text or file hidden in the active mesh with the key"""
    bl_idname = "meshmark.stego_extract"
    bl_label = "Reveal"
    bl_options = set()
    job_label = "Reveal"

    key: StringProperty(name="Key", subtype="PASSWORD", options={"SKIP_SAVE"})
    tolerance: tolerance_arg()
    adaptive: adaptive_arg()
    out_file: path_property("FILE_PATH", name="Save to", options={"SKIP_SAVE"},
                             description="Write what was hidden to this file")

    def steps(self, context):
        out = self.out_file if self.given("out_file") else context.scene.meshmark.stego_save
        return task.reveal_steps(context, bridge.active_mesh_object(context), key=self.arg(context, "key"),
                                 out_file=out, **settings(self, context))


CLASSES = (MESHMARK_OT_stego_embed, MESHMARK_OT_stego_extract)
