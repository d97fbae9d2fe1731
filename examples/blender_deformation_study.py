"""Check the mark on every frame of an animation with the add-on's deformation-study operator.

    python examples/blender_deformation_study.py --blend marked.blend --keyfile k.json --out DIR [--bend 20]

If the marked object is not animated, the script bends it over frames 1-10 with a keyframed Simple
Deform modifier (--bend degrees, default 20) first. Writes a CSV and a plot into DIR.
"""
import argparse
import math

from _blender_common import argv, result, select, start

import bpy

ap = argparse.ArgumentParser()
ap.add_argument("--blend", required=True)
ap.add_argument("--keyfile", required=True)
ap.add_argument("--out", required=True, help="folder for the CSV and the plot")
ap.add_argument("--object", help="the marked object (default: the active one)")
ap.add_argument("--bend", type=float, default=20.0, help="degrees of bend when the object is not animated")
a = ap.parse_args(argv())
start(a.blend)
obj = bpy.data.objects[a.object] if a.object else bpy.context.view_layer.objects.active
select(obj)
if obj.animation_data is None and not any(m.type == "ARMATURE" for m in obj.modifiers):
    mod = obj.modifiers.new("Bend", "SIMPLE_DEFORM")
    mod.deform_method, mod.deform_axis = "BEND", "X"
    for frame, deg in ((1, 0.0), (10, a.bend)):
        mod.angle = math.radians(deg)
        obj.keyframe_insert(f'modifiers["{mod.name}"].angle', frame=frame)
bpy.ops.meshmark.deformation_study(keyfile=a.keyfile, frame_start=1, frame_end=10, frame_step=1, output_dir=a.out)
s = result()["summary"]
print(f"mark found on {s['detected_frames']}/{s['frames']} frames, message on {s['message_frames']}, "
      f"mean bits matching {100 * s['mean_cdr']:.1f}%")
