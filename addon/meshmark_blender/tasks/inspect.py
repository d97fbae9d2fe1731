"""The precision heat map (meshmark.analysis) and steganalysis (meshmark.steganalysis).

Analyze writes attributes and colours only, never coordinates. Steganalysis gives one of three
states (:func:`meshmark_blender.bridge.steganalysis_verdict`): likely marked, no sign of hidden data,
or cannot judge (the mesh is too small, or unlike anything the detector learned from).
"""
from __future__ import annotations

import os
import time

import numpy as np

from meshmark import MeshError, analysis

from .. import bridge, heatmap, keyfiles, words
from .outcome import Outcome

ANALYZE, DETECT = "meshmark.analyze", "meshmark.steganalysis_detect"
_MODELS: dict = {}


def analyze_mesh(mesh, tolerance: float, adaptive: bool) -> dict:
    """Levels (n,) and |kappa' - kappa| (n,) after rounding the vertices to those levels (bpy-free)."""
    if adaptive:
        d = analysis.adaptive_details(mesh, tolerance)
        levels, kappa = d["levels"], d["kappa"]
    else:
        levels = np.full(mesh.n_vertices, analysis.quantization_level(mesh, tolerance), np.int64)
        kappa = analysis.gaussian_curvature(mesh)["kappa"]
    q = analysis.quantize(mesh, levels=levels, seed=0)
    dk = np.abs(analysis.gaussian_curvature(q)["kappa"] - kappa)  # eq. 5.1.1 per vertex
    return {"levels": levels, "curvature_change": dk}


def analyze_steps(context, obj, *, tolerance=0.1, mode="ADAPTIVE", show="LEVELS"):
    if not tolerance or tolerance <= 0:
        raise MeshError(f"Shading change must be more than 0 degrees, got {tolerance}")
    me = obj.data
    mesh = bridge.base_mesh(obj)
    if mesh.n_vertices < 4 or mesh.n_faces < 2:
        raise MeshError(f"mesh too small to analyze: {mesh.n_vertices} vertices, {mesh.n_faces} faces")
    yield 0.1, f"Analyzing '{obj.name}'"
    t0 = time.perf_counter()
    a = analyze_mesh(mesh, float(tolerance), mode == "ADAPTIVE")
    t_native = time.perf_counter() - t0
    lv, dk = a["levels"], a["curvature_change"]
    ref = mesh.referenced().astype(bool)
    lo, hi = (int(lv[ref].min()), int(lv[ref].max())) if ref.any() else (0, 0)
    dpos = dk[ref & (dk > 0)]
    clo, chi = (float(np.log10(dpos.min())), float(np.log10(dpos.max()))) if dpos.size else (0.0, 0.0)
    logdk = np.log10(np.maximum(dk, dpos.min() if dpos.size else 1.0))
    # everything computed: now the only writes (attributes, never coordinates)
    heatmap.point_attr(me, heatmap.LEVEL_ATTR, "INT").data.foreach_set("value", lv.astype(np.int32))
    heatmap.point_attr(me, heatmap.CURV_ATTR, "FLOAT").data.foreach_set("value", dk.astype(np.float32))
    for name, x, l, h in ((heatmap.LEVEL_COLOR, lv, lo, hi), (heatmap.CURV_COLOR, logdk, clo, chi)):
        heatmap.color_attr(me, name).data.foreach_set("color", heatmap.heat_colors(x, l, h).ravel())
    heatmap.show(obj, show)
    me.update()
    shown = heatmap.show_in_viewports(getattr(context, "screen", None))
    hist = np.bincount(lv[ref].astype(np.int64), minlength=33)
    d = {"tolerance_deg": float(tolerance), "adaptive": mode == "ADAPTIVE", "n_vertices": mesh.n_vertices,
         "level_min": lo, "level_max": hi, "level_mean": float(lv[ref].mean()) if ref.any() else 0.0,
         "histogram": {int(i): int(c) for i, c in enumerate(hist) if c},
         "curvature_change_mean": float(dk[ref].mean()) if ref.any() else 0.0,
         "curvature_change_max": float(dk.max()), "attributes": [heatmap.LEVEL_ATTR, heatmap.CURV_ATTR],
         "colors": [heatmap.LEVEL_COLOR, heatmap.CURV_COLOR], "viewports_set": shown, "seconds_native": t_native}
    text = (f"'{obj.name}' needs {lo} to {hi} bits per coordinate (mean {d['level_mean']:.1f}) for {tolerance:g} "
            "degrees of shading change; the viewport shows it in colour (blue few, red many)")
    return Outcome(ANALYZE, [obj.name], "INFO", text, d)


def load_model(path: str | None):
    """The steganalysis model (cached per file and modification time); None: the built-in one."""
    from meshmark.steganalysis.model import Model
    sig = (path, os.path.getmtime(path) if path and os.path.exists(path) else None)
    if sig not in _MODELS:
        _MODELS.clear()
        _MODELS[sig] = Model.load(path)
    return _MODELS[sig]


STATE_TEXT = {
    "marked": "Something is probably hidden",
    "clean": "No sign of hidden data",
    "too_small": "Cannot judge: too small",
    "out_of_range": "Cannot judge: unusual mesh",
}


def detect_steps(context, obj, *, model=None):
    path = keyfiles.resolve(model, "detector file") if model else None
    if path is not None and not os.path.isfile(path):
        raise MeshError(f"the detector file '{path}' does not exist")
    m = load_model(path)
    mesh = bridge.base_mesh(obj)
    yield 0.1, f"Measuring '{obj.name}'"
    t0 = time.perf_counter()
    r = m.detect(mesh)
    t_native = time.perf_counter() - t0
    v = bridge.steganalysis_verdict(r, mesh.n_vertices)
    per = dict(sorted(r["methods"].items(), key=lambda kv: -kv[1]))
    d = {"model": path or "built-in", "state": v["state"], "why": v["why"], "marked": v["state"] == "marked",
         "probability": r["probability"], "threshold": r.get("threshold", 0.5), "methods": per,
         "feature_set": r["feature_set"], "classifier": r["classifier"], "n_vertices": mesh.n_vertices,
         "seconds_native": t_native}
    if "operating_point" in r:
        d["operating_point"] = r["operating_point"]
    if v["state"] == "cannot_judge":
        reason = (f"it has {mesh.n_vertices} vertices, fewer than the smallest mesh the detector learned from "
                  f"({bridge.STEGANALYSIS_MIN_VERTICES})" if v["why"] == "too_small" else
                  "it is unlike the meshes the detector learned from")
        return Outcome(DETECT, [obj.name], "WARNING", f"The detector cannot judge '{obj.name}': {reason}", d)
    if v["state"] == "marked":
        top = next(iter(per), None)
        text = (f"Something is probably hidden in '{obj.name}' (the detector's score is {words.score(r['probability'])})"
                + (f"; most like the {top.partition(':')[0]} method" if top else ""))
        return Outcome(DETECT, [obj.name], "WARNING", text, d)
    text = (f"No sign of hidden data in '{obj.name}' (score {words.score(r['probability'])}); this detector misses "
            "much of what is hidden, so this is weak evidence")
    return Outcome(DETECT, [obj.name], "INFO", text, d)
