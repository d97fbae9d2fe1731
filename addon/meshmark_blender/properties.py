"""``scene.meshmark``: the settings shown in the sidebar and used as the operators' defaults.

Method parameters live in one sub-group per method (``scene.meshmark.params.laplacian.K`` ...),
generated from the method's defaults (:mod:`.params`), so a method registered in
``meshmark.watermark.METHODS`` gets its panel fields with thesis defaults automatically.

Fields that must stay out of the .blend, or must not be rolled back by undo, have a getter and a
setter and no stored value (:mod:`.session`): Key, the text to hide, the last result, the study's
progress. The Keyfile field shows the keyfile of the selected objects (:mod:`.keyfiles`: what was
chosen or written for them, else ``//<object>.meshmark.json``) and setting it sets theirs.
"""
from __future__ import annotations

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty
from bpy.types import PropertyGroup

from meshmark.watermark import METHODS

from . import heatmap, keyfiles, session
from . import params as _params

_ENUM_ITEMS = []  # keep the strings alive (Blender does not copy dynamic enum items)
PARAMS_MODE_ITEMS = [("auto", "Automatic", "Choose the parameters for this mesh and message (recorded in the keyfile)"),
                     ("thesis", "Thesis", "The published defaults")]
PARAM_MODES = [("AUTO", "Auto", "Settings chosen for this mesh and message"),
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
COPY_FORMATS = [(x, x.upper(), f"Write each copy as a .{x} file") for x in ("obj", "ply", "off", "stl")]
AUTO_FILL_MAX_VERTICES = 50_000  # switching to Custom fills in the automatic choice up to this size


def _relative_ok() -> set:
    """The option that lets a path property hold ``//`` (blend-relative) paths where Blender has it
    (4.5+; older versions take such paths without it and refuse the option when a class registers)."""
    if bpy.app.version < (4, 2, 0):
        return set()
    probe = type("MESHMARK_PG_probe", (PropertyGroup,), {"__annotations__": {
        "p": StringProperty(subtype="FILE_PATH", options={"PATH_SUPPORTS_BLEND_RELATIVE"})}})
    try:
        bpy.utils.register_class(probe)
    except (TypeError, ValueError):
        return set()
    bpy.utils.unregister_class(probe)
    return {"PATH_SUPPORTS_BLEND_RELATIVE"}


RELATIVE = _relative_ok()


def path_property(subtype: str = "FILE_PATH", options=frozenset(), **kw):
    """A file or folder path property that may be ``//`` relative to the .blend."""
    return StringProperty(subtype=subtype, options=set(options) | RELATIVE, **kw)


# -- the current objects (the selection with the active object) -------------------------------------------
def current_objects(context=None) -> list:
    """The mesh objects the operators would work on now: the selected meshes and the active one."""
    context = context or bpy.context
    active = getattr(context, "active_object", None)
    objs = {o for o in getattr(context, "selected_objects", ()) or () if o.type == "MESH"}
    if active is not None and active.type == "MESH":
        objs.add(active)
    return sorted(objs, key=lambda o: o.name)


# -- session-backed fields ------------------------------------------------------------------------------
def _get_key(self):
    return session.KEY["value"]


def _set_key(self, value):
    session.KEY["value"] = value


def _get_keyfile(self):
    objs = current_objects()
    return keyfiles.for_objects(objs) if objs else ""


def _set_keyfile(self, value):
    objs = current_objects()
    if objs:
        keyfiles.remember(objs, value)


def _text_field(name):
    return (lambda self: session.TEXT.get(name, "")), (lambda self, v: session.TEXT.__setitem__(name, v))


def _get_result(self):
    return session.RESULT["json"]


def _set_result(self, value):
    session.RESULT["json"] = value


def _get_progress(self):
    job = session.JOB["running"]
    return 100.0 * job.fraction if job is not None else 0.0


def _show_heat(self, context):
    """The Show menu switches the heat map of the active object (if it has been analyzed)."""
    obj = getattr(context, "active_object", None)
    if obj is not None and obj.type == "MESH":
        heatmap.show(obj, self.analysis_show)
        obj.data.update()


def _fill_custom(self, context):
    """Switching Settings to Custom starts from what Auto would use (so nothing changes until edited)."""
    if self.param_mode != "CUSTOM":
        return
    objs = current_objects(context)
    if not objs or sum(len(o.data.vertices) for o in objs) > AUTO_FILL_MAX_VERTICES:
        return
    from . import targets
    from .tasks.watermark import plan
    try:
        d = plan(targets.Target(objs), self.method, self.message, None, "auto", self.weld)
    except Exception:  # a mesh too small: the fields keep their values, the panel says why
        return
    group = getattr(self.params, self.method)
    for p in _params.panel_params(self.method):
        v = d["params"].get(p.name)
        if v is not None:
            setattr(group, p.name, v)


def method_items(self, context):
    _ENUM_ITEMS[:] = _params.method_items()
    return _ENUM_ITEMS


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


def _session(name, label, description, **kw):
    get, set_ = _text_field(name)
    return StringProperty(name=label, description=description, get=get, set=set_, options={"SKIP_SAVE"}, **kw)


def _settings_annotations() -> dict:
    return {
        "method": EnumProperty(name="Method", description="How the mark is hidden in the mesh", items=method_items),
        "show_advanced": BoolProperty(name="Advanced", default=False, description="Show the method's settings and welding"),
        "param_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO", update=_fill_custom,
                                   description="Let meshmark choose the method's settings, or set them"),
        "message": StringProperty(name="Message", default="meshmark", description="Text to hide in the mesh (at most "
                                  "31 bytes; a small mesh holds less: see the line below)"),
        "key": StringProperty(name="Key", subtype="PASSWORD", get=_get_key, set=_set_key, options={"SKIP_SAVE"},
                              description="Secret key (kept in memory for this session only: never saved in the "
                                          ".blend; stored in the keyfile unless Store key is off)"),
        "store_key": BoolProperty(name="Store key in keyfile", default=True,
                                  description="Keep the key in the keyfile (and the registry of copies); off: they "
                                              "hold no key and Verify and Trace use the key typed in the panel"),
        "keyfile": path_property(name="Keyfile", get=_get_keyfile, set=_set_keyfile, options={"SKIP_SAVE"},
                                  description="The keyfile of the selected objects: written by "
                                  "Embed, read by Verify (one per object, beside the .blend, unless you choose another)"),
        "weld": BoolProperty(name="Weld split vertices", default=True,
                             description="Treat vertices at exactly the same place (UV seams, flat shading, glTF "
                                         "exports) as one, so the model never cracks open"),
        "evaluated": BoolProperty(name="Check as posed", default=True,
                                  description="Check the mesh as it looks now (armature, shape keys, lattices) rather "
                                              "than its rest shape; modifiers that add vertices are left out"),
        "last_result": StringProperty(name="Last result", get=_get_result, set=_set_result, options={"SKIP_SAVE"},
                                      description="The last meshmark operator's result as JSON (this session only)"),
        # frames (the deformation study)
        "frames_auto": BoolProperty(name="Frames of the animation", default=True,
                                    description="Check the frames of the action playing on the armature (else the "
                                                "scene's range); off: the range below"),
        "frame_start": IntProperty(name="Start", default=1, description="First frame to check"),
        "frame_end": IntProperty(name="End", default=250, description="Last frame to check"),
        "frame_step": IntProperty(name="Step", default=1, min=1, description="Check every n-th frame"),
        "output_dir": path_property("DIR_PATH", name="Save table to", default="//meshmark/",
                                     description="Folder where the frame check writes its table (CSV) and plot"),
        # copy tracing
        "registry": path_property(name="Registry", default="//meshmark-copies.sqlite",
                                   description="The file that records every issued copy (to find whose copy leaked)"),
        "copies": IntProperty(name="Copies", default=10, min=1, description="How many copies Issue makes"),
        "copies_dir": path_property("DIR_PATH", name="Copies to", default="//copies/",
                                     description="Folder the issued copies are written to"),
        "copies_format": EnumProperty(name="Format", items=COPY_FORMATS, default="obj",
                                      description="File format of the issued copies"),
        # steganography (meshmark.stego): the key is the panel's Key (never saved)
        "stego_source": EnumProperty(name="Hide", items=STEGO_SOURCES, default="TEXT",
                                     description="Hide a text typed here, or the contents of a file"),
        "stego_text": _session("stego_text", "Text", "The text to hide in the mesh (this session only: never saved "
                               "in the .blend)"),
        "stego_file": path_property(name="File", default="", description="The file to hide in the mesh"),
        "stego_save": path_property(name="Save to", default="",
                                     description="Where Reveal writes what it finds (empty: show the text)"),
        "stego_show_advanced": BoolProperty(name="Advanced", default=False, description="Show how much the surface may change"),
        "stego_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO",
                                   description="Let meshmark choose, or set the settings below"),
        "stego_tolerance": FloatProperty(name="Shading change", default=STEGO_TOLERANCE, min=0.001, max=45.0, precision=3,
                                         description="How far the surface's shading may turn, in degrees: more hides "
                                                     "more, but may show"),
        "stego_spread": EnumProperty(name="Spread", items=STEGO_SPREAD, default="triangle", description="Where the hidden bits go"),
        # analysis (meshmark.analysis)
        "analysis_show_advanced": BoolProperty(name="Advanced", default=False, description="Show the analysis settings"),
        "analysis_mode": EnumProperty(name="Settings", items=PARAM_MODES, default="AUTO",
                                      description="The published settings, or the ones below"),
        "analysis_tolerance": FloatProperty(name="Shading change", default=ANALYSIS_TOLERANCE, min=0.001, max=45.0,
                                            precision=3, description="How far the shading may turn on a flat part, in degrees"),
        "analysis_show": EnumProperty(name="Show", items=ANALYSIS_SHOW, default="LEVELS", update=_show_heat,
                                      description="Which heat map the viewport shows"),
        # steganalysis (meshmark.steganalysis)
        "model_source": EnumProperty(name="Detector", items=MODEL_SOURCES, default="DEFAULT",
                                     description="The detector shipped with meshmark, or one you trained"),
        "model_file": path_property(name="File", default="",
                                     description="A detector file made by 'meshmark steganalysis train'"),
        # study (meshmark.study, run in the background)
        "study_spec": path_property(name="Study file", default="",
                                     description="The study to run (a .toml file, see docs/studies.md)"),
        "study_out": path_property("DIR_PATH", name="Results to", default="//study/",
                                    description="Folder where the study writes its results"),
        "study_progress": FloatProperty(name="Progress", min=0.0, max=100.0, subtype="PERCENTAGE", precision=0,
                                        get=_get_progress, description="How far the running task is"),
    }


