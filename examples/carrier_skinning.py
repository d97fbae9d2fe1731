"""Which Laplacian carrier scalar survives skinning? (issue 10 item 4; docs/carrier.md)

Runs in the venv's Python with the bpy wheel (Blender as a module):

    nice -n 5 .venv/bin/python examples/carrier_skinning.py [--rigs knight,fox,arm,hand,elephant]
        [--step 2] [--budget 180] [--pipeline knight,arm] [--keys 3] [--out build/carrier]

Rigs: the shared rigged characters (Knight: its 6 skinned parts joined, 2,145 welded vertices, all 76
actions; Fox: 290 welded, 3 actions), the procedural arm of blender_tests/rigs.py (20,482 vertices,
two bones, automatic weights) and two shared meshes with a generated two-bone PCA armature
(blender_tests/test_rig_shared.py: classic/hand.obj, classic/elephant.off). The generated rigs have
no actions: their "frames" are a sweep of bends (0-90 degrees) and twists (0-90) and both combined.

Part 1 (no embedding), for every candidate carrier of native/include/meshmark/laplacian_carrier.h and
every frame (every --step-th frame of every action, at most --budget seconds per rig):
  * flip: the fraction of vertices whose bin (K bins over the rest pose's [min, max], eq. 7.1.6)
    differs from the rest pose's; flip_mid: the same for the vertices that sit in the middle half of
    their bin at rest (where the embedding puts the lengths it moves: the effect of bin placement);
  * med_iqr: median |s_frame - s_rest| over the rest-pose interquartile range; med_bin: the same in
    bin widths, p90_bin its 90th percentile; unchanged: fraction with |ds| < 1e-3 IQR (unchanged to
    float32 precision: Blender skins in float32).
  Bins: K of the rig's test parameters, and half and twice that (margins vs bin width).

Part 2 (--pipeline): embed a one-letter message with each carrier (same K, n_thr, n_robust as the
rig's test) under --keys keys, write the marked positions into the Blender mesh (float32), and
extract at every frame: detected / message / CDR per frame, per carrier. Plus the false alarms with
each carrier: the marked mesh read with 20 wrong keys at every 10th frame, and the unmarked mesh
read with the keyfiles at every frame.

Writes CSVs and markdown tables into --out (default build/carrier/).
"""
from __future__ import annotations

import argparse
import json
import math
import os
import pathlib
import sys
import time

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "examples"))

import bpy  # noqa: E402

import meshmark  # noqa: E402
import meshmark.watermark  # noqa: E402
from _common import write_csv  # noqa: E402
from blender_tests import rigs  # noqa: E402
from meshmark import _core  # noqa: E402
from meshmark.watermark import laplacian as lap  # noqa: E402
from meshmark.watermark.keyfile import save_keyfile  # noqa: E402
from meshmark_blender import bridge  # noqa: E402

# Exploratory carriers, measured here only (not offered by meshmark: see docs/carrier.md): the native
# asinh compression of laplacian_carrier.h, bins growing with |s|.
lap.CARRIERS.update({"thesis_asinh": (0, 0.25, True), "normal_asinh": (2, 0.1, False)})
CARRIERS = list(lap.CARRIERS)
NO_RANGE_SEARCH = False
KNIGHT_PARTS = ["Knight_ArmLeft", "Knight_ArmRight", "Knight_Body", "Knight_Head", "Knight_LegLeft", "Knight_LegRight"]
SWEEP = [(b, 0) for b in range(0, 91, 10)] + [(0, t) for t in range(10, 91, 10)] + [(b, b) for b in range(10, 91, 20)]


# --- scenes ------------------------------------------------------------------------------------
class Rig:
    """A skinned object and the frames to play: a list of callables that pose the scene."""

    def __init__(self, name, obj, frames, params, message="K"):
        self.name, self.obj, self.frames, self.params, self.message = name, obj, frames, params, message


def _actions_frames(rig_obj, actions, step):
    frames = []
    for name in actions:
        act = bpy.data.actions[name]
        s, e = (int(round(x)) for x in act.frame_range)
        for f in range(s, e + 1, step):
            frames.append((f"{name}:{f}", (lambda a=act, f=f: (_set_action(rig_obj, a), bpy.context.scene.frame_set(f)))))
    return frames


def _set_action(rig_obj, act):
    if rig_obj.animation_data.action is not act:
        rig_obj.animation_data.action = act


