"""Time of the add-on's operators (embed, verify, capacity, deformation study; stego_embed, stego_extract,
analyze, steganalysis_detect, study with --new or after the others) against the native
calls they wrap, on a mesh of >= 100k vertices (a jittered 128 x 800 tube, 102,402 vertices), in the
same process; and the time of one draw of every Meshmark panel.

    PYTHONPATH=src python bench/blender_operators.py [--repeat 3]

Prints, for each operator, the best-of-N wall time of the operator, of the meshmark call on numpy
arrays, and the difference (the add-on's overhead: reading/writing Blender data with foreach_get/
foreach_set, the float32 check after embedding, JSON). Target: overhead <= 1 s each.
"""
import argparse
import os
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(ROOT, "addon"))
sys.path.insert(0, os.path.join(ROOT, "blender_tests"))

import bpy  # noqa: E402
import numpy as np  # noqa: E402

import meshmark_blender  # noqa: E402
import rigs  # noqa: E402
from meshmark.shapes import cylinder  # noqa: E402
from meshmark.watermark import capacity, embed, extract  # noqa: E402
import ui_layout  # noqa: E402


def best(f, n):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return min(ts)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--new", action="store_true", help="only the steganography/analysis/steganalysis/study operators")
    a = ap.parse_args()
    meshmark_blender.register()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    m = cylinder(segments=128, rings=800)
    h = 2 * np.pi * 0.15 / 128
    m = m.with_vertices(m.V + np.random.default_rng(0).uniform(-0.25, 0.25, m.V.shape) * h)
    obj = rigs.mesh_object("Tube", mesh=m)
    V0 = rigs.base_coords(obj).copy()
    base = m.with_vertices(V0.astype(np.float64))
    if a.new:
        return bench_new(obj, m, a.repeat)
    kf = os.path.join(tempfile.mkdtemp(), "k.json")
    kw = dict(message="mark", key="k")

    def op_embed():
        obj.data.vertices.foreach_set("co", V0.ravel())
        rigs.select_only(obj)
        bpy.ops.meshmark.embed(keyfile=kf, **kw)

    t_op_e = best(op_embed, a.repeat)
    inner_e = rigs.last_result()["seconds_native"]  # the meshmark.embed call inside the last operator run
    t_nat_e = best(lambda: embed(base, payload=kw["message"], key=kw["key"]), a.repeat)
    t_op_v = best(lambda: bpy.ops.meshmark.verify(keyfile=kf, evaluated=True), a.repeat)
    t_op_vb = best(lambda: bpy.ops.meshmark.verify(keyfile=kf, evaluated=False), a.repeat)
    marked = m.with_vertices(rigs.base_coords(obj).astype(np.float64))
    t_nat_v = best(lambda: extract(marked, keyfile=kf), a.repeat)
    r = rigs.last_result()
    t_op_c = best(lambda: bpy.ops.meshmark.capacity(), a.repeat)
    t_nat_c = best(lambda: capacity(base), a.repeat)
    # the study over 5 frames of a bend (Simple Deform keyframed): the operator vs 5 native extractions
    mod = obj.modifiers.new("Bend", "SIMPLE_DEFORM")
    mod.deform_method = "BEND"
    for f, deg in ((1, 0.0), (5, 20.0)):
        mod.angle = np.radians(deg)
        obj.keyframe_insert('modifiers["Bend"].angle', frame=f)
    out = tempfile.mkdtemp()
    t_op_s = best(lambda: bpy.ops.meshmark.deformation_study(keyfile=kf, frame_start=1, frame_end=5, output_dir=out),
                  a.repeat)
    evaluated = []
    for f in range(1, 6):
        bpy.context.scene.frame_set(f)
        evaluated.append(m.with_vertices(_evaluated(obj)))
    t_nat_s = best(lambda: [extract(e, keyfile=kf) for e in evaluated], a.repeat)
    # what the study spends outside the add-on: Blender evaluating the frames, matplotlib's plot
    t_frames = best(lambda: [(bpy.context.scene.frame_set(f), _evaluated(obj)) for f in (1, 2, 3, 4, 5, 1)], a.repeat)
    from meshmark_blender import study
    rows = rigs.last_result()["rows"]
    t_plot = best(lambda: study.write_plot(rows, os.path.join(out, "p.png"), "bench"), a.repeat)
    from meshmark_blender import panels
    from meshmark_blender import session
    session.CACHE.clear()

    def draw_all():
        for cls in panels._registered:
            ui_layout.draw_recorded(cls, bpy.context)
    t_draw = best(draw_all, a.repeat)
    print(f"mesh: {m.n_vertices:,} vertices, {m.n_faces:,} faces; capacity {r['bits']} bits, CDR {r['cdr']:.3f}")
    print(f"embed: meshmark.embed inside the operator took {inner_e:.3f}s of its run")
    print(f"{'':24}{'operator':>10}{'native':>10}{'overhead':>10}")
    for name, op, nat in (("embed", t_op_e, t_nat_e), ("verify (evaluated)", t_op_v, t_nat_v),
                          ("verify (base mesh)", t_op_vb, t_nat_v), ("capacity", t_op_c, t_nat_c),
                          ("study, 5 frames", t_op_s, t_nat_s)):
        print(f"{name:24}{op:9.3f}s{nat:9.3f}s{op - nat:9.3f}s")
    print(f"study: Blender's frame evaluation {t_frames:.3f}s, the plot (matplotlib) {t_plot:.3f}s; the rest of "
          f"the overhead {t_op_s - t_nat_s - t_frames - t_plot:.3f}s")
    print(f"one draw of every Meshmark panel (102k vertices: capacity on request): {t_draw * 1000:.1f} ms")
    obj.modifiers.remove(mod)
    bench_new(obj, m, a.repeat)


