"""``scene.meshmark``: the settings shown in the sidebar and used as the operators' defaults.

Method parameters live in one sub-group per method (``scene.meshmark.params.laplacian.K`` ...),
generated from the method's defaults (:mod:`.params`), so a method registered in
``meshmark.watermark.METHODS`` gets its panel fields with thesis defaults automatically.
"""
from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from meshmark.watermark import METHODS

from . import params as _params

_ENUM_ITEMS = []  # keep the strings alive (Blender does not copy dynamic enum items)
PARAMS_MODE_ITEMS = [("auto", "Automatic", "Choose the parameters for this mesh and message (recorded in the keyfile)"),
                     ("thesis", "Thesis", "The published defaults")]

# The panel's key lives only in this Python session, never in the .blend: scene.meshmark.key is a
# property with a getter and a setter, so Blender stores no value for it in the scene (SKIP_SAVE
# only concerns operator presets, not ID data). One entry per scene settings block, for the session.
_KEYS: dict = {}


def _get_key(self):
    return _KEYS.get(self.as_pointer(), "")


def _set_key(self, value):
    _KEYS[self.as_pointer()] = value


def forget_keys():
    """Drop every key held in memory (on unregister and when another .blend is loaded)."""
    _KEYS.clear()


def _show_heat(self, context):
    """The Show menu switches the heat map of the active object (if it has been analyzed)."""
    obj = getattr(context, "active_object", None)
    if obj is not None and obj.type == "MESH":
        from .hiding_ops import show_attr
        show_attr(obj, self.analysis_show)
        obj.data.update()


def method_items(self, context):
    _ENUM_ITEMS[:] = _params.method_items()
    return _ENUM_ITEMS


PARAM_MODES = [("AUTO", "Auto", "Settings chosen for this mesh and method"),
               ("CUSTOM", "Custom", "Use the settings below")]

# Steganography, analysis, steganalysis: every choice a menu (identifier, label, tooltip)
STEGO_SOURCES = [("TEXT", "Text", "Hide a text typed here"), ("FILE", "File", "Hide the contents of a file")]
STEGO_SPREAD = [("triangle", "Even", "The same shading change everywhere (the default)"),
                ("curvature", "Curved parts", "Hide more where the surface is curved, less where it is flat"),
                ("global", "Uniform", "The same precision on every vertex: holds less")]
STEGO_TOLERANCE = 1.0      # degrees: docs/stego.md (Table 4.4 uses 1 deg)
ANALYSIS_TOLERANCE = 0.1   # degrees: the eps_0 of the heat map in docs/blender.md
ANALYSIS_SHOW = [("LEVELS", "Precision", "Bits each vertex needs: red many, blue few"),
                 ("CURVATURE", "Curvature change", "How much the curvature moves when the vertices are "
                                                   "rounded to those bits: red much, blue little")]
MODEL_SOURCES = [("DEFAULT", "Built-in", "The detector shipped with meshmark"),
                 ("FILE", "From file", "A detector you trained")]


def blender_property(p: _params.Param, **extra):
    """A bpy property for a method parameter (``p``: :class:`params.Param`)."""
    kw = dict(name=p.label, description=p.description, default=p.default, **extra)
    if p.kind == "bool":
        return BoolProperty(**kw)
    if p.kind == "int":
        return IntProperty(min=0, **kw)
    if p.kind == "float":
        return FloatProperty(min=0.0, precision=6 if p.default and p.default < 1e-3 else 3, **kw)
    if p.kind == "enum":
        return EnumProperty(items=p.items, **kw)
    return StringProperty(**kw)


_classes = []


