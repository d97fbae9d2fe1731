"""How likely a mesh hides something, per method, with the add-on's steganalysis operator.

    python examples/blender_steganalysis.py [--mesh FILE] [--model FILE.npz]
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--model", default="", help="a detector from `meshmark steganalysis train` (default: built-in)")
a = ap.parse_args(argv())
start()
mesh_object(a.mesh)
bpy.ops.meshmark.steganalysis_detect(model=a.model)
r = result()
print(f"{r['object']}: hidden data with probability {r['probability']:.2f}; "
      + ", ".join(f"{m} {p:.2f}" for m, p in r["methods"].items()))