def knight(step):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Knight.glb"))
    bpy.ops.object.select_all(action="DESELECT")
    parts = [bpy.data.objects[n] for n in KNIGHT_PARTS]
    for o in parts:
        o.select_set(True)
    body = bpy.data.objects["Knight_Body"]
    bpy.context.view_layer.objects.active = body
    bpy.ops.object.join()
    rig = bpy.data.objects["Rig"]
    actions = sorted(a.name for a in bpy.data.actions)
    return Rig("knight", body, _actions_frames(rig, actions, step), {"K": 100, "n_thr": 4, "n_robust": 1})


def fox(step):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=rigs.shared_mesh("rigged/Fox.glb"))
    rig = bpy.data.objects["root"]
    return Rig("fox", bpy.data.objects["fox"], _actions_frames(rig, ["Survey", "Walk", "Run"], step),
               {"K": 80, "n_thr": 1, "n_robust": 1}, "F")


def _sweep_frames(skel):
    return [(f"bend{b}_twist{t}", (lambda b=b, t=t: rigs.pose(skel, "b1", bend_deg=b, twist_deg=t))) for b, t in SWEEP]


def arm(step):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    obj = rigs.mesh_object("Arm", mesh=rigs.jittered_arm())
    skel = rigs.chain_armature("ArmRig", [(0, 0, 0), (0, 0, 1.0), (0, 0, 2.0)])
    rigs.rig_auto(obj, skel)
    return Rig("arm", obj, _sweep_frames(skel), {}, "M")


def shared(rel, how, params, message):
    def make(step):
        bpy.ops.wm.read_factory_settings(use_empty=True)
        path = rigs.shared_mesh(rel)
        if how == "obj":
            bpy.ops.wm.obj_import(filepath=path)
            obj = bpy.context.active_object
        else:
            obj = rigs.mesh_object(pathlib.Path(rel).stem, mesh=meshmark.read_mesh(path))
        base = meshmark.Mesh.from_polygons(rigs.base_coords(obj).astype(float), *rigs.bridge_faces(obj))
        skel = rigs.chain_armature("Rig", rigs.pca_chain(base, 2))
        rigs.rig_auto(obj, skel)
        return Rig(pathlib.Path(rel).stem, obj, _sweep_frames(skel), params, message)
    return make


RIGS = {"knight": knight, "fox": fox, "arm": arm,
        "hand": shared("classic/hand.obj", "obj", {"K": 230, "n_thr": 4, "n_robust": 1}, "H"),
        "elephant": shared("classic/elephant.off", "meshmark", {}, "E")}


# --- part 1: the scalar under skinning ---------------------------------------------------------------
def welded_positions(obj, first):
    return bridge.evaluated_mesh(bpy.context, obj).V[first]


