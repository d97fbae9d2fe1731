"""The study engine's Blender deformation (``blender_bend``) with the bpy wheel."""
import numpy as np

from meshmark import shapes
from meshmark.study import deform


def test_blender_bend_runs_with_bpy():
    import bpy  # noqa: F401  (fails, not skips, when the wheel is missing)
    assert "blender_bend" in deform.available()
    m = shapes.cylinder(segments=16, rings=32)
    flat = deform.apply("blender_bend", m, {"degrees": 0.0, "axis": "X"})
    assert np.allclose(flat.V, m.V, atol=1e-6) and np.array_equal(flat.face_indices, m.face_indices)
    bent = deform.apply("blender_bend", m, {"degrees": 90.0, "axis": "X"})
    assert bent.n_vertices == m.n_vertices and np.abs(bent.V - m.V).max() > 0.1
