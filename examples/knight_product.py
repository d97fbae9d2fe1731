"""The Knight as rigged (its 6 skinned parts, 2,145 welded vertices), every action, default settings:
how often the mark is detected, a 1-byte text is recovered, and a leaked copy out of 100 is traced.

    .venv/bin/python examples/knight_product.py [--step 1] [--out examples/out/knight]

Runs with the `bpy` module. The mark is embedded with ``meshmark.watermark.embed`` (params="auto",
as the add-on's Embed does) into the base mesh and written to Blender exactly as the operator does
(bridge.apply_displacement, float32); each frame's evaluated mesh (armature) is extracted. Tracing:
100 copies issued with ``tracing.issue`` (auto parameters for copies), copy 0037 applied, every frame
traced against the registry.
"""
from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "addon"))
KNIGHT = os.path.join(os.path.dirname(ROOT), "shared", "meshes", "rigged", "Knight.glb")

import bpy  # noqa: E402
import numpy as np  # noqa: E402

from meshmark_blender import bridge  # noqa: E402
from meshmark.watermark import embed, extract, tracing  # noqa: E402



def _import_knight():
    """The Knight (Quaternius, CC0) in an empty scene: its skinned parts and its armature."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=KNIGHT)
    skinned = [o for o in bpy.data.objects
               if o.type == "MESH" and any(m.type == "ARMATURE" for m in o.modifiers)]
    return skinned, bpy.data.objects["Rig"]


def _join(parts, into):
    """Join the parts into one object (the character as one carrier)."""
    bpy.ops.object.select_all(action="DESELECT")
    for o in parts:
        o.select_set(True)
    bpy.context.view_layer.objects.active = into
    bpy.ops.object.join()

def frames(rig, step):
    for act in bpy.data.actions:
        if not act.name or act.users == 0 and False:
            continue
        s, e = (int(round(x)) for x in act.frame_range)
        for f in range(s, e + 1, step):
            yield act, f


def play(knight, rig, step, fn):
    out = []
    scene = bpy.context.scene
    for act, f in frames(rig, step):
        rig.animation_data.action = act
        scene.frame_set(f)
        out.append((act.name, f, fn(bridge.evaluated_mesh(bpy.context, knight))))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--step", type=int, default=1)
    ap.add_argument("--message", default="K")
    ap.add_argument("--out", default=os.path.join(HERE, "out", "knight"))
    ap.add_argument("--params", default="", help="explicit parameters as JSON (default: automatic)")
    ap.add_argument("--no-trace", action="store_true")
    ap.add_argument("--no-mark", action="store_true")
    ap.add_argument("--trace-carriers", type=int, default=tracing.TRACE_CARRIERS)
    ap.add_argument("--trace-copies", type=int, default=10)
    ap.add_argument("--trace-step", type=int, default=4)
    ap.add_argument("--original", action="store_true",
                    help="trace with the unmarked base mesh as the original (informed + blind evidence)")
    a = ap.parse_args(argv)
    os.makedirs(a.out, exist_ok=True)
    skinned, rig = _import_knight()
    _join(skinned, bpy.data.objects["Knight_Body"])
    knight = bpy.data.objects["Knight_Body"]
    base = bridge.base_mesh(knight)
    co0 = bridge.base_coords(knight.data).copy()
    print(f"{len(bpy.data.actions)} actions, {sum(1 for _ in frames(rig, a.step))} frames", flush=True)

    t = time.perf_counter()
    import json
    tracing.TRACE_CARRIERS = a.trace_carriers
    if a.no_mark:
        return trace_part(a, knight, rig, base, co0)
    r = embed(base, payload=a.message, key="knight", **(json.loads(a.params) if a.params else {}))
    bridge.apply_displacement(knight, r.V - base.V)
    print(f"embedded {a.message!r}: {r.capacity} carriers, params {r.keyfile.params}, choice {r.keyfile.choice}",
          flush=True)
    rows = play(knight, rig, a.step, lambda m: extract(m, keyfile=r.keyfile))
    det = np.mean([x.detected for _, _, x in rows])
    msg = np.mean([x.message_ok and x.message == a.message for _, _, x in rows])
    wrong = sum(x.message_ok and x.message != a.message for _, _, x in rows)
    cdr = np.mean([x.cdr for _, _, x in rows])
    print(f"mark: {len(rows)} frames, detected {100 * det:.1f} %, message {100 * msg:.1f} %, wrong messages {wrong}, "
          f"mean CDR {cdr:.3f} ({time.perf_counter() - t:.0f} s)", flush=True)
    with open(os.path.join(a.out, "mark.csv"), "w") as f:
        f.write("action,frame,detected,message_ok,cdr,nc\n")
        for act, fr, x in rows:
            f.write(f"{act},{fr},{int(x.detected)},{int(x.message_ok)},{x.cdr:.4f},{x.nc:.4f}\n")

    if a.no_trace:
        return 0
    return trace_part(a, knight, rig, base, co0)


def _restore(knight, co0):
    knight.data.vertices.foreach_set("co", co0.ravel())
    if knight.data.shape_keys is not None:
        for kb in knight.data.shape_keys.key_blocks:
            kb.data.foreach_set("co", co0.ravel())
    knight.data.update()


def trace_part(a, knight, rig, base, co0):
    """100 copies issued; the first --trace-copies of them applied in turn and traced at every
    --trace-step-th frame of every action; the unmarked Knight traced too."""
    _restore(knight, co0)  # back to the unmarked base
    t = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        reg = os.path.join(tmp, "r.sqlite")
        copies = tracing.issue(base, key="studio", registry=reg, n_copies=100)
        with tracing.Registry(reg) as R:
            (_, setup, C), = R.assets()
        orig = base if a.original else None
        none_rows = play(knight, rig, max(a.step, 4), lambda m: tracing.trace(m, registry=reg, original=orig))
        for cid, V in copies[:a.trace_copies]:
            _restore(knight, co0)
            bridge.apply_displacement(knight, V - base.V)
            rows += [(cid, act, fr, x) for act, fr, x in
                     play(knight, rig, a.trace_step, lambda m: tracing.trace(m, registry=reg, original=orig))]
    right = np.mean([x["copy"] == cid for cid, _, _, x in rows])
    per_copy = {}
    for cid, _, _, x in rows:
        per_copy.setdefault(cid, []).append(x["copy"] == cid)
    wrongc = sum(x["copy"] not in (None, cid) for cid, _, _, x in rows)
    none_named = sum(x["copy"] is not None for _, _, x in none_rows)
    print(f"tracing: {C} carriers ({setup['params']}), {a.trace_copies} of 100 copies each applied and traced on "
          f"every {a.trace_step}th frame: right copy on {100 * right:.1f} % of {len(rows)} frames (per copy "
          f"{', '.join(f'{100 * np.mean(v):.0f}' for v in per_copy.values())} %), a wrong copy on {wrongc}; "
          f"unmarked Knight named a copy on {none_named} of {len(none_rows)} frames ({time.perf_counter() - t:.0f} s)",
          flush=True)
    with open(os.path.join(a.out, "trace.csv"), "w") as f:
        f.write("copy,action,frame,named,p_false_alarm,matches,n_carriers\n")
        for cid, act, fr, x in rows:
            f.write(f"{cid},{act},{fr},{x['copy']},{x['p_false_alarm']:.3g},{x['matches']},{x['n_carriers']}\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
