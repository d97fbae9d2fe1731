"""``bpy.ops.meshmark.embed / verify / capacity / select_parts``.

They work on the selected mesh objects (with the active one): several selected parts of a character
are one carrier with one keyfile. Embed writes ``//<object>.meshmark.json`` unless another keyfile is
chosen; when that file exists the panel asks first, naming the file and the mark it holds (from
scripts: ``overwrite=True``). When the .blend has not been saved (no folder for ``//``) the panel asks
where, after checking that the mesh can take the message.
"""
from __future__ import annotations

import os

import bpy
from bpy.props import BoolProperty, EnumProperty, StringProperty

from .. import keyfiles, properties, session, targets
from .. import params as _params
from ..tasks import watermark as task
from ..properties import path_property
from .base import Base


def method_arg():
    return EnumProperty(name="Method", items=properties.method_items, options={"SKIP_SAVE"})


def weld_arg():
    return BoolProperty(name="Weld split vertices", default=True, options={"SKIP_SAVE"},
                        description="Treat vertices at exactly the same place (UV seams, flat shading, "
                                    "glTF exports) as one, so the model never cracks open")


def params_arg():
    return EnumProperty(name="Parameters", items=properties.PARAMS_MODE_ITEMS, default="auto", options={"SKIP_SAVE"})


def add_method_params(cls):
    """Give an operator one keyword argument per method parameter (union over METHODS)."""
    ann = cls.__dict__.get("__annotations__", {})
    for name, p in _params.all_params().items():
        ann[name] = properties.blender_property(p, options={"SKIP_SAVE"})
    cls.__annotations__ = ann


class _Marking(Base):
    """Embed and Capacity: the method, its parameters and the message, from arguments or the panel."""

    def marking(self, context) -> dict:
        s = context.scene.meshmark
        method = self.arg(context, "method")
        specs = {q.name: q for q in _params.method_params(method)}
        given = {n: specs[n].to_method(getattr(self, n)) for n in specs if self.given(n)}
        if self.given("params"):
            params, method_params = self.params, given
        else:
            params, method_params = properties.method_settings(s, method)
            if isinstance(params, dict):
                params = {**params, **given}
            else:
                method_params = given
        bits = getattr(self, "bits", "") or None
        return {"method": method, "message": None if bits else self.arg(context, "message"), "bits": bits,
                "params": params, "weld": self.arg(context, "weld"), "method_params": method_params}


class MESHMARK_OT_embed(_Marking, bpy.types.Operator):
    """Hide the message in the selected mesh (the selected parts of a character as one) and write its keyfile"""
    bl_idname = "meshmark.embed"
    bl_label = "Embed"
    bl_options = {"REGISTER", "UNDO"}
    job_label = "Embed"

    method: method_arg()
    message: StringProperty(name="Message", options={"SKIP_SAVE"})
    bits: StringProperty(name="Bits", options={"SKIP_SAVE"},
                         description="A raw bit string such as 0110 to hide instead of the text message")
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD")
    keyfile: path_property("FILE_PATH", name="Keyfile", options={"SKIP_SAVE"})
    weld: weld_arg()
    params: params_arg()
    store_key: BoolProperty(name="Store key in keyfile", default=True, options={"SKIP_SAVE"})
    overwrite: BoolProperty(name="Overwrite", default=False, options={"SKIP_SAVE"},
                            description="Replace an existing keyfile (the marks made with it can no longer be read)")
    filepath: path_property("FILE_PATH", options={"SKIP_SAVE", "HIDDEN"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    check_existing: BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})
    confirm: BoolProperty(default=False, options={"HIDDEN", "SKIP_SAVE"})

    def chosen_keyfile(self, context) -> str:
        if self.given("keyfile") and self.keyfile:
            return self.keyfile
        return self.filepath or context.scene.meshmark.keyfile

    def steps(self, context):
        return task.embed_steps(context, self.target(context), key=self.arg(context, "key"),
                                keyfile=self.chosen_keyfile(context), store_key=self.arg(context, "store_key"),
                                overwrite=self.overwrite, **self.marking(context))

    def invoke(self, context, event):
        try:
            target = self.target(context)
            m = self.marking(context)
            task.precheck(target, m["method"], m["message"], m["bits"], m["params"], m["weld"], m["method_params"])
            shown = self.chosen_keyfile(context) or keyfiles.for_objects(target.objects)
            path = keyfiles.abspath(shown)
        except Exception as exc:
            return self.fail(context, exc)
        if path is None:  # the .blend is not saved: ask where the keyfile goes (never into the .blend)
            self.filepath = os.path.join(os.path.expanduser("~"), os.path.basename(shown.lstrip("/")))
            context.window_manager.fileselect_add(self)
            return {"RUNNING_MODAL"}
        if os.path.exists(path) and not self.overwrite:
            self.keyfile, self.overwrite, self.confirm = shown, True, True
            return dialog(context, self, "Replace the keyfile?", "Replace")
        return self.start_job(context)

    def draw(self, context):
        """The replace dialog (what is lost), or the file browser's side panel (what will be marked)."""
        col = self.layout.column()
        if self.confirm:
            path = keyfiles.abspath(self.keyfile) or self.keyfile
            for i, line in enumerate(keyfiles.what_is_lost(path, session.KEY["value"])):
                col.label(text=line, icon="ERROR" if i == 0 else "BLANK1")
            return
        objs = properties.current_objects(context)
        col.label(text=targets.Target(objs).label if objs else "No mesh selected", icon="MESH_DATA")
        col.label(text=_params.method_label(self.arg(context, "method")), icon="MOD_SMOOTH")
        col.label(text=f"{len(self.arg(context, 'message').encode())}-byte message" if not self.bits
                  else f"{len(self.bits)} bits", icon="FONT_DATA")
        col.label(text="Key: " + ("set" if self.arg(context, "key") else "missing"), icon="KEY_HLT")