def bench_new(obj, m, repeat):
    """The steganography, analysis, steganalysis and study operators against their native calls."""
    from meshmark import stego
    from meshmark.steganalysis.model import Model
    from meshmark.study import engine
    from meshmark_blender import bridge
    from meshmark_blender.tasks import inspect as hiding_ops
    rigs.select_only(obj)
    V0 = rigs.base_coords(obj).copy()
    base = bridge.base_mesh(obj)
    text = "meshmark bench " * 4

    def op_hide():
        obj.data.vertices.foreach_set("co", V0.ravel())
        obj.data.update()
        bpy.ops.meshmark.stego_embed(message=text, key="k")
    t_op_h = best(op_hide, repeat)
    marked = bridge.base_mesh(obj)
    t_nat_h = best(lambda: stego.embed(base, text, "k", precision="float32"), repeat)
    t_nat_x = best(lambda: stego.extract(marked, "k", precision="float32"), repeat)
    t_op_x = best(lambda: bpy.ops.meshmark.stego_extract(key="k"), repeat)
    assert rigs.last_result()["text"] == text
    t_op_a = best(lambda: bpy.ops.meshmark.analyze(), repeat)
    t_nat_a = best(lambda: hiding_ops.analyze_mesh(marked, 0.1, True), repeat)
    r_a = rigs.last_result()
    model = Model.load()
    bpy.ops.meshmark.steganalysis_detect()  # loads (and caches) the model once
    t_op_d = best(lambda: bpy.ops.meshmark.steganalysis_detect(), repeat)
    t_nat_d = best(lambda: model.detect(marked), repeat)
    spec = os.path.join(tempfile.mkdtemp(), "s.toml")
    with open(spec, "w") as f:
        f.write(rigs.study_spec(rigs.shared_mesh("classic/fandisk.obj"), seeds=(0, 1, 2), name="bench", attacks=[
            'name = "noise"\ngrid = { strength = [0.001] }', 'name = "smooth"\ngrid = { iterations = [5] }', 'name = "reorder"']))
    t_op_s = best(lambda: bpy.ops.meshmark.study(spec=spec, out=tempfile.mkdtemp()), repeat)
    assert rigs.last_result()["summary"]["ok"] == 12, rigs.last_result()
    # the same run in this process (workers=0, as the runner does in its own process)
    t_nat_s = best(lambda: engine.run(spec, tempfile.mkdtemp(), workers=0, progress=False, log=lambda t: None), repeat)
    print(f"\nmesh: {m.n_vertices:,} vertices; analyze: levels {r_a['level_min']}..{r_a['level_max']}")
    print(f"{'':30}{'operator':>10}{'native':>10}{'overhead':>10}")
    rows = (("stego_embed (embed)", t_op_h, t_nat_h), ("stego_embed (embed + check)", t_op_h, t_nat_h + t_nat_x),
            ("stego_extract", t_op_x, t_nat_x), ("analyze (heat map)", t_op_a, t_nat_a),
            ("steganalysis_detect", t_op_d, t_nat_d), ("study (12 tasks, subprocess)", t_op_s, t_nat_s))
    for name, op, nat in rows:
        print(f"{name:30}{op:9.3f}s{nat:9.3f}s{op - nat:9.3f}s")
    print(f"analyze in all: {t_op_a:.3f}s (target <= 0.5 s)")




def _evaluated(obj):
    dg = bpy.context.evaluated_depsgraph_get()
    me = obj.evaluated_get(dg).to_mesh()
    co = np.empty(3 * len(me.vertices), np.float32)
    me.vertices.foreach_get("co", co)
    obj.evaluated_get(dg).to_mesh_clear()
    return co.reshape(-1, 3).astype(np.float64)


if __name__ == "__main__":
    main()
