"""``bpy.ops.meshmark.stego_embed`` / ``stego_extract`` (meshmark.stego), ``meshmark.analyze``
(meshmark.analysis: a heat map of the quantization levels and the curvature change, Fig. 4.7) and
``meshmark.steganalysis_detect`` (meshmark.steganalysis). Like the watermark operators: keyword
arguments from scripts, the panel's settings otherwise, ``self.report``, JSON in
``scene.meshmark.last_result``, and a failed call leaves the mesh bit-identical.

Steganography writes the base mesh in float32, Blender's precision (``precision="float32"`` of the
core), reads it back with ``foreach_get`` and extracts before it reports success; if the message does
not come back, every coordinate array is put back as it was and the call fails.
"""
from __future__ import annotations

import os
import time

import bpy
import numpy as np
from bpy.props import EnumProperty, FloatProperty, StringProperty

from meshmark import MeshError, analysis, stego

from . import bridge, properties
from .operators import _Base, _abspath

STEGO_PRECISION = "float32"  # what Blender stores


def _stego_settings(op, context) -> tuple:
    """(tolerance in degrees, spread) from the operator's arguments, else the panel (Auto: defaults)."""
    s = context.scene.meshmark
    custom = s.stego_mode == "CUSTOM"
    tol = op.tolerance if op.properties.is_property_set("tolerance") else (
        s.stego_tolerance if custom else properties.STEGO_TOLERANCE)
    spread = op.spread if op.properties.is_property_set("spread") else (s.stego_spread if custom else "triangle")
    return float(tol), spread


def _key(op, context) -> str:
    key = op.key if op.properties.is_property_set("key") else context.scene.meshmark.key
    if not key:
        raise MeshError("the key is empty: type a secret key")
    return key


def _tolerance_arg():
    return FloatProperty(name="Shading change", min=0.0, options={"SKIP_SAVE"},
                         description="How far the shading may turn, in degrees")


def _spread_arg():
    return EnumProperty(name="Spread", items=properties.STEGO_SPREAD, options={"SKIP_SAVE"})


class MESHMARK_OT_stego_embed(_Base, bpy.types.Operator):
    """Hide a text or a file in the active mesh (only someone with the key can read it)"""
    bl_idname = "meshmark.stego_embed"
    bl_label = "Hide"

    source: EnumProperty(name="Hide", items=properties.STEGO_SOURCES, options={"SKIP_SAVE"})
    text: StringProperty(name="Text", options={"SKIP_SAVE"})
    filepath: StringProperty(name="File", subtype="FILE_PATH", options={"SKIP_SAVE"})
    key: StringProperty(name="Key", subtype="PASSWORD", options={"SKIP_SAVE"})
    tolerance: _tolerance_arg()
    spread: _spread_arg()

    def _message(self, context) -> tuple:
        s = context.scene.meshmark
        path = self.filepath if self.properties.is_property_set("filepath") else ""
        text_given = self.properties.is_property_set("text")
        source = self.source if self.properties.is_property_set("source") else (
            "FILE" if path else "TEXT" if text_given else s.stego_source)
        if source == "FILE":
            path = _abspath(path or s.stego_file)
            if not path:
                raise MeshError("choose the file to hide (filepath='/path/f', or the panel's File field)")
            if not os.path.isfile(path):
                raise MeshError(f"the file to hide '{path}' does not exist")
            with open(path, "rb") as f:
                data = f.read()
            if not data:
                raise MeshError(f"the file to hide '{path}' is empty")
            return data, os.path.basename(path)
        text = self.text if text_given else s.stego_text
        if not text:
            raise MeshError("the text is empty: type a text to hide")
        return text.encode("utf-8"), None

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        data, fname = self._message(context)
        key = _key(self, context)
        tol, spread = _stego_settings(self, context)
        me = obj.data
        mesh = bridge.base_mesh(obj)
        t0 = time.perf_counter()
        res = stego.embed(mesh, data, key, tolerance=tol, adaptive=spread, precision=STEGO_PRECISION)
        t_native = time.perf_counter() - t0
        V32 = res.V.astype(np.float32)
        if not np.array_equal(V32.astype(np.float64), res.V):  # the core promised float32 words
            raise MeshError("the hidden data would not survive Blender's float32 storage; nothing was changed")
        saved = bridge.snapshot_coords(me)
        bridge.write_base_exact(obj, V32)
        try:  # read back what Blender stores, and extract from it
            t1 = time.perf_counter()
            back = bridge.base_mesh(obj)
            got = stego.extract(back, key, tolerance=tol, adaptive=spread, precision=STEGO_PRECISION)
            t_check = time.perf_counter() - t1
            if not (got.found and got.message == data):
                raise MeshError("the hidden data would not read back from this mesh as Blender stores it "
                                f"({got.reason or 'different data'}); nothing was changed. Try another Shading change")
        except BaseException:
            bridge.restore_coords(obj, saved)
            raise
        moved = float(np.abs(res.V - mesh.V).max()) / max(bridge.bbox_diagonal(mesh.V), 1e-300)
        result = {"ok": True, "object": obj.name, "bytes": len(data), "file": fname,
                  "max_bytes": res.max_message_bytes, "capacity_bits": res.capacity_bits,
                  "bits_per_vertex": res.bits_per_vertex, "tolerance": tol, "spread": spread,
                  "precision": STEGO_PRECISION, "n_vertices": res.n_vertices, "read_back": True,
                  "max_move_rel": moved, "seconds_native": t_native + t_check}
        what = f"the file '{fname}'" if fname else f"{len(data)} bytes of text"
        return self.finish(context, result, "INFO",
                           f"meshmark: hid {what} in '{obj.name}' (room for {res.max_message_bytes} bytes); "
                           "it reads back as stored")


