"""How long a message a mesh can carry, with the add-on's capacity operator.

    python examples/blender_capacity.py [--mesh FILE] [--method laplacian] [--message TEXT] [--params thesis]

The figures are those Embed would use for the message (Settings Auto: the automatic choice, the
same call Embed makes), or the published parameters with ``--params thesis``.
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--method", default="laplacian", help="laplacian, radial, cho-mean or cho-variance")
ap.add_argument("--message", default="meshmark", help="the message Embed would hide")
ap.add_argument("--params", default="auto", choices=["auto", "thesis"])
a = ap.parse_args(argv())
start()
mesh_object(a.mesh)
bpy.ops.meshmark.capacity(method=a.method, message=a.message, params=a.params)
r = result()
print(f"{r['object']}: {r['capacity']} bits with the {a.method} method ({a.params} parameters), up to "
      f"{r['max_text_bytes']} byte(s) of text")
