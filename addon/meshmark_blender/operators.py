"""``bpy.ops.meshmark.*``: embed, verify, capacity, deformation_study, save_keyfile, load_keyfile.

Every operator works on the active object, takes keyword arguments from scripts (arguments not
given fall back to ``scene.meshmark``), reports through ``self.report`` and leaves its result as a
JSON string in ``scene.meshmark.last_result``. Failures report an error and return {'CANCELLED'}
without touching the mesh: embed computes and checks everything, and writes the keyfile, before it
writes a single coordinate.
"""
from __future__ import annotations

import json
import math
import os
import time
import traceback

import bpy
import numpy as np
from bpy.props import BoolProperty, EnumProperty, IntProperty, StringProperty

import meshmark
from meshmark import MeshError
from meshmark.watermark import METHODS, capacity as wm_capacity, embed as wm_embed, extract as wm_extract
from meshmark.watermark import load_keyfile, save_keyfile
from meshmark.watermark.auto import longest_payload_bits
from meshmark.watermark.coding import max_data_bits
from meshmark.watermark.keyfile import KeyRequired, refuse_overwrite
from meshmark.watermark.payload import MAX_DATA_BITS, Payload

from . import bridge, messages, properties, study
from . import params as _params

# Session state kept out of the .blend: the last keyfile made by Embed (for "Save keyfile") and the
# capacity of meshes the panel has shown.
LAST = {"keyfile": None}


def _load_keyfile(context, path, key=None):
    """load_keyfile, with the panel's key (held in memory only) for a keyfile written without its key."""
    try:
        return load_keyfile(path, key=key)
    except KeyRequired:
        key = context.scene.meshmark.key
        if not key:
            raise MeshError(f"the keyfile '{path}' holds no key (written with Store key off): type the key in the "
                            "panel") from None
        return load_keyfile(path, key=key)
CAPACITY_CACHE = {}

_EXPECTED = (MeshError, bridge.BlenderInputError, OSError, ValueError)


def _abspath(path: str) -> str:
    return os.path.abspath(bpy.path.abspath(path)) if path else ""


class _Progress:
    """wm.progress_begin/update/end as a meshmark ``progress(fraction, text)`` callback."""

    def __init__(self, context, lo=0.0, hi=1.0):
        self.wm, self.lo, self.hi = context.window_manager, lo, hi
        self.wm.progress_begin(0, 1000)

    def __call__(self, fraction, text=""):
        self.wm.progress_update(int(1000 * (self.lo + (self.hi - self.lo) * fraction)))

    def end(self):
        self.wm.progress_end()


def operator_id(name: str) -> str:
    """``meshmark.verify`` for ``MESHMARK_OT_verify`` (Blender's internal form of an idname)."""
    if "_OT_" in name:
        mod, op = name.split("_OT_", 1)
        return f"{mod.lower()}.{op}"
    return name


class _Base:
    bl_options = {"REGISTER", "UNDO"}

    def arg(self, context, name):
        """The operator argument if given, else the scene setting of the same name."""
        if self.properties.is_property_set(name):
            return getattr(self, name)
        return getattr(context.scene.meshmark, name)

    def method_params(self, context, method: str) -> dict:
        p = properties.method_settings(context.scene.meshmark, method)
        specs = {q.name: q for q in _params.method_params(method)}
        for name in specs:
            if self.properties.is_property_set(name):
                p[name] = specs[name].to_method(getattr(self, name))
        return p

    def finish(self, context, result: dict, level: str, text: str):
        result = {"operator": operator_id(self.bl_idname), **result}
        context.scene.meshmark.last_result = json.dumps(result, default=_json_default)
        self.report({level}, text)
        return {"FINISHED"}

    def error_method(self, context):
        """The method an error message is about (to name its parameters as the panel does)."""
        try:
            return self.arg(context, "method") if "method" in self.properties.bl_rna.properties else None
        except Exception:  # pragma: no cover
            return None

    def draw(self, context):
        """The redo panel and the file browser's side panel: no second copy of the panel's fields
        (the operator takes its values from the Meshmark panel)."""
        self.layout.label(text="Settings: Meshmark panel", icon="INFO")

    def fail(self, context, exc):
        if isinstance(exc, _EXPECTED):
            msg = messages.friendly(str(exc), self.error_method(context))
        else:  # a bug: keep Blender alive, say so, and keep the traceback in the console
            traceback.print_exc()
            msg = f"internal error ({type(exc).__name__}: {exc}); the mesh was not changed"
        try:
            obj = getattr(context, "active_object", None)
            context.scene.meshmark.last_result = json.dumps({
                "operator": operator_id(self.bl_idname), "ok": False, "error": msg,
                "object": obj.name if obj is not None else None})
        except Exception:  # pragma: no cover - e.g. a read-only context
            pass
        self.report({"ERROR"}, f"meshmark: {msg}")
        return {"CANCELLED"}

    def run(self, context):
        raise NotImplementedError

    def execute(self, context):
        try:
            return self.run(context)
        except Exception as exc:  # never let an exception reach Blender
            return self.fail(context, exc)