def dialog(context, op, title: str, confirm: str):
    """A confirmation dialog drawn by ``op.draw`` (its title and button where Blender has them: 4.1+)."""
    wm = context.window_manager
    try:
        return wm.invoke_props_dialog(op, width=420, title=title, confirm_text=confirm)
    except TypeError:  # Blender < 4.1
        return wm.invoke_props_dialog(op, width=420)


class MESHMARK_OT_verify(Base, bpy.types.Operator):
    """Check whether the selected mesh carries its keyfile's mark (as posed now, or its rest shape); any part of a
    character marked as one checks the whole character"""
    bl_idname = "meshmark.verify"
    bl_label = "Verify"
    job_label = "Verify"

    keyfile: path_property("FILE_PATH", name="Keyfile", options={"SKIP_SAVE"})
    evaluated: BoolProperty(name="Check as posed", default=True, options={"SKIP_SAVE"},
                            description="Check the mesh as it looks now (armature, shape keys, lattices) "
                                        "rather than its rest shape")
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD",
                        description="Use this key instead of the keyfile's (empty: the keyfile's)")

    def steps(self, context):
        key = self.key if self.given("key") and self.key else None
        return task.verify_steps(context, self.target(context), keyfile=self.arg(context, "keyfile"), key=key,
                                 evaluated=self.arg(context, "evaluated"))


class MESHMARK_OT_capacity(_Marking, bpy.types.Operator):
    """How much text the selected mesh (or character) can hold with the chosen method and settings"""
    bl_idname = "meshmark.capacity"
    bl_label = "Capacity"
    job_label = "Capacity"

    method: method_arg()
    message: StringProperty(name="Message", options={"SKIP_SAVE"})
    weld: weld_arg()
    params: params_arg()

    def steps(self, context):
        target = self.target(context)
        m = self.marking(context)
        return task.capacity_steps(context, target, m["method"], m["message"], None, m["params"], m["weld"],
                                   m["method_params"])

    def done(self, context, outcome):
        session.remember(("capacity", outcome.data.get("method"), tuple(outcome.objects)), outcome.data)
        return super().done(context, outcome)

    def invoke(self, context, event):
        return self.execute(context)


class MESHMARK_OT_select_parts(bpy.types.Operator):
    """Select every part of the active object's character (the meshes skinned to the same armature)"""
    bl_idname = "meshmark.select_parts"
    bl_label = "Select parts"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH" and len(targets.character_parts(context, obj)) > 1

    def execute(self, context):
        parts = targets.character_parts(context, context.active_object)
        for o in parts:
            o.select_set(True)
        self.report({"INFO"}, f"meshmark: selected the {len(parts)} parts of the character")
        return {"FINISHED"}


CLASSES = (MESHMARK_OT_embed, MESHMARK_OT_verify, MESHMARK_OT_capacity, MESHMARK_OT_select_parts)
WITH_METHOD_PARAMS = (MESHMARK_OT_embed, MESHMARK_OT_capacity)
