"""Colour a mesh by the precision each vertex needs (and how rounding to it moves the curvature) with
the add-on's analysis operator: two colour attributes, a heat map like the thesis' Fig. 4.7.

    python examples/blender_analyze.py [--mesh FILE] [--tolerance 0.1] [--out heat.blend]
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--tolerance", type=float, default=0.1, help="shading change on a flat part, degrees")
ap.add_argument("--out", help=".blend to save (open it, Solid shading, Color: Attribute)")
a = ap.parse_args(argv())
start()
obj = mesh_object(a.mesh)
bpy.ops.meshmark.analyze(tolerance=a.tolerance)
r = result()
if a.out:
    bpy.ops.wm.save_as_mainfile(filepath=a.out)
print(f"{r['object']}: {r['level_min']} to {r['level_max']} bits per coordinate, colour attributes "
      f"{', '.join(r['colors'])}")