def _json_default(o):
    if isinstance(o, (np.integer,)):
        return int(o)
    if isinstance(o, (np.floating,)):
        return float(o)
    if isinstance(o, np.ndarray):
        return o.tolist()
    return str(o)


def _method_arg():
    return EnumProperty(name="Method", items=properties.method_items, options={"SKIP_SAVE"})


def _weld_arg():
    return BoolProperty(name="Weld split vertices", default=True, options={"SKIP_SAVE"},
                        description="Treat vertices at exactly the same place (UV seams, flat shading, "
                                    "glTF exports) as one, so the model never cracks open")


def _add_method_params(cls):
    """Give an operator one keyword argument per method parameter (union over METHODS)."""
    ann = cls.__dict__.get("__annotations__", {})
    for name, p in _params.all_params().items():
        ann[name] = properties.blender_property(p, options={"SKIP_SAVE"})
    cls.__annotations__ = ann


def _params_arg():
    return EnumProperty(name="Parameters", items=properties.PARAMS_MODE_ITEMS, default="auto", options={"SKIP_SAVE"})


def changed_params(method: str, params: dict) -> dict:
    """The parameters that differ from the method's defaults: with automatic parameters the panel's
    fields at their (thesis) defaults mean "choose", values the user changed are kept."""
    defaults = _params.method_defaults(method)
    return {k: v for k, v in params.items() if v is not None and v != defaults.get(k)}


def proposed_keyfile(context, obj) -> str:
    """A keyfile name for this object: ``<object>.meshmark.json`` beside the scene's keyfile, the
    .blend, or in the current directory."""
    base = context.scene.meshmark.keyfile
    folder = os.path.dirname(_abspath(base)) if base else (os.path.dirname(bpy.data.filepath) if bpy.data.filepath else "")
    return os.path.join(folder, f"{bpy.path.clean_name(obj.name)}.meshmark.json") if folder else \
        f"{bpy.path.clean_name(obj.name)}.meshmark.json"


def _check_text(message: str, kind="text"):
    if not message:
        raise MeshError("the message is empty: type a message to hide")


