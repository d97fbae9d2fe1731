"""``bpy.ops.meshmark.save_keyfile`` / ``load_keyfile``: a copy of the keyfile where you choose, and
opening a keyfile for the selected objects (Verify and the frame check then use it; the panel shows
its settings)."""
from __future__ import annotations

import os

import bpy
from bpy.props import BoolProperty, StringProperty

from meshmark import MeshError
from meshmark.watermark import save_keyfile
from meshmark.watermark.payload import Payload

from .. import keyfiles, properties, session, targets
from .. import params as _params
from ..tasks.outcome import Outcome
from ..tasks.watermark import read_keyfile
from ..properties import path_property
from .base import Base


class MESHMARK_OT_save_keyfile(Base, bpy.types.Operator):
    """Save a copy of the selected object's keyfile (or the last Embed's) where you choose"""
    bl_idname = "meshmark.save_keyfile"
    bl_label = "Save keyfile"

    filepath: path_property("FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    check_existing: BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})
    overwrite: BoolProperty(name="Overwrite", default=False, options={"SKIP_SAVE"},
                            description="Replace an existing file (the marks made with it can no longer be read)")

    def draw(self, context):  # the file browser: nothing to set beside the file name
        pass

    def invoke(self, context, event):
        objs = properties.current_objects(context)
        name = keyfiles.shared_name([o.name for o in objs]) if objs else "keyfile"
        folder = os.path.dirname(bpy.data.filepath) if bpy.data.filepath else os.path.expanduser("~")
        self.filepath = os.path.join(folder, f"{name}-copy{keyfiles.SUFFIX}")
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def steps(self, context):
        src = keyfiles.abspath(context.scene.meshmark.keyfile)
        if src and os.path.isfile(src):
            kf = read_keyfile(src)
        elif session.LAST["keyfile"] is not None:
            kf = session.LAST["keyfile"]
        else:
            raise MeshError("no keyfile to save: embed a watermark first")
        path = keyfiles.resolve(self.filepath, "file")
        if not path:
            raise MeshError("choose a file name for the keyfile")
        if os.path.exists(path) and not self.overwrite:
            raise MeshError(f"'{os.path.basename(path)}' already exists: " + " ".join(keyfiles.what_is_lost(path))
                            + " Choose another name, or tick Overwrite")
        yield 0.5, "Saving"
        save_keyfile(kf, path, overwrite=self.overwrite)
        return Outcome("meshmark.save_keyfile", [o.name for o in properties.current_objects(context)], "INFO",
                       f"Keyfile saved to {path}", {"keyfile": path})


class MESHMARK_OT_load_keyfile(Base, bpy.types.Operator):
    """Open a keyfile for the selected objects: Verify and the frame check use it, the panel shows its settings"""
    bl_idname = "meshmark.load_keyfile"
    bl_label = "Load keyfile"

    filepath: path_property("FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def draw(self, context):  # the file browser: nothing to set beside the file name
        pass

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def steps(self, context):
        path = keyfiles.resolve(self.filepath, "keyfile")
        kf = read_keyfile(path)  # validates (schema, tag) before anything is set
        yield 0.5, "Reading"
        s = context.scene.meshmark
        parts = [p["object"] for p in targets.recorded_parts(kf)]
        objs = properties.current_objects(context)
        present = [bpy.data.objects[n] for n in parts if n in bpy.data.objects]
        keyfiles.remember(sorted(set(objs) | set(present), key=lambda o: o.name), keyfiles.display(path))
        s.method, s.weld = kf.method, kf.weld
        if kf.key:
            session.KEY["value"] = kf.key
        s.param_mode = "CUSTOM"  # the keyfile's settings, shown under Advanced
        text = Payload(kf.payload["kind"], Payload.from_bits(kf.payload["bits"]).data).message()
        if kf.payload["kind"] == "text":
            s.message = text
        group = getattr(s.params, kf.method)
        for p in _params.method_params(kf.method):
            v = kf.params.get(p.name)
            if v is not None:
                setattr(group, p.name, v)
        return Outcome("meshmark.load_keyfile", [o.name for o in objs], "INFO",
                       f"Loaded keyfile {path} ({kf.method}, message '{text}')",
                       {"keyfile": path, "method": kf.method, "message": text, "params": kf.params,
                        "weld": kf.weld, "mesh": kf.mesh, "parts": parts})


CLASSES = (MESHMARK_OT_save_keyfile, MESHMARK_OT_load_keyfile)
