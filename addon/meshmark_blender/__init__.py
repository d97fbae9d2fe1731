"""meshmark for Blender: watermark a mesh from the 3D View sidebar, deform it, check the mark.

The add-on only translates between Blender and the bpy-free ``meshmark`` package (the algorithms
live there): :mod:`.bridge` moves coordinates between Blender meshes and numpy, :mod:`.properties`
holds the settings (``scene.meshmark``), :mod:`.operators` the ``bpy.ops.meshmark.*`` operators,
:mod:`.panels` the "Meshmark" sidebar tab, :mod:`.study` the bpy-free CSV/plot writer of the
deformation study. Methods come from ``meshmark.watermark.METHODS``; their parameters and thesis
defaults are read from the method, so a new method appears in the panel without add-on changes.

Packaging: an extension for Blender 4.2+ (``blender_manifest.toml``, the meshmark wheel under
``wheels/``, built by ``addon/build_extension.py``) and, from the same files, a legacy add-on
(``bl_info``) for older Blenders, which need ``meshmark`` importable on their Python path.
"""

bl_info = {
    "name": "Meshmark",
    "author": "meshmark developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Sidebar > Meshmark",
    "description": "Watermark meshes and check that the mark survives posing and export",
    "category": "Mesh",
}

if "bpy" in locals():  # "Reload Scripts": reload the submodules too
    import importlib
    for _m in ("bridge", "study", "params", "messages", "properties", "operators", "tracing_ops", "hiding_ops", "study_ops", "panels"):
        if _m in locals():
            importlib.reload(locals()[_m])

import bpy  # noqa: E402

try:
    import numpy  # noqa: F401
    import meshmark  # noqa: F401  (the wheel of the extension, or the user's Python path)
    import meshmark.watermark  # noqa: F401
    _IMPORT_ERROR = None
except ImportError as exc:  # report at register time instead of failing on import
    _IMPORT_ERROR = exc

if _IMPORT_ERROR is None:
    from . import bridge, study, params, messages, properties, operators, panels  # noqa: E402,F401


def register():
    if _IMPORT_ERROR is not None:
        raise ImportError(
            "meshmark: the meshmark Python package is not importable in this Blender "
            f"({_IMPORT_ERROR}). Install the meshmark extension zip (Blender 4.2+), or put the "
            "package on Blender's Python path (e.g. PYTHONPATH) for the legacy add-on.")
    properties.register()
    operators.register()
    panels.register()


def unregister():
    panels.unregister()
    operators.unregister()
    properties.unregister()
