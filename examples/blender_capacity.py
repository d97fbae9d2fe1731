"""How long a message a mesh can carry, with the add-on's capacity operator.

    python examples/blender_capacity.py [--mesh FILE] [--method laplacian]
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--method", default="laplacian", help="laplacian, radial, cho-mean or cho-variance")
a = ap.parse_args(argv())
start()
mesh_object(a.mesh)
bpy.ops.meshmark.capacity(method=a.method)  # settings not given (K=..., n_thr=...) are the panel's (Auto)
r = result()
print(f"{r['object']}: {r['capacity']} bits with the {a.method} method, up to {r['max_text_bytes']} byte(s) of text")