def _build_classes():
    """One PropertyGroup per method, one holding them all, and the settings group."""
    method_groups = {}
    for name in METHODS:
        ann = {p.name: blender_property(p) for p in _params.method_params(name)}
        method_groups[name] = type(f"MESHMARK_PG_params_{name}", (PropertyGroup,), {"__annotations__": ann})
    all_params = type("MESHMARK_PG_params", (PropertyGroup,),
                      {"__annotations__": {n: PointerProperty(type=c) for n, c in method_groups.items()}})
    settings = type("MESHMARK_PG_settings", (PropertyGroup,), {
        "__doc__": "meshmark settings of the scene (scene.meshmark)",
        "__annotations__": {
            "method": EnumProperty(name="Method", description="How the mark is hidden in the mesh",
                                   items=method_items),
            "show_advanced": BoolProperty(name="Advanced", default=False,
                                          description="Show the method's settings and welding"),
            "param_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO",
                                       description="Let meshmark choose the method's settings, or set them"),
            "message": StringProperty(name="Message", description="Text to hide in the mesh (at most 31 bytes; "
                                      "a small mesh holds less: see the capacity line)", default="meshmark"),
            "registry": StringProperty(name="Registry", default="", subtype="FILE_PATH",
                                       description="SQLite registry of issued copies (copy tracing)"),
            "copies": IntProperty(name="Copies", default=10, min=1, description="Copies to issue"),
            "key": StringProperty(name="Key", description="Secret key (kept in memory for this session only: "
                                  "never saved in the .blend; stored in the keyfile unless Store key is off)",
                                  subtype="PASSWORD", get=_get_key, set=_set_key, options={"SKIP_SAVE"}),
            "store_key": BoolProperty(name="Store key in keyfile", default=True,
                                      description="Keep the key in the keyfile; off: the keyfile holds no key and "
                                                  "Verify uses the key typed in the panel"),
            "keyfile": StringProperty(name="Keyfile", description="Keyfile written by Embed and read by Verify "
                                      "(JSON; keep it outside the .blend)", default="", subtype="FILE_PATH"),
            "params": PointerProperty(type=all_params),
            "weld": BoolProperty(name="Weld split vertices", default=True,
                                 description="Treat vertices at exactly the same place (UV seams, flat shading, "
                                             "glTF exports) as one, so the model never cracks open"),
            "evaluated": BoolProperty(name="Check as posed", default=True,
                                      description="Check the mesh as it looks now (armature, shape keys, "
                                                  "modifiers) rather than its rest shape"),
            "frame_start": IntProperty(name="Start", default=1, description="First frame to check"),
            "frame_end": IntProperty(name="End", default=48, description="Last frame to check"),
            "frame_step": IntProperty(name="Step", default=1, min=1, description="Check every n-th frame"),
            "output_dir": StringProperty(name="Folder", default="", subtype="DIR_PATH",
                                         description="Folder where the study writes its table (CSV) and plot"),
            "last_result": StringProperty(name="Last result", default="",
                                          description="JSON result of the last meshmark operator"),
            # Steganography (meshmark.stego): the key is the panel's Key (never saved)
            "stego_source": EnumProperty(name="Hide", items=STEGO_SOURCES, default="TEXT",
                                         description="Hide a text typed here, or the contents of a file"),
            "stego_text": StringProperty(name="Text", default="", description="The text to hide in the mesh"),
            "stego_file": StringProperty(name="File", default="", subtype="FILE_PATH",
                                         description="The file to hide in the mesh"),
            "stego_save": StringProperty(name="Save to", default="", subtype="FILE_PATH",
                                         description="Where Extract writes a hidden file (empty: show the text)"),
            "stego_show_advanced": BoolProperty(name="Advanced", default=False,
                                                description="Show how much the surface may change"),
            "stego_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO",
                                       description="Let meshmark choose, or set the settings below"),
            "stego_tolerance": FloatProperty(name="Shading change", default=STEGO_TOLERANCE, min=0.001, max=45.0,
                                             precision=3, description="How far the surface's shading may turn, "
                                             "in degrees: more hides more, but may show"),
            "stego_spread": EnumProperty(name="Spread", items=STEGO_SPREAD, default="triangle",
                                         description="Where the hidden bits go"),
            # Analysis (meshmark.analysis)
            "analysis_show_advanced": BoolProperty(name="Advanced", default=False,
                                                   description="Show the analysis settings"),
            "analysis_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO",
                                          description="The published settings, or the ones below"),
            "analysis_tolerance": FloatProperty(name="Shading change", default=ANALYSIS_TOLERANCE, min=0.001,
                                                max=45.0, precision=3, description="How far the shading may "
                                                "turn on a flat part, in degrees"),
            "analysis_show": EnumProperty(name="Show", items=ANALYSIS_SHOW, default="LEVELS",
                                          description="Which heat map the viewport shows", update=_show_heat),
            # Steganalysis (meshmark.steganalysis)
            "model_source": EnumProperty(name="Detector", items=MODEL_SOURCES, default="DEFAULT",
                                         description="The detector shipped with meshmark, or one you trained"),
            "model_file": StringProperty(name="File", default="", subtype="FILE_PATH",
                                         description="A detector file made by 'meshmark steganalysis train'"),
            # Study (meshmark.study, run in the background)
            "study_spec": StringProperty(name="Spec", default="", subtype="FILE_PATH",
                                         description="The study to run (a .toml file)"),
            "study_out": StringProperty(name="Folder", default="", subtype="DIR_PATH",
                                        description="Where the study writes its results"),
            "study_progress": FloatProperty(name="Progress", default=0.0, min=0.0, max=100.0, subtype="PERCENTAGE",
                                            precision=0, description="How far the running study is"),
        },
    })
    return [*method_groups.values(), all_params, settings]


def method_settings(settings, method: str) -> dict:
    """The method's parameters from ``scene.meshmark`` (None where 'automatic'). With Settings
    "Auto" every parameter is left to the method (its defaults for the mesh)."""
    if settings.param_mode == "AUTO":
        return {p.name: None for p in _params.method_params(method)}
    group = getattr(settings.params, method)
    return {p.name: p.to_method(getattr(group, p.name)) for p in _params.method_params(method)}


def register():
    _classes[:] = _build_classes()
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.meshmark = PointerProperty(type=_classes[-1])


def unregister():
    forget_keys()
    if hasattr(bpy.types.Scene, "meshmark"):
        del bpy.types.Scene.meshmark
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
    _classes.clear()
