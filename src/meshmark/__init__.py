"""meshmark: information hiding and detection in 3D triangle meshes.

A Python package over a native C++ core (``meshmark._core``: the per-vertex and per-face work; checking,
keyfiles, coding, studies and glTF are Python). Arrays go in and out as numpy:
vertices ``V`` are ``(n, 3) float64`` in model units, faces are either an ``(m, k)`` integer array or
a :class:`Mesh` holding polygons of mixed sizes. The package never imports ``bpy``.

Modules, one per concern (thesis chapters get their own modules as they land):

* :mod:`meshmark.mesh` — the :class:`Mesh` model and input validation;
* :mod:`meshmark.io` — reading and writing OBJ, OFF, PLY, STL and glTF (:mod:`meshmark.gltf`);
* :mod:`meshmark.topology` — edges, adjacency, boundary, components, manifoldness, welding;
* :mod:`meshmark.geometry` — triangulation, normals, areas, angles, PCA;
* :mod:`meshmark.attacks` — attacks: similarity, reordering, noise, smoothing, quantization,
  simplification, subdivision, cropping, storage round trips;
* :mod:`meshmark.metrics` — distortion (RMSE, surface distance, normal degradation) and watermark measures;
* :mod:`meshmark.parts` — several meshes (a character's parts) joined as one carrier and split back;
* :mod:`meshmark.shapes` — built-in procedural meshes (the default inputs of the demos);
* :mod:`meshmark.cli` — the ``meshmark`` command.
"""
from ._core import MeshError
from .mesh import Mesh, as_mesh
from .io import read_mesh, write_mesh
from .topology import (unique_edges, vertex_adjacency, valence, boundary_edges, boundary_vertices,
                       connected_components, manifold_report, weld_vertices, Welded)
from .geometry import (triangulate, face_normals, face_areas, interior_angles, dihedral_angles,
                       angle_sum, pca)
from .info import mesh_info
from . import attacks, metrics, parts

__version__ = "0.1.0"

__all__ = [
    "MeshError", "Mesh", "as_mesh", "read_mesh", "write_mesh",
    "unique_edges", "vertex_adjacency", "valence", "boundary_edges", "boundary_vertices",
    "connected_components", "manifold_report", "weld_vertices", "Welded",
    "triangulate", "face_normals", "face_areas", "interior_angles", "dihedral_angles", "angle_sum", "pca",
    "mesh_info", "__version__",
]