# ---------------------------------------------------------------------------------------------
class MESHMARK_OT_embed(_Base, bpy.types.Operator):
    """Hide the message in the active mesh with the chosen method and key, and write the keyfile"""
    bl_idname = "meshmark.embed"
    bl_label = "Embed"

    method: _method_arg()
    message: StringProperty(name="Message", options={"SKIP_SAVE"})
    bits: StringProperty(name="Bits", options={"SKIP_SAVE"},
                         description="A raw bit string such as 0110 to hide instead of the text message")
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD")
    keyfile: StringProperty(name="Keyfile", options={"SKIP_SAVE"}, subtype="FILE_PATH")
    weld: _weld_arg()
    params_mode: _params_arg()
    overwrite: BoolProperty(name="Overwrite", default=False, options={"SKIP_SAVE"},
                            description="Replace an existing keyfile (its marks can no longer be read without it)")
    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE", "HIDDEN"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    check_existing: BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})

    def invoke(self, context, event):
        obj = context.active_object
        given = self.properties.is_property_set("keyfile") and self.keyfile
        if not given and not context.scene.meshmark.keyfile:
            # ask where the keyfile goes (never into the .blend), proposing one name per object
            self.filepath = proposed_keyfile(context, obj) if obj is not None else "keyfile.json"
            context.window_manager.fileselect_add(self)
            return {"RUNNING_MODAL"}
        path = _abspath(self.keyfile if given else context.scene.meshmark.keyfile)
        if path and os.path.exists(path) and not self.overwrite:
            try:  # anything else wrong is said first (and nothing is asked)
                self.run(context, dry=True)
            except Exception as exc:
                return self.fail(context, exc)
            self.overwrite = True  # confirmed in the dialog: "OK" runs execute
            return context.window_manager.invoke_confirm(self, event)
        return self.execute(context)

    def draw(self, context):
        """The file browser's side panel: what will be marked, not a second set of empty fields."""
        obj = context.active_object
        col = self.layout.column()
        col.label(text=obj.name if obj is not None else "No active object", icon="MESH_DATA")
        col.label(text=_params.method_label(self.arg(context, "method")), icon="MOD_SMOOTH")
        col.label(text=f"{len(self.arg(context, 'message').encode())}-byte message" if not self.bits
                  else f"{len(self.bits)} bits", icon="FONT_DATA")
        col.label(text="Key: " + ("set" if self.arg(context, "key") else "missing"), icon="KEY_HLT")

    def run(self, context, dry: bool = False):
        """Embed; ``dry``: compute and check everything, write nothing (the overwrite dialog's check)."""
        obj = bridge.active_mesh_object(context)
        method = self.arg(context, "method")
        message = self.arg(context, "message")
        key = self.arg(context, "key")
        keyfile = _abspath(self.keyfile if self.properties.is_property_set("keyfile") and self.keyfile
                           else self.filepath or context.scene.meshmark.keyfile)
        payload = Payload.from_bits(self.bits) if self.bits else message
        if not self.bits:
            _check_text(message)
        if not key:
            raise MeshError("the key is empty: type a secret key")
        if not keyfile:
            raise MeshError("choose where to save the keyfile (keyfile='/path/k.json', or the panel's Keyfile field)")
        if not os.path.isdir(os.path.dirname(keyfile)):
            raise MeshError(f"cannot write the keyfile '{keyfile}': the directory does not exist")
        if not dry:
            refuse_overwrite(keyfile, self.overwrite, "overwrite=True (or confirm in the dialog)")
        if self.properties.is_property_set("params_mode"):
            params_mode = self.params_mode
        else:  # the panel's Settings: Auto = the automatic choice, Custom = the fields as set
            params_mode = "auto" if context.scene.meshmark.param_mode == "AUTO" else "thesis"
        params = self.method_params(context, method)
        if params_mode == "auto":
            params = changed_params(method, params)
        weld = self.arg(context, "weld")
        mesh = bridge.base_mesh(obj)
        progress = _Progress(context, 0.0, 0.9)
        try:
            t0 = time.perf_counter()
            res = wm_embed(mesh, payload=payload, key=key, method=method, progress=progress, weld=weld,
                           params=params_mode, store_key=bool(context.scene.meshmark.store_key), **params)
            t_native = time.perf_counter() - t0
            # what Blender will store (float32), checked before anything is written
            D = res.V - mesh.V
            stored = (mesh.V + D).astype(np.float32).astype(np.float64)
            check = wm_extract(mesh.with_vertices(stored), keyfile=res.keyfile)
            progress(1.0)
            if dry:
                return None
            save_keyfile(res.keyfile, keyfile, overwrite=self.overwrite)  # may fail: the mesh is still untouched
            bridge.apply_displacement(obj, D)  # the only write
        finally:
            progress.end()
        LAST["keyfile"] = res.keyfile
        context.scene.meshmark.keyfile = keyfile
        disp = float(np.linalg.norm(D, axis=1).max()) / max(bridge.bbox_diagonal(mesh.V), 1e-300)
        result = {"ok": True, "object": obj.name, "keyfile": keyfile, "n_vertices": mesh.n_vertices,
                  **res.to_dict(), "stored_cdr": check.cdr, "stored_message_ok": check.message_ok,
                  "max_disp_rel": disp, "seconds_native": t_native}
        level = "INFO" if check.message_ok and check.cdr == 1.0 else "WARNING"
        return self.finish(context, result, level,
                           f"meshmark: embedded {self.bits or message!r} into '{obj.name}' ({res.capacity} carrier bits, "
                           f"CDR as stored {check.cdr:.3f}); keyfile: {keyfile}")


