"""``bpy.ops.meshmark.issue_copies`` and ``bpy.ops.meshmark.trace``: copy tracing from Blender
(meshmark.watermark.tracing). Issue writes marked copies of the active object's base mesh as files
(the object itself is not changed); trace checks the active object (as deformed now, or its base
mesh) against the registry."""
from __future__ import annotations

import os

import bpy
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty

import meshmark
from meshmark import MeshError
from meshmark.watermark import tracing

from . import bridge
from .operators import _Base, _abspath


class MESHMARK_OT_issue_copies(_Base, bpy.types.Operator):
    """Write marked copies of the active mesh (each with its own codeword) and record them in the registry"""
    bl_idname = "meshmark.issue_copies"
    bl_label = "Issue copies"
    bl_options = {"REGISTER"}

    copies: IntProperty(name="Copies", min=1, default=10, options={"SKIP_SAVE"})
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD")
    registry: StringProperty(name="Registry", options={"SKIP_SAVE"}, subtype="FILE_PATH")
    directory: StringProperty(name="Output", options={"SKIP_SAVE"}, subtype="DIR_PATH")
    file_format: EnumProperty(name="Format", items=[(x, x.upper(), "") for x in ("obj", "ply", "off", "stl")],
                              default="obj", options={"SKIP_SAVE"})

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        key = self.arg(context, "key")
        registry = _abspath(self.arg(context, "registry"))
        copies = self.arg(context, "copies")
        out = _abspath(self.directory) or (os.path.dirname(registry) if registry else "")
        if not key:
            raise MeshError("the key is empty: type a secret key")
        if not registry:
            raise MeshError("choose the registry file (registry='/path/r.sqlite' or the panel's Registry field)")
        if not out or not os.path.isdir(out):
            raise MeshError(f"the output directory '{out}' does not exist")
        mesh = bridge.base_mesh(obj)
        made = tracing.issue(mesh, key=key, registry=registry, n_copies=copies, source_name=obj.name)
        stem = bpy.path.clean_name(obj.name)
        paths = {}
        for cid, V in made:
            path = os.path.join(out, f"{stem}-{cid}.{self.file_format}")
            meshmark.write_mesh(path, V, mesh)
            paths[cid] = path
        tracing.set_paths(registry, paths)
        return self.finish(context, {"ok": True, "object": obj.name, "registry": registry,
                                     "copies": [{"id": c, "path": p} for c, p in paths.items()]}, "INFO",
                           f"meshmark: issued {len(paths)} copies of '{obj.name}' into {out}; registry {registry}")


class MESHMARK_OT_trace(_Base, bpy.types.Operator):
    """Which issued copy is the active mesh? Names it if P(false alarm) < 1e-6, else none"""
    bl_idname = "meshmark.trace"
    bl_label = "Trace"
    bl_options = {"REGISTER"}

    registry: StringProperty(name="Registry", options={"SKIP_SAVE"}, subtype="FILE_PATH")
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD",
                        description="The owner's key (empty: the registry's)")
    evaluated: BoolProperty(name="Deformed", default=True, options={"SKIP_SAVE"})

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        registry = _abspath(self.arg(context, "registry"))
        if not registry:
            raise MeshError("choose the registry file (registry='/path/r.sqlite' or the panel's Registry field)")
        mesh = bridge.evaluated_mesh(context, obj) if self.arg(context, "evaluated") else bridge.base_mesh(obj)
        key = self.key if self.properties.is_property_set("key") and self.key else None
        r = tracing.trace(mesh, registry=registry, key=key)
        text = (f"meshmark: '{obj.name}' is copy {r['copy']} (P(false alarm) {r['p_false_alarm']:.2g}, "
                f"{r['matches']}/{r['n_carriers']} bits)" if r["detected"] else
                f"meshmark: '{obj.name}': none of the {r['n_copies']} copies (P(false alarm) {r['p_false_alarm']:.2g})")
        return self.finish(context, {"ok": True, "object": obj.name, "registry": registry,
                                     "frame": context.scene.frame_current, **r},
                           "INFO" if r["detected"] else "WARNING", text)


classes = (MESHMARK_OT_issue_copies, MESHMARK_OT_trace)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