_classes = []


def _build_classes():
    """One PropertyGroup per method, one holding them all, and the settings group."""
    method_groups = {}
    for name in METHODS:
        ann = {p.name: blender_property(p) for p in _params.method_params(name)}
        method_groups[name] = type(f"MESHMARK_PG_params_{name}", (PropertyGroup,), {"__annotations__": ann})
    all_params = type("MESHMARK_PG_params", (PropertyGroup,),
                      {"__annotations__": {n: PointerProperty(type=c) for n, c in method_groups.items()}})
    ann = _settings_annotations()
    ann["params"] = PointerProperty(type=all_params)
    settings = type("MESHMARK_PG_settings", (PropertyGroup,),
                    {"__doc__": "meshmark settings of the scene (scene.meshmark)", "__annotations__": ann})
    return [*method_groups.values(), all_params, settings]


def method_settings(settings, method: str):
    """(params, method_params) for Embed from the panel: Auto -> ``("auto", {})``; Custom -> every
    field the panel shows, as given parameters (``"thesis"`` defaults for the rest)."""
    if settings.param_mode == "AUTO":
        return "auto", {}
    group = getattr(settings.params, method)
    return {p.name: p.to_method(getattr(group, p.name)) for p in _params.panel_params(method)}, {}


def register():
    _classes[:] = _build_classes()
    for c in _classes:
        bpy.utils.register_class(c)
    bpy.types.Scene.meshmark = PointerProperty(type=_classes[-1])
    bpy.types.Object.meshmark_keyfile = path_property(
        name="Meshmark keyfile", options={"HIDDEN"},
        description="The keyfile of this object's mark (a path; the key is never stored in the .blend)")


def unregister():
    session.forget()
    for owner, name in ((bpy.types.Object, "meshmark_keyfile"), (bpy.types.Scene, "meshmark")):
        if hasattr(owner, name):
            delattr(owner, name)
    for c in reversed(_classes):
        bpy.utils.unregister_class(c)
    _classes.clear()
