"""Check a marked .blend with the add-on's verify operator (the mesh as posed now, or its rest shape).

    python examples/blender_verify.py --blend marked.blend --keyfile k.json [--object NAME] [--rest]
"""
import argparse

from _blender_common import argv, result, select, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--blend", required=True)
ap.add_argument("--keyfile", required=True)
ap.add_argument("--object", help="the marked object (default: the active one)")
ap.add_argument("--rest", action="store_true", help="check the rest shape instead of the posed mesh")
a = ap.parse_args(argv())
start(a.blend)
if a.object:
    select(bpy.data.objects[a.object])
bpy.ops.meshmark.verify(keyfile=a.keyfile, evaluated=not a.rest)
r = result()
print(("mark found" if r["detected"] else "no mark found") + f": bits matching {100 * r['cdr']:.1f}%, "
      f"message {r['message']!r}")
