"""Hide a text (or a file) in a mesh with the add-on's steganography operator, and save the .blend.

    python examples/blender_stego_embed.py --out hidden.blend [--mesh FILE] [--message T | --message-file F] [--key K]

The mesh is written in float32 (what Blender stores) and read back before the operator reports success.
"""
import argparse

from _blender_common import argv, mesh_object, result, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--mesh", help="OBJ/OFF/PLY/STL (default: a built-in tube)")
ap.add_argument("--message", default="Meet at the bridge at noon", help="the text to hide")
ap.add_argument("--message-file", help="hide this file instead of the text")
ap.add_argument("--key", default="example-key")
ap.add_argument("--tolerance", type=float, default=1.0, help="shading change allowed, degrees")
ap.add_argument("--out", required=True, help=".blend to save")
a = ap.parse_args(argv())
start()
mesh_object(a.mesh)
what = dict(message_file=a.message_file) if a.message_file else dict(message=a.message)
bpy.ops.meshmark.stego_embed(key=a.key, tolerance=a.tolerance, **what)
r = result()
bpy.ops.wm.save_as_mainfile(filepath=a.out)  # the key is not saved in it
print(f"{r['object']}: hid {r['bytes']} bytes (room for {r['max_bytes']}); saved {a.out}")
