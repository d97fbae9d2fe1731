"""Hold-out covers made in Blender (bpy), for the default steganalysis model's unseen-mesh measurement
(docs/steganalysis.md, "Default model on unseen meshes"):

    .venv/bin/python examples/steganalysis_blender_holdout.py --out out/holdout_blender --n 24 --seed 0

Primitives (Suzanne, UV sphere, cone, cylinder, cube, torus) with a random stack of Blender modifiers
(Subdivision Surface, Displace with a Clouds texture, voxel Remesh, Decimate collapse, then Triangulate),
written as OBJ files ``blender_<i>_<primitive>.obj``. Runs in its own process (bpy; never import
pymeshlab beside it). None of these meshes or families is used for training; reproducible from --seed.
"""
from __future__ import annotations

import argparse
import pathlib
import random

import bpy
import numpy as np

PRIMS = ("monkey", "uv_sphere", "cone", "cylinder", "cube", "torus")


def _add(prim, r):
    ops = bpy.ops.mesh
    if prim == "monkey":
        ops.primitive_monkey_add()
    elif prim == "uv_sphere":
        ops.primitive_uv_sphere_add(segments=r.randint(12, 64), ring_count=r.randint(8, 32))
    elif prim == "cone":
        ops.primitive_cone_add(vertices=r.randint(8, 48), depth=r.uniform(1, 3))
    elif prim == "cylinder":
        ops.primitive_cylinder_add(vertices=r.randint(8, 64), depth=r.uniform(1, 4))
    elif prim == "cube":
        ops.primitive_cube_add()
    else:
        ops.primitive_torus_add(major_segments=r.randint(12, 64), minor_segments=r.randint(6, 24))
    return bpy.context.active_object


def make(i, r, out):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    prim = PRIMS[i % len(PRIMS)]
    ob = _add(prim, r)
    ob.scale = (r.uniform(0.5, 1.5), r.uniform(0.5, 1.5), r.uniform(0.5, 1.5))
    stack = []
    if prim in ("cube", "cone", "cylinder") or r.random() < 0.7:
        m = ob.modifiers.new("sub", "SUBSURF")
        m.levels = r.randint(1, 3)
        m.subdivision_type = "CATMULL_CLARK" if r.random() < 0.8 else "SIMPLE"
        stack.append(f"subsurf{m.levels}")
    if r.random() < 0.6:
        tex = bpy.data.textures.new("clouds", "CLOUDS")
        tex.noise_scale = r.uniform(0.3, 1.5)
        m = ob.modifiers.new("disp", "DISPLACE")
        m.texture, m.strength = tex, r.uniform(0.02, 0.2)
        stack.append("displace")
    if r.random() < 0.35:
        m = ob.modifiers.new("remesh", "REMESH")
        m.mode, m.voxel_size = "VOXEL", r.uniform(0.03, 0.08)
        stack.append("remesh")
    if r.random() < 0.4:
        m = ob.modifiers.new("dec", "DECIMATE")
        m.ratio = r.uniform(0.2, 0.7)
        stack.append("decimate")
    ob.modifiers.new("tri", "TRIANGULATE")
    dg = bpy.context.evaluated_depsgraph_get()
    me = ob.evaluated_get(dg).to_mesh()
    if len(me.vertices) < 300 and "decimate" in stack:  # too coarse to carry a mark: keep it undecimated
        ob.modifiers.remove(ob.modifiers["dec"])
        stack.remove("decimate")
        dg = bpy.context.evaluated_depsgraph_get()
        me = ob.evaluated_get(dg).to_mesh()
    V = np.empty(len(me.vertices) * 3)
    me.vertices.foreach_get("co", V)
    F = np.empty(len(me.polygons) * 3, np.int64)
    me.polygons.foreach_get("vertices", F)
    V, F = V.reshape(-1, 3), F.reshape(-1, 3) + 1
    name = out / f"blender_{i:03d}_{prim}.obj"
    with open(name, "w") as f:
        f.write(f"# blender {bpy.app.version_string}: {prim} {' '.join(stack)}\n")
        np.savetxt(f, V, fmt="v %.9g %.9g %.9g")
        np.savetxt(f, F, fmt="f %d %d %d")
    return name, len(V), stack


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default="out/holdout_blender")
    ap.add_argument("--n", type=int, default=24)
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args()
    out = pathlib.Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    for i in range(a.n):
        name, nv, stack = make(i, random.Random(a.seed * 100003 + i), out)
        print(f"{name} {nv} vertices {' '.join(stack)}")


if __name__ == "__main__":
    main()