class MESHMARK_OT_stego_extract(_Base, bpy.types.Operator):
    """Read the text or file hidden in the active mesh with the key"""
    bl_idname = "meshmark.stego_extract"
    bl_label = "Reveal"
    bl_options = {"REGISTER"}

    key: StringProperty(name="Key", subtype="PASSWORD", options={"SKIP_SAVE"})
    tolerance: _tolerance_arg()
    spread: _spread_arg()
    filepath: StringProperty(name="Save to", subtype="FILE_PATH", options={"SKIP_SAVE"},
                             description="Write what was hidden to this file")

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        key = _key(self, context)
        tol, spread = _stego_settings(self, context)
        out = _abspath(self.filepath if self.properties.is_property_set("filepath") else context.scene.meshmark.stego_save)
        if out and not os.path.isdir(os.path.dirname(out)):
            raise MeshError(f"cannot write '{out}': the folder does not exist")
        mesh = bridge.base_mesh(obj)
        t0 = time.perf_counter()
        got = stego.extract(mesh, key, tolerance=tol, adaptive=spread, precision=STEGO_PRECISION)
        t_native = time.perf_counter() - t0
        result = {"ok": True, "object": obj.name, "found": got.found, "reason": got.reason, "tolerance": tol,
                  "spread": spread, "seconds_native": t_native}
        if not got.found and got.reason in ("too few LSB slots", "carrier too small"):
            raise MeshError(f"mesh too small to hold hidden data ({mesh.n_vertices} vertices)")
        if not got.found:
            return self.finish(context, result, "WARNING",
                               f"meshmark: nothing hidden found in '{obj.name}' with this key and settings")
        data = got.message
        try:
            text = data.decode("utf-8")
        except UnicodeDecodeError:
            text = None
        result.update(bytes=len(data), text=text, hex=data[:64].hex())
        if out:
            with open(out, "wb") as f:
                f.write(data)
            result["saved"] = out
        shown = f"'{text}'" if text is not None and len(text) <= 64 else f"{len(data)} bytes"
        return self.finish(context, result, "INFO", f"meshmark: found {shown} in '{obj.name}'"
                           + (f"; saved to {out}" if out else ""))


# ---------------------------------------------------------------------------------------------
LEVEL_ATTR, CURV_ATTR = "meshmark_level", "meshmark_curvature_change"
LEVEL_COLOR, CURV_COLOR = "Meshmark precision", "Meshmark curvature change"


