"""The Knight as an artist marks it: its 6 skinned parts selected, not joined, marked as one carrier
through the add-on's pipeline API; every frame of every action verified; 100 copies issued and a
leaked copy traced on every frame.

    .venv/bin/python examples/knight_parts.py [--part detect|trace|all] [--step 1] [--key knight]
        [--copies 100] [--leaks 0037] [--out build/blender-results] [--actions N] [--quick]

Runs with the bpy module (Blender's own glTF importer reads ../shared/meshes/rigged/Knight.glb).
``detect``: ``api.embed(parts, message=...)`` (automatic parameters, as Embed), then
``api.check_frames`` for each action (the frame check: each frame's parts posed by the armature,
read through their deforming modifiers, joined as the keyfile records them). ``trace``: a fresh
import, ``api.issue(parts, copies=N)``, each leaked copy's file read back and split into the parts
(their base meshes), and ``api.trace(parts)`` on every ``--step``-th frame of every action; then the
unmarked original on every 4 ``--step``-th frame (no copy may be named). Prints and
writes a markdown table and a JSON file into ``--out``.
"""
from __future__ import annotations

import argparse
import json
import os
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(ROOT, "addon"))
SHARED = os.path.join(os.path.dirname(ROOT), "shared", "meshes")

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import meshmark  # noqa: E402

N_ACTIONS = 0  # --actions: the first N actions only (0: all)


