"""meshmark.parts: several meshes as one carrier (joined side by side, split back)."""
import numpy as np
import pytest

import meshmark
from meshmark import parts
from meshmark.watermark import laplacian


def _grid(n, shift):
    x, y = np.meshgrid(np.arange(n, dtype=float), np.arange(n, dtype=float))
    V = np.c_[x.ravel(), y.ravel(), np.sin(x.ravel() * 0.7) * np.cos(y.ravel() * 0.5)] + shift
    i = np.arange(n * n).reshape(n, n)
    a, b, c, d = i[:-1, :-1].ravel(), i[:-1, 1:].ravel(), i[1:, 1:].ravel(), i[1:, :-1].ravel()
    return V, np.r_[np.c_[a, b, c], np.c_[a, c, d]]


def test_join_renumbers_faces_and_splits_back():
    quad = meshmark.Mesh(np.eye(4, 3), [[0, 1, 2, 3]])
    V1, F1 = _grid(4, 0.0)
    j = parts.join([(V1, F1), quad, meshmark.Mesh(V1 + 10, F1)])
    assert j.n_parts == 3 and j.offsets.tolist() == [0, 16, 20, 36]
    assert j.face_offsets.tolist() == [0, 18, 19, 37]
    assert j.mesh.face_sizes.tolist() == [3] * 18 + [4] + [3] * 18
    np.testing.assert_array_equal(j.mesh.triangles[:18], F1)
    sizes = j.mesh.face_sizes
    quad_corners = j.mesh.face_indices[j.mesh.face_offsets[18]:j.mesh.face_offsets[19]]
    assert quad_corners.tolist() == [16, 17, 18, 19] and sizes[18] == 4
    last = j.mesh.face_indices[j.mesh.face_offsets[19]:].reshape(-1, 3)
    np.testing.assert_array_equal(last, F1 + 20)
    a, b, c = j.split(j.mesh.V)
    np.testing.assert_array_equal(a, V1)
    np.testing.assert_array_equal(c, V1 + 10)
    assert j.part_of_vertex().tolist() == [0] * 16 + [1] * 4 + [2] * 16


def test_bad_parts_are_named():
    with pytest.raises(meshmark.MeshError, match="at least one part"):
        parts.join([])
    with pytest.raises(meshmark.MeshError, match="part 1"):
        parts.join([_grid(3, 0.0), (np.zeros((3, 2)), [[0, 1, 2]])])
    j = parts.join([_grid(3, 0.0)])
    with pytest.raises(meshmark.MeshError, match="9 vertices"):
        j.split(np.zeros((8, 3)))


def test_two_parts_carry_one_mark():
    """A message that needs both parts' carriers is embedded in the joined mesh and read from it."""
    j = parts.join([_grid(40, 0.0), _grid(40, np.array([50.0, 0.0, 0.0]))])
    res = laplacian.embed(j.mesh, payload="AC", key="k")
    body, other = j.split(res.V)
    back = parts.join([(body, j.mesh.triangles[:j.face_offsets[1]]),
                       (other, j.mesh.triangles[j.face_offsets[1]:] - j.offsets[1])])
    out = laplacian.extract(back.mesh, keyfile=res.keyfile)
    assert out.detected and out.message == "AC"