# ---------------------------------------------------------------------------------------------
class MESHMARK_OT_verify(_Base, bpy.types.Operator):
    """Check whether the active mesh carries the keyfile's mark (as posed now, or its rest shape)"""
    bl_idname = "meshmark.verify"
    bl_label = "Verify"

    keyfile: StringProperty(name="Keyfile", options={"SKIP_SAVE"}, subtype="FILE_PATH")
    evaluated: BoolProperty(name="Check as posed", default=True, options={"SKIP_SAVE"},
                            description="Check the mesh as it looks now (armature, shape keys, modifiers) "
                                        "rather than its rest shape")
    key: StringProperty(name="Key", options={"SKIP_SAVE"}, subtype="PASSWORD",
                        description="Use this key instead of the keyfile's (empty: the keyfile's)")

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        keyfile = _abspath(self.arg(context, "keyfile"))
        if not keyfile:
            raise MeshError("no keyfile: give keyfile='/path/k.json' or choose one in the panel")
        key = self.key if self.properties.is_property_set("key") and self.key else None
        kf = _load_keyfile(context, keyfile, key)
        evaluated = self.arg(context, "evaluated")
        progress = _Progress(context)
        try:
            t0 = time.perf_counter()
            mesh = bridge.evaluated_mesh(context, obj) if evaluated else bridge.base_mesh(obj)
            t_read = time.perf_counter() - t0
            res = wm_extract(mesh, keyfile=kf, key=key, progress=progress)
            t_native = time.perf_counter() - t0 - t_read
        finally:
            progress.end()
        d = res.to_dict()
        result = {"ok": True, "object": obj.name, "keyfile": keyfile, "evaluated": bool(evaluated),
                  "frame": context.scene.frame_current, "n_input_vertices": mesh.n_vertices, **d,
                  "welded": res.n_merged > 0, "seconds_native": t_native}
        if not res.same_vertex_count and not res.detected:
            # A different mesh (or the wrong object): an error, not an answer. The core extracts blindly
            # whatever the count (a simplified or cropped copy may still carry the mark), so a mark
            # found despite a different count is reported below as a detection with a warning.
            welded = f" after welding ({mesh.n_vertices} as stored)" if res.n_merged else ""
            msg = (f"'{obj.name}' has {res.n_vertices} vertices{welded} but the keyfile was made for a mesh of "
                   f"{res.expected_vertices}, and its mark is not found (NC {res.nc:.3f}, CDR {res.cdr:.3f}): "
                   f"verify is run on a different mesh, or with the wrong keyfile")
            result.update(ok=False, error=msg, operator=operator_id(self.bl_idname))
            context.scene.meshmark.last_result = json.dumps(result, default=_json_default)
            self.report({"ERROR"}, f"meshmark: {msg}")
            return {"CANCELLED"}
        for w in res.warnings:
            self.report({"WARNING"}, f"meshmark: {w}")
        if res.detected:
            msg = (f"meshmark: watermark DETECTED in '{obj.name}': NC {res.nc:.3f}, CDR {res.cdr:.3f}, "
                   + (f"message {res.message!r}" if res.message_ok else f"message not recovered ({res.reason})"))
            return self.finish(context, result, "INFO", msg)
        return self.finish(context, result, "WARNING",
                           f"meshmark: watermark NOT detected in '{obj.name}': NC {res.nc:.3f}, CDR {res.cdr:.3f}, "
                           f"P(false alarm) {res.p_false_alarm:.2g}")


