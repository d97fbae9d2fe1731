"""Hide a message in a mesh with the add-on's embed operator and save the .blend.

    python examples/blender_embed.py --keyfile k.json --out marked.blend [--mesh FILE] [--message M] [--key K]
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--message", default="M")
ap.add_argument("--key", default="example-key")
ap.add_argument("--keyfile", required=True, help="where the keyfile goes (keep it, and out of the .blend)")
ap.add_argument("--out", help="save the marked scene as this .blend")
a = ap.parse_args(argv())
start()
obj = mesh_object(a.mesh)
bpy.ops.meshmark.embed(message=a.message, key=a.key, keyfile=a.keyfile)  # raises RuntimeError on bad input
r = result()
print(f"embedded {a.message!r} into {obj.name!r}: {r['capacity']} bits, read back as stored: {r['stored_cdr']:.3f}")
if a.out:
    bpy.ops.wm.save_as_mainfile(filepath=a.out)
