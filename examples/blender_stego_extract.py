"""Read what is hidden in a mesh of a .blend with the add-on's steganography operator.

    python examples/blender_stego_extract.py --blend hidden.blend [--object Mesh] [--key K] [--out-file FILE]
"""
import argparse

from _blender_common import argv, result, select, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--blend", required=True)
ap.add_argument("--object", default="Mesh")
ap.add_argument("--key", default="example-key")
ap.add_argument("--tolerance", type=float, default=1.0, help="the shading change used when hiding")
ap.add_argument("--out-file", default="", help="write what was hidden to this file")
a = ap.parse_args(argv())
start(a.blend)
select(bpy.data.objects[a.object])
bpy.ops.meshmark.stego_extract(key=a.key, tolerance=a.tolerance, out_file=a.out_file)
r = result()
print(f"{r['object']}: " + (f"found {r['bytes']} bytes" + (f": {r['text']!r}" if r.get("text") else "")
                            if r["found"] else "nothing hidden found with this key"))