# ---------------------------------------------------------------------------------------------
def capacity_of(obj, method: str, params: dict, weld: bool = True) -> dict:
    mesh = bridge.base_mesh(obj)
    n_input = mesh.n_vertices
    if weld:
        mesh = meshmark.weld_vertices(mesh).mesh
    cap = wm_capacity(mesh, method=method, weld=False, params="thesis", **params)
    fit = min(max_data_bits(cap), MAX_DATA_BITS)
    auto_fit = min(longest_payload_bits(mesh, METHODS[method], changed_params(method, params)), MAX_DATA_BITS)
    return {"ok": True, "object": obj.name, "method": method, "n_vertices": mesh.n_vertices,
            "n_input_vertices": n_input, "weld": bool(weld), "params": METHODS[method].resolve(mesh, params),
            "capacity": cap, "max_message_bits": fit, "max_text_bytes": fit // 8,
            "auto_max_message_bits": auto_fit, "auto_max_text_bytes": auto_fit // 8}


def capacity_signature(obj, method, params, weld=True):
    me = obj.data
    return (me.name, len(me.vertices), len(me.polygons), method, json.dumps(params, sort_keys=True), bool(weld))


class MESHMARK_OT_capacity(_Base, bpy.types.Operator):
    """How much text the active mesh can hold with the chosen method and settings"""
    bl_idname = "meshmark.capacity"
    bl_label = "Capacity"

    method: _method_arg()
    weld: _weld_arg()

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        method = self.arg(context, "method")
        params = self.method_params(context, method)
        weld = self.arg(context, "weld")
        d = capacity_of(obj, method, params, weld)
        CAPACITY_CACHE[obj.name] = (capacity_signature(obj, method, params, weld), d)
        return self.finish(context, d, "INFO",
                           f"meshmark: '{obj.name}' offers {d['capacity']} carrier bits to the {method} method: "
                           f"up to {d['max_text_bytes']} text bytes ({d['max_message_bits']} bits) with the thesis "
                           f"parameters, {d['auto_max_text_bytes']} ({d['auto_max_message_bits']} bits) with automatic ones")


# ---------------------------------------------------------------------------------------------
class MESHMARK_OT_deformation_study(_Base, bpy.types.Operator):
    """Check the mark on every n-th frame of the animation; write a table (CSV) and a plot"""
    bl_idname = "meshmark.deformation_study"
    bl_label = "Deformation study"

    keyfile: StringProperty(name="Keyfile", options={"SKIP_SAVE"}, subtype="FILE_PATH")
    frame_start: IntProperty(name="Start", options={"SKIP_SAVE"})
    frame_end: IntProperty(name="End", options={"SKIP_SAVE"})
    frame_step: IntProperty(name="Step", min=1, default=1, options={"SKIP_SAVE"})
    output_dir: StringProperty(name="Output", options={"SKIP_SAVE"}, subtype="DIR_PATH")

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        keyfile = _abspath(self.arg(context, "keyfile"))
        if not keyfile:
            raise MeshError("no keyfile: give keyfile='/path/k.json' or choose one in the panel")
        kf = _load_keyfile(context, keyfile)
        start, end, step = (self.arg(context, n) for n in ("frame_start", "frame_end", "frame_step"))
        if end < start or step < 1:
            raise MeshError(f"empty frame range {start}..{end} step {step}")
        out = _abspath(self.arg(context, "output_dir"))
        if not out:
            raise MeshError("choose an output directory for the study (output_dir=...)")
        scene = context.scene
        rest = bridge.base_mesh(obj)
        diag = max(bridge.bbox_diagonal(rest.V), 1e-300)
        frames = list(range(start, end + 1, step))
        rows, old = [], scene.frame_current
        wm = context.window_manager
        wm.progress_begin(0, len(frames))
        try:
            for i, f in enumerate(frames):
                scene.frame_set(f)
                m = bridge.evaluated_mesh(context, obj)
                disp = (float(np.linalg.norm(m.V - rest.V, axis=1).max()) / diag
                        if m.n_vertices == rest.n_vertices else math.nan)  # Blender's vertex order
                r = wm_extract(m, keyfile=kf)
                rows.append({"frame": f, "nc": r.nc, "cdr": r.cdr, "matches": r.matches, "bits": r.n_bits,
                             "detected": r.detected, "message_ok": r.message_ok, "message": r.message,
                             "max_disp_rel": disp, "n_vertices": r.n_vertices})
                wm.progress_update(i + 1)
        finally:
            scene.frame_set(old)
            wm.progress_end()
        stem = f"meshmark_study_{bpy.path.clean_name(obj.name)}"
        csv_path, png_path = study.output_paths(out, stem)
        study.write_csv(rows, csv_path)
        why = study.write_plot(rows, png_path, f"{obj.name}: {kf.method} watermark, frames {start}-{end}")
        s = study.summarize(rows)
        result = {"ok": True, "object": obj.name, "keyfile": keyfile, "csv": csv_path,
                  "plot": None if why else png_path, "summary": s, "rows": rows}
        if why:
            self.report({"WARNING"}, f"meshmark: {why}")
        level = "INFO" if s["detected_frames"] == s["frames"] else "WARNING"
        return self.finish(context, result, level,
                           f"meshmark: {s['detected_frames']}/{s['frames']} frames detected, message on "
                           f"{s['message_frames']}, mean CDR {s['mean_cdr']:.3f}, min NC {s['min_nc']:.3f}, "
                           f"max displacement {100 * s['max_disp_rel']:.1f}% of the diagonal; {csv_path}")


# ---------------------------------------------------------------------------------------------
class MESHMARK_OT_save_keyfile(_Base, bpy.types.Operator):
    """Save a copy of the keyfile of the last Embed where you choose"""
    bl_idname = "meshmark.save_keyfile"
    bl_label = "Save keyfile"
    bl_options = {"REGISTER"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})
    check_existing: BoolProperty(default=True, options={"HIDDEN", "SKIP_SAVE"})
    overwrite: BoolProperty(name="Overwrite", default=False, options={"SKIP_SAVE"},
                            description="Replace an existing keyfile (its marks can no longer be read without it)")

    def draw(self, context):  # the file browser: nothing to set beside the file name
        pass

    def invoke(self, context, event):
        obj = context.active_object
        self.filepath = proposed_keyfile(context, obj) if obj is not None else "keyfile.json"
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def run(self, context):
        kf = LAST["keyfile"]
        if kf is None:
            src = _abspath(context.scene.meshmark.keyfile)
            if not src or not os.path.isfile(src):
                raise MeshError("no keyfile to save: embed a watermark first")
            kf = _load_keyfile(context, src)
        path = _abspath(self.filepath)
        if not path:
            raise MeshError("choose a file name for the keyfile")
        save_keyfile(kf, path, overwrite=self.overwrite)  # MeshError if it exists: tick Overwrite
        context.scene.meshmark.keyfile = path
        return self.finish(context, {"ok": True, "keyfile": path}, "INFO", f"meshmark: keyfile saved to {path}")


