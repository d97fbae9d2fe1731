"""pytest suites that drive Blender's Python (the `bpy` wheel, or Debian's blender binary).

Run: ``python -m pytest blender_tests`` in the environment where ``bpy`` and ``meshmark`` import.
"""
import bpy  # a missing bpy is an error, never a skip
import numpy as np
import pytest


@pytest.fixture
def empty_scene():
    """A fresh empty scene for each test."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    yield bpy.context.scene


def mesh_arrays(obj, evaluated: bool = False):
    """(V (n,3) float64, loop vertex indices int32, offsets int64) of a Blender mesh via foreach_get."""
    me = obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data if evaluated else obj.data
    n, m, c = len(me.vertices), len(me.polygons), len(me.loops)
    co = np.empty(3 * n, np.float32)
    me.vertices.foreach_get("co", co)
    loops = np.empty(c, np.int32)
    me.loops.foreach_get("vertex_index", loops)
    starts = np.empty(m, np.int32)
    me.polygons.foreach_get("loop_start", starts)
    totals = np.empty(m, np.int32)
    me.polygons.foreach_get("loop_total", totals)
    offsets = np.zeros(m + 1, np.int64)
    np.cumsum(totals, out=offsets[1:])
    assert (starts == offsets[:-1]).all()
    return co.reshape(-1, 3).astype(np.float64), loops, offsets


@pytest.fixture(scope="session")
def addon():
    """The meshmark add-on (addon/meshmark_blender), registered once for the session."""
    from blender_tests import rigs  # noqa: F401  (puts addon/ on sys.path)
    import meshmark_blender
    meshmark_blender.register()
    yield meshmark_blender
    meshmark_blender.unregister()
