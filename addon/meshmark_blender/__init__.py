"""meshmark for Blender: watermark a mesh (or a character of several parts) from the 3D View sidebar,
pose it, check the mark; hide data; trace copies; run studies.

The add-on only translates between Blender and the bpy-free ``meshmark`` package (the algorithms
live there). Layers, each importing only the ones above it:

* bpy-free: :mod:`.params` (method parameters and their labels), :mod:`.messages` and :mod:`.words`
  (errors and figures in an artist's words), :mod:`.session` (what is kept for the session only),
  :mod:`.study` (the frame check's CSV and plot), :mod:`.study_runner` (a study's own process);
* Blender data: :mod:`.bridge` (meshes <-> numpy, the posed cage, the steganalysis verdict),
  :mod:`.targets` (the objects one mark covers), :mod:`.keyfiles` (one keyfile per object),
  :mod:`.heatmap`;
* the work: :mod:`.tasks` (each task a generator of steps) and :mod:`.api` (the pipeline API over it);
* the UI: :mod:`.properties` (``scene.meshmark``), :mod:`.operators` (``bpy.ops.meshmark.*``, thin over
  the tasks) and :mod:`.panels` (the "Meshmark" sidebar tab), registered here.

Packaging: an extension for Blender 4.2+ (``blender_manifest.toml``; the meshmark wheel and every
package it imports under ``wheels/``, built by ``addon/build_extension.py``; module
``bl_ext.<repository>.meshmark``) and, from the same files, a legacy add-on (``bl_info``) for older
Blenders, which need ``meshmark`` importable on their Python path.
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

_MODULES = ("params", "messages", "words", "session", "study", "bridge", "targets", "keyfiles", "heatmap",
            "tasks.outcome", "tasks.watermark", "tasks.frames", "tasks.copies", "tasks.hiding", "tasks.inspect",
            "tasks.study", "api", "properties", "operators.base", "operators.watermark", "operators.keyfile_ops",
            "operators.copies", "operators.hiding", "operators.inspect_ops", "operators.study_ops", "operators",
            "panels.layout", "panels.results", "panels.watermark", "panels.tasks", "panels")

if "bpy" in locals():  # "Reload Scripts": reload the submodules too, in dependency order
    import importlib
    import sys
    for _m in _MODULES:
        _full = f"{__name__}.{_m}"
        if _full in sys.modules:
            importlib.reload(sys.modules[_full])

import bpy  # noqa: E402

try:
    import numpy  # noqa: F401
    import meshmark  # noqa: F401  (the wheel of the extension, or the user's Python path)
    import meshmark.watermark  # noqa: F401
    _IMPORT_ERROR = None
except ImportError as exc:  # report at register time instead of failing on import
    _IMPORT_ERROR = exc

if _IMPORT_ERROR is None:
    from . import api, operators, panels, properties  # noqa: E402,F401


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