class MESHMARK_OT_load_keyfile(_Base, bpy.types.Operator):
    """Open a keyfile: Verify and the study use it, and the panel shows its settings"""
    bl_idname = "meshmark.load_keyfile"
    bl_label = "Load keyfile"
    bl_options = {"REGISTER"}

    filepath: StringProperty(subtype="FILE_PATH", options={"SKIP_SAVE"})
    filter_glob: StringProperty(default="*.json", options={"HIDDEN"})

    def draw(self, context):  # the file browser: nothing to set beside the file name
        pass

    def invoke(self, context, event):
        context.window_manager.fileselect_add(self)
        return {"RUNNING_MODAL"}

    def run(self, context):
        path = _abspath(self.filepath)
        kf = _load_keyfile(context, path)  # validates (schema, tag) before anything is set
        s = context.scene.meshmark
        s.keyfile, s.method, s.key, s.weld = path, kf.method, kf.key, kf.weld
        s.param_mode = "CUSTOM"  # the keyfile's settings, shown under Advanced
        pl = Payload.from_bits(kf.payload["bits"])
        text = Payload(kf.payload["kind"], pl.data).message()
        if kf.payload["kind"] == "text":
            s.message = text
        group = getattr(s.params, kf.method)
        for p in _params.method_params(kf.method):
            v = kf.params.get(p.name)
            if v is not None:
                setattr(group, p.name, v)
        return self.finish(context, {"ok": True, "keyfile": path, "method": kf.method, "message": text,
                                     "params": kf.params, "weld": kf.weld, "mesh": kf.mesh}, "INFO",
                           f"meshmark: loaded keyfile {path} ({kf.method}, message {text!r})")


classes = (MESHMARK_OT_embed, MESHMARK_OT_verify, MESHMARK_OT_capacity, MESHMARK_OT_deformation_study,
           MESHMARK_OT_save_keyfile, MESHMARK_OT_load_keyfile)


def register():
    for c in (MESHMARK_OT_embed, MESHMARK_OT_capacity):
        _add_method_params(c)
    for c in classes:
        bpy.utils.register_class(c)
    from . import hiding_ops, study_ops, tracing_ops
    tracing_ops.register()
    hiding_ops.register()
    study_ops.register()


def unregister():
    from . import hiding_ops, study_ops, tracing_ops
    study_ops.unregister()
    hiding_ops.unregister()
    tracing_ops.unregister()
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
    LAST["keyfile"] = None
    CAPACITY_CACHE.clear()