def carrier_study(r: Rig, budget: float):
    base = bridge.base_mesh(r.obj)
    w = meshmark.weld_vertices(base)
    wm = w.mesh
    ref = wm.referenced() == 1
    E, T = wm.edges(), np.ascontiguousarray(wm.triangles, np.int32)
    K0 = r.params.get("K") or int(math.ceil(ref.sum() / 70))
    Ks = sorted({max(8, K0 // 2), K0, 2 * K0})
    rest = {c: lap.carrier_values(wm, c)[ref] for c in CARRIERS}
    stats = {}
    for c, s0 in rest.items():
        lo, hi = s0.min(), s0.max()
        q1, q3 = np.percentile(s0, [25, 75])
        stats[c] = {"iqr": q3 - q1, "lo": lo, "hi": hi}
    rows = []
    t0 = time.time()
    for label, setf in r.frames:
        if time.time() - t0 > budget:
            break
        setf()
        V = welded_positions(r.obj, w.first)
        m = wm.with_vertices(V)
        for c in CARRIERS + [x + "+rescale" for x in CARRIERS if lap.CARRIERS[x][2]]:
            s = lap.carrier_values(m, c.split("+")[0])[ref]
            s0, st = rest[c.split("+")[0]], stats[c.split("+")[0]]
            if c.endswith("+rescale"):  # the global unit corrected as well as one factor can (cf. the range search)
                ok = np.abs(s) > 1e-12
                s = s * np.median(s0[ok] / s[ok])
            ds = np.abs(s - s0)
            row = {"rig": r.name, "frame": label, "carrier": c,
                   "med_iqr": float(np.median(ds) / st["iqr"]),
                   "unchanged": float((ds < 1e-3 * st["iqr"]).mean())}
            for K in Ks:
                delta = (st["hi"] - st["lo"]) / K
                b0 = np.clip(np.floor((s0 - st["lo"]) / delta), 0, K - 1)
                b = np.clip(np.floor((s - st["lo"]) / delta), 0, K - 1)
                frac = (s0 - st["lo"]) / delta - b0
                mid = (frac >= 0.25) & (frac <= 0.75)
                row[f"flip_K{K}"] = float((b != b0).mean())
                row[f"flip_mid_K{K}"] = float((b[mid] != b0[mid]).mean())
                row[f"med_bin_K{K}"] = float(np.median(ds) / delta)
                row[f"p90_bin_K{K}"] = float(np.percentile(ds, 90) / delta)
            rows.append(row)
    return rows, Ks, len({x["frame"] for x in rows}), wm.n_vertices


def summarise_study(rows, Ks):
    out = []
    for c in dict.fromkeys(x["carrier"] for x in rows):
        sel = [x for x in rows if x["carrier"] == c]
        if not sel:
            continue
        agg = {"carrier": c, "frames": len(sel),
               "med_iqr": float(np.mean([x["med_iqr"] for x in sel])),
               "unchanged": float(np.mean([x["unchanged"] for x in sel]))}
        for K in Ks:
            for k in ("flip", "flip_mid", "med_bin", "p90_bin"):
                agg[f"{k}_K{K}"] = float(np.mean([x[f"{k}_K{K}"] for x in sel]))
        out.append(agg)
    return out


# --- part 2: embed, then extract per frame -------------------------------------------------------
def matched_K(base, carrier, params, n_carriers):
    """The smallest K (in steps of 2) at which ``carrier`` offers at least ``n_carriers`` carriers with the
    rig's n_thr and n_robust: compares the scalars at the same capacity, not at the same K."""
    p = {k: v for k, v in params.items() if k != "K"}
    for K in range(20, 1001, 2):
        if meshmark.watermark.capacity(base.V, base, carrier=carrier, K=K, **p) >= n_carriers:
            return K
    raise meshmark.MeshError(f"no K gives {n_carriers} carriers with carrier {carrier}")


def pipeline(r: Rig, carriers, keys, budget: float, out: pathlib.Path, match_capacity: int = 0):
    base = bridge.base_mesh(r.obj)
    V0 = rigs.base_coords(r.obj).copy()
    marks = []  # (carrier, key, keyfile path, marked float32 coords)
    info = []
    for c in carriers:
        params = dict(r.params)
        if match_capacity < 0:  # the thesis carrier's capacity at the rig's parameters
            match_capacity = meshmark.watermark.capacity(base.V, base, carrier="thesis", **r.params)
        if match_capacity:
            params["K"] = matched_K(base, c, r.params, match_capacity)
        for key in keys:
            try:
                t = time.time()
                e = meshmark.watermark.embed(base.V, base, payload=r.message, key=key, method="laplacian", carrier=c,
                                             **params)
                t_embed = time.time() - t
            except meshmark.MeshError as ex:
                info.append({"rig": r.name, "carrier": c, "key": key, "error": str(ex)})
                continue
            if NO_RANGE_SEARCH:
                e.keyfile.side_info["range_search"] = False
            kf = out / f"{r.name}-{c}-{key}.json"
            save_keyfile(e.keyfile, kf)
            Vm = e.V.astype(np.float32)
            # read back at rest, float32 as Blender stores it
            x = meshmark.watermark.extract(Vm.astype(float), base, keyfile=str(kf))
            info.append({"rig": r.name, "carrier": c, "key": key, "K": e.keyfile.params["K"], "capacity": e.capacity,
                         "rest_cdr": x.cdr,
                         "rest_message": x.message_ok, "embed_s": round(t_embed, 3),
                         "rounds": e.stats.get("rounds"), "n_solve_rounds": e.stats.get("n_solve_rounds")})
            marks.append((c, key, str(kf), Vm))
    me = r.obj.data
    rows, fa = [], []
    t0 = time.time()
    for fi, (label, setf) in enumerate(r.frames):
        if time.time() - t0 > budget:
            break
        setf()
        for c, key, kf, Vm in marks:
            me.vertices.foreach_set("co", Vm.ravel())
            me.update()
            m = bridge.evaluated_mesh(bpy.context, r.obj)
            x = meshmark.watermark.extract(m.V, m, keyfile=kf)
            rows.append({"rig": r.name, "frame": label, "carrier": c, "key": key, "cdr": x.cdr,
                         "detected": int(x.detected), "message": int(x.message_ok and x.message is not None)})
            if fi % 10 == 0:  # false alarms: wrong keys on the marked mesh
                for j in range(5):
                    y = meshmark.watermark.extract(m.V, m, keyfile=kf, key=f"wrong-{j}-{key}")
                    fa.append({"rig": r.name, "frame": label, "carrier": c, "case": "wrong key",
                               "detected": int(y.detected), "message": int(y.message_ok)})
        # unmarked mesh at this frame, read with every keyfile
        me.vertices.foreach_set("co", V0.ravel())
        me.update()
        m = bridge.evaluated_mesh(bpy.context, r.obj)
        for c, key, kf, _ in marks:
            y = meshmark.watermark.extract(m.V, m, keyfile=kf)
            fa.append({"rig": r.name, "frame": label, "carrier": c, "case": "unmarked",
                       "detected": int(y.detected), "message": int(y.message_ok)})
    me.vertices.foreach_set("co", V0.ravel())
    me.update()
    return rows, fa, info


def summarise_pipeline(rows, fa, info):
    out = []
    for c in dict.fromkeys(x["carrier"] for x in rows):
        sel = [x for x in rows if x["carrier"] == c]
        f = [x for x in fa if x["carrier"] == c]
        caps = sorted({i["capacity"] for i in info if i["carrier"] == c and "capacity" in i})
        Ks = sorted({i["K"] for i in info if i["carrier"] == c and "K" in i})
        out.append({"carrier": c, "K": "/".join(map(str, Ks)), "capacity": "/".join(map(str, caps)), "frames": len(sel),
                    "mean_cdr": float(np.mean([x["cdr"] for x in sel])), "min_cdr": float(np.min([x["cdr"] for x in sel])),
                    "detected": float(np.mean([x["detected"] for x in sel])),
                    "message": float(np.mean([x["message"] for x in sel])),
                    "false_tests": len(f), "false_detected": int(sum(x["detected"] for x in f)),
                    "false_messages": int(sum(x["message"] for x in f))})
    return out


def md_table(rows, cols=None):
    cols = cols or list(rows[0])
    fmt = lambda v: f"{v:.3f}" if isinstance(v, float) else str(v)
    return "\n".join(["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)] +
                     ["| " + " | ".join(fmt(r[c]) for c in cols) + " |" for r in rows]) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--rigs", default="knight,fox,arm,hand,elephant")
    ap.add_argument("--step", type=int, default=2)
    ap.add_argument("--budget", type=float, default=180.0, help="seconds per rig and part")
    ap.add_argument("--pipeline", default="", help="rigs for part 2 (comma separated)")
    ap.add_argument("--carriers", default=",".join(CARRIERS))
    ap.add_argument("--keys", type=int, default=3)
    ap.add_argument("--match-capacity", type=int, default=0,
                    help="choose K per carrier: the smallest with at least this many carriers (0: the rig's K)")
    ap.add_argument("--study", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--param", action="append", default=[], help="rig:name=value, e.g. knight:K=130")
    ap.add_argument("--no-range-search", action="store_true", help="extract without the range search")
    ap.add_argument("--solve-rounds", type=int, default=0, help="rounds of the iterative reconstruction (0: default)")
    ap.add_argument("--out", default=str(ROOT / "build" / "carrier"))
    a = ap.parse_args(argv)
    if a.solve_rounds:
        lap.MAX_SOLVE_ROUNDS = a.solve_rounds
    global NO_RANGE_SEARCH
    NO_RANGE_SEARCH = a.no_range_search
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    import meshmark_blender
    meshmark_blender.register()
    report = []
    for name in a.rigs.split(","):
        r = RIGS[name](a.step)
        for spec in a.param:
            rig_name, kv = spec.split(":", 1)
            if rig_name == name:
                k, v = kv.split("=", 1)
                r.params[k] = int(v)
        if a.study:
            t = time.time()
            rows, Ks, n_frames, n_v = carrier_study(r, a.budget)
            write_csv(rows, out / f"study_{name}.csv")
            s = summarise_study(rows, Ks)
            head = f"## {name}: {n_v} welded vertices, {n_frames} of {len(r.frames)} frames, K in {Ks} ({time.time() - t:.0f} s)\n"
            report.append(head + "\n" + md_table(s))
            print(report[-1], flush=True)
        if name in a.pipeline.split(","):
            t = time.time()
            keys = [f"{name}-{i}" for i in range(a.keys)]
            rows, fa, info = pipeline(r, a.carriers.split(","), keys, a.budget, out, a.match_capacity)
            write_csv(rows, out / f"pipeline_{name}.csv")
            if fa:
                write_csv(fa, out / f"false_{name}.csv")
            s = summarise_pipeline(rows, fa, info)
            head = (f"## pipeline {name}: {r.params or 'thesis defaults'}, message {r.message!r}, keys {keys} "
                    f"({time.time() - t:.0f} s)\n")
            report.append(head + "\n" + md_table(s) + "\n" + md_table([{k: i.get(k, "") for k in
                          ("carrier", "key", "K", "capacity", "rest_cdr", "rest_message", "embed_s", "rounds", "n_solve_rounds", "error")}
                          for i in info]))
            print(report[-1], flush=True)
    (out / "report.md").write_text("\n".join(report))


if __name__ == "__main__":
    main()