def knight(folder):
    """A fresh scene with the Knight, saved in ``folder`` ('//' is there); its skinned parts and rig."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    import meshmark_blender
    if not hasattr(bpy.types.Scene, "meshmark"):
        meshmark_blender.register()
    bpy.ops.import_scene.gltf(filepath=os.path.join(SHARED, "rigged", "Knight.glb"))
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(folder, "knight.blend"))
    parts = sorted((o for o in bpy.data.objects if o.type == "MESH" and any(m.type == "ARMATURE" for m in o.modifiers)),
                   key=lambda o: o.name)
    assert len(parts) == 6, [o.name for o in parts]
    return parts, bpy.data.objects["Rig"]


def actions():
    acts = sorted((a for a in bpy.data.actions if a.name), key=lambda a: a.name)
    return acts[:N_ACTIONS] if N_ACTIONS else acts


def base_coords(obj) -> np.ndarray:
    co = np.empty(3 * len(obj.data.vertices), np.float32)
    obj.data.vertices.foreach_get("co", co)
    return co.reshape(-1, 3)


def frames_of(act, step):
    s, e = (int(round(x)) for x in act.frame_range)
    return list(range(s, e + 1, step))


def detect(args, folder):
    from meshmark_blender import api
    parts, rig = knight(folder)
    t0 = time.perf_counter()
    e = api.embed(parts, message=args.message, key=args.key)
    rows, per = [], []
    for act in actions():
        rig.animation_data.action = act
        fr = frames_of(act, args.step)
        r = api.check_frames(parts[:1], frame_start=fr[0], frame_end=fr[-1], frame_step=args.step,
                             output_dir=os.path.join(folder, "frames"), plot=False)
        got = r.rows
        rows += got
        per.append((act.name, len(got), sum(x["detected"] for x in got), sum(x["message_ok"] for x in got),
                    float(np.mean([x["cdr"] for x in got]))))
    n = len(rows)
    d = {"key": args.key, "message": args.message, "objects": e.objects, "params": e.params, "capacity": e.capacity,
         "welded_vertices": e.welded_vertices, "actions": len(per), "frames": n,
         "detected": sum(x["detected"] for x in rows) / n, "message_ok": sum(x["message_ok"] for x in rows) / n,
         "mean_cdr": float(np.mean([x["cdr"] for x in rows])), "min_cdr": float(min(x["cdr"] for x in rows)),
         "worst_actions": sorted(per, key=lambda p: (p[2] / p[1], p[3] / p[1]))[:5],
         "min_action_detected": min(p[2] / p[1] for p in per), "min_action_message": min(p[3] / p[1] for p in per),
         "seconds": time.perf_counter() - t0}
    return d


def trace(args, folder):
    from meshmark_blender import api
    parts, rig = knight(folder)
    t0 = time.perf_counter()
    made = api.issue(parts, copies=args.copies, key=args.key, registry="//copies.sqlite", output_dir="//copies")
    paths = {c["id"]: c["path"] for c in made.copies}
    rest = {o.name: base_coords(o).copy() for o in parts}
    sizes = np.cumsum([0] + [len(o.data.vertices) for o in parts])
    out = {"copies": len(paths), "issue_seconds": time.perf_counter() - t0, "leaks": {}}
    for leak in args.leaks:
        V = meshmark.read_mesh(paths[leak]).V
        for i, o in enumerate(parts):  # the leaked copy, as the buyer's file puts it back into the rig
            o.data.vertices.foreach_set("co", V[sizes[i]:sizes[i + 1]].astype(np.float32).ravel())
            o.data.update()
        right = wrong = none = 0
        per = []
        for act in actions():
            rig.animation_data.action = act
            got = []
            for f in frames_of(act, args.step):
                bpy.context.scene.frame_set(f)
                got.append(api.trace(parts, registry="//copies.sqlite").copy)
            right += got.count(leak)
            none += got.count(None)
            wrong += len(got) - got.count(leak) - got.count(None)
            per.append((act.name, len(got), got.count(leak) / len(got)))
        n = right + wrong + none
        out["leaks"][leak] = {"frames": n, "right": right / n, "wrong": wrong, "none": none,
                              "min_action_right": min(p[2] for p in per), "worst_actions": sorted(per, key=lambda p: p[2])[:3]}
        for o in parts:
            o.data.vertices.foreach_set("co", rest[o.name].ravel())
            o.data.update()
    # the unmarked original, at rest and posed on every 4th frame of every action: none
    out["original_at_rest"] = api.trace(parts, registry="//copies.sqlite", evaluated=False).copy
    named, ps = 0, []
    for act in actions():
        rig.animation_data.action = act
        for f in frames_of(act, 4 * args.step):
            bpy.context.scene.frame_set(f)
            r = api.trace(parts, registry="//copies.sqlite")
            named += r.copy is not None
            ps.append(r.p_false_alarm)
    out["unmarked"] = {"frames": len(ps), "named": named, "min_p": float(min(ps))}
    out["seconds"] = time.perf_counter() - t0
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--part", choices=["detect", "trace", "all"], default="all")
    ap.add_argument("--step", type=int, default=1, help="every n-th frame")
    ap.add_argument("--key", default="knight")
    ap.add_argument("--message", default="K")
    ap.add_argument("--copies", type=int, default=100)
    ap.add_argument("--leaks", nargs="+", default=["0037"])
    ap.add_argument("--out", default=os.path.join(ROOT, "build", "blender-results"))
    ap.add_argument("--actions", type=int, default=0, help="the first N actions by name only (0: all)")
    ap.add_argument("--quick", action="store_true", help="2 actions, every 4th frame, 5 copies, leak 0003 (tested)")
    args = ap.parse_args(argv)
    if args.quick:
        args.actions, args.step, args.copies, args.leaks = args.actions or 2, 4, 5, ["0003"]
    global N_ACTIONS
    N_ACTIONS = args.actions
    os.makedirs(args.out, exist_ok=True)
    res = {}
    with tempfile.TemporaryDirectory() as folder:
        if args.part in ("detect", "all"):
            res["detect"] = detect(args, folder)
            d = res["detect"]
            print(f"knight parts: {d['frames']} frames of {d['actions']} actions, key {args.key!r}, {d['capacity']} "
                  f"carriers {d['params']}: detected {100 * d['detected']:.1f} %, message {100 * d['message_ok']:.1f} %, "
                  f"mean CDR {d['mean_cdr']:.3f} (min {d['min_cdr']:.3f}); worst action: detected "
                  f"{100 * d['min_action_detected']:.1f} %, message {100 * d['min_action_message']:.1f} %; "
                  f"worst {d['worst_actions']}", flush=True)
        if args.part in ("trace", "all"):
            res["trace"] = trace(args, folder)
            for leak, t in res["trace"]["leaks"].items():
                print(f"knight parts: copy {leak} of {res['trace']['copies']}, {t['frames']} frames: right copy "
                      f"{100 * t['right']:.1f} % (worst action {100 * t['min_action_right']:.1f} %), wrong copy {t['wrong']}, "
                      f"none {t['none']}", flush=True)
            u = res["trace"]["unmarked"]
            print(f"knight parts: the unmarked original posed, {u['frames']} frames: a copy named on {u['named']} "
                  f"(smallest p {u['min_p']:.2g})", flush=True)
    name = f"knight_parts_{args.part}_{args.key}_step{args.step}"
    with open(os.path.join(args.out, name + ".json"), "w") as f:
        json.dump(res, f, indent=1, default=str)
    return 0


if __name__ == "__main__":
    sys.exit(main())