def heat_colors(x: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """(n, 4) float32 RGBA of ``x`` on a blue (lo) - white - red (hi) ramp, like Fig. 4.7."""
    t = np.clip((np.asarray(x, np.float64) - lo) / (hi - lo), 0.0, 1.0) if hi > lo else np.zeros(len(x))
    rgba = np.empty((len(t), 4), np.float32)
    rgba[:, 0] = np.clip(2.0 * t, 0.0, 1.0)
    rgba[:, 2] = np.clip(2.0 - 2.0 * t, 0.0, 1.0)
    rgba[:, 1] = 1.0 - np.abs(2.0 * t - 1.0)
    rgba[:, 3] = 1.0
    return rgba


def _point_attr(me, name, kind):
    a = me.attributes.get(name)
    if a is not None and (a.domain != "POINT" or a.data_type != kind):
        me.attributes.remove(a)
        a = None
    return a if a is not None else me.attributes.new(name, kind, "POINT")


def analyze_mesh(mesh, tolerance: float, adaptive: bool) -> dict:
    """Levels (n,) and |kappa' - kappa| (n,) after rounding the vertices to those levels (bpy-free)."""
    if adaptive:
        d = analysis.adaptive_details(mesh, tolerance)
        levels, kappa = d["levels"], d["kappa"]
    else:
        levels = np.full(mesh.n_vertices, analysis.quantization_level(mesh, tolerance), np.int64)
        kappa = analysis.gaussian_curvature(mesh)["kappa"]
    q = analysis.quantize(mesh, levels=levels, seed=0)
    dk = np.abs(analysis.gaussian_curvature(q)["kappa"] - kappa)
    return {"levels": levels, "curvature_change": dk}


class MESHMARK_OT_analyze(_Base, bpy.types.Operator):
    """Colour the active mesh by how many bits each vertex needs, and by how much rounding them moves the curvature"""
    bl_idname = "meshmark.analyze"
    bl_label = "Analyze"

    tolerance: _tolerance_arg()
    mode: EnumProperty(name="Levels", options={"SKIP_SAVE"},
                       items=[("ADAPTIVE", "Per vertex", "Each vertex its own precision, by curvature (Fig. 4.7)"),
                              ("GLOBAL", "One for the mesh", "One precision for the whole mesh")])
    show: EnumProperty(name="Show", items=properties.ANALYSIS_SHOW, options={"SKIP_SAVE"})

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        s = context.scene.meshmark
        tol = self.tolerance if self.properties.is_property_set("tolerance") else (
            s.analysis_tolerance if s.analysis_mode == "CUSTOM" else properties.ANALYSIS_TOLERANCE)
        if tol <= 0:
            raise MeshError(f"Shading change must be more than 0 degrees, got {tol}")
        adaptive = (self.mode if self.properties.is_property_set("mode") else "ADAPTIVE") == "ADAPTIVE"
        show = self.show if self.properties.is_property_set("show") else s.analysis_show
        me = obj.data
        mesh = bridge.base_mesh(obj)
        if mesh.n_vertices < 4 or mesh.n_faces < 2:
            raise MeshError(f"mesh too small to analyze: {mesh.n_vertices} vertices, {mesh.n_faces} faces")
        t0 = time.perf_counter()
        a = analyze_mesh(mesh, float(tol), adaptive)
        t_native = time.perf_counter() - t0
        lv, dk = a["levels"], a["curvature_change"]
        ref = mesh.referenced().astype(bool)
        lo, hi = (int(lv[ref].min()), int(lv[ref].max())) if ref.any() else (0, 0)
        dpos = dk[ref & (dk > 0)]
        clo, chi = (float(np.log10(dpos.min())), float(np.log10(dpos.max()))) if dpos.size else (0.0, 0.0)
        logdk = np.log10(np.maximum(dk, dpos.min() if dpos.size else 1.0))
        # everything computed: now the only writes (attributes, never coordinates)
        _point_attr(me, LEVEL_ATTR, "INT").data.foreach_set("value", lv.astype(np.int32))
        _point_attr(me, CURV_ATTR, "FLOAT").data.foreach_set("value", dk.astype(np.float32))
        for name, x, l, h in ((LEVEL_COLOR, lv, lo, hi), (CURV_COLOR, logdk, clo, chi)):
            c = me.color_attributes.get(name)
            if c is not None and (c.domain != "POINT" or c.data_type != "FLOAT_COLOR"):
                me.color_attributes.remove(c)
                c = None
            c = c if c is not None else me.color_attributes.new(name, "FLOAT_COLOR", "POINT")
            c.data.foreach_set("color", heat_colors(x, l, h).ravel())
        show_attr(obj, show)
        me.update()
        hist = np.bincount(lv[ref].astype(np.int64), minlength=33)
        result = {"ok": True, "object": obj.name, "tolerance": float(tol), "adaptive": adaptive,
                  "n_vertices": mesh.n_vertices, "level_min": lo, "level_max": hi,
                  "level_mean": float(lv[ref].mean()) if ref.any() else 0.0,
                  "histogram": {int(i): int(c) for i, c in enumerate(hist) if c},
                  "curvature_change_mean": float(dk[ref].mean()) if ref.any() else 0.0,
                  "curvature_change_max": float(dk.max()), "attributes": [LEVEL_ATTR, CURV_ATTR],
                  "colors": [LEVEL_COLOR, CURV_COLOR], "seconds_native": t_native}
        return self.finish(context, result, "INFO",
                           f"meshmark: '{obj.name}' needs {lo} to {hi} bits per coordinate (mean "
                           f"{result['level_mean']:.1f}) for {tol:g} deg; mean curvature change "
                           f"{result['curvature_change_mean']:.2e} rad")


def show_attr(obj, show: str) -> None:
    """Make the chosen heat map the active colour attribute (what Solid > Attribute shows)."""
    me = obj.data
    name = LEVEL_COLOR if show == "LEVELS" else CURV_COLOR
    c = me.color_attributes.get(name)
    if c is None:
        return
    try:
        me.color_attributes.active_color = c
    except (AttributeError, TypeError):  # pragma: no cover - older API
        pass
    if hasattr(me.color_attributes, "render_color_index"):
        try:
            me.color_attributes.render_color_index = me.color_attributes.active_color_index
        except Exception:  # pragma: no cover
            pass


# ---------------------------------------------------------------------------------------------
_MODELS: dict = {}


def load_model(path: str | None):
    """The steganalysis model (cached per file and modification time); None: the shipped one."""
    from meshmark.steganalysis.model import Model
    sig = (path, os.path.getmtime(path) if path and os.path.exists(path) else None)
    if sig not in _MODELS:
        _MODELS.clear()
        _MODELS[sig] = Model.load(path)
    return _MODELS[sig]


class MESHMARK_OT_steganalysis_detect(_Base, bpy.types.Operator):
    """How likely it is that something is hidden in the active mesh, and by which method"""
    bl_idname = "meshmark.steganalysis_detect"
    bl_label = "Check"
    bl_options = {"REGISTER"}

    model: StringProperty(name="Detector file", subtype="FILE_PATH", options={"SKIP_SAVE"},
                          description="A detector file (empty: the built-in one)")

    def run(self, context):
        obj = bridge.active_mesh_object(context)
        s = context.scene.meshmark
        if self.properties.is_property_set("model"):
            path = _abspath(self.model) or None
        else:
            path = _abspath(s.model_file) if s.model_source == "FILE" else None
            if s.model_source == "FILE" and not path:
                raise MeshError("choose the detector file (or Detector: Built-in)")
        if path is not None and not os.path.isfile(path):
            raise MeshError(f"detector file {path} does not exist")
        model = load_model(path)
        mesh = bridge.base_mesh(obj)
        t0 = time.perf_counter()
        r = model.detect(mesh)
        t_native = time.perf_counter() - t0
        per = dict(sorted(r["methods"].items(), key=lambda kv: -kv[1]))
        result = {"ok": True, "object": obj.name, "model": path or "built-in", "marked": bool(r["marked"]),
                  "probability": r["probability"], "threshold": r.get("threshold", 0.5), "methods": per,
                  "feature_set": r["feature_set"], "classifier": r["classifier"], "seconds_native": t_native}
        if "operating_point" in r:
            result["operating_point"] = r["operating_point"]
        top = next(iter(per.items()), None)
        # the verdict first: the universal score means "marked" only above the model's threshold (the
        # built-in detector's is 0.94, set for few false alarms; docs/steganalysis.md §10)
        verdict = "something is probably hidden" if r["marked"] else "nothing hidden found"
        text = (f"meshmark: '{obj.name}': {verdict} (score {r['probability']:.2f}, threshold "
                f"{result['threshold']:.2f})" + (f"; closest method {top[0]} ({top[1]:.2f})" if r["marked"] and top else ""))
        return self.finish(context, result, "WARNING" if r["marked"] else "INFO", text)


classes = (MESHMARK_OT_stego_embed, MESHMARK_OT_stego_extract, MESHMARK_OT_analyze, MESHMARK_OT_steganalysis_detect)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
    _MODELS.clear()
