"""glTF 2.0 (``.glb`` and ``.gltf``) in and out: an asset's triangle meshes as one carrier, and
marked positions written back into a copy of the asset with everything else unchanged.

    mesh, info = meshmark.gltf.read("hero.glb")         # all triangle primitives, joined
    res = laplacian.embed(mesh, payload="ACME", key="k")
    meshmark.gltf.write_positions(info, res.V, "marked.glb")   # only POSITION bytes and min/max change

``meshmark.read_mesh`` / ``write_mesh`` dispatch here on the extension (``write_mesh("x.glb", mesh,
source=info)`` writes back; without ``source`` a minimal glTF of the mesh). See ``docs/gltf.md``.
"""
from .reader import GltfInfo, Part, read
from .writer import plan_write, write_positions
from .minimal import gltf_bytes, write_gltf

EXTENSIONS = (".glb", ".gltf")


def is_gltf(path) -> bool:
    """Whether ``path`` names a glTF file (by its extension)."""
    import os
    try:
        name = os.fsdecode(os.fspath(path))
    except TypeError:
        return False
    return os.path.splitext(name)[1].lower() in EXTENSIONS


__all__ = ["GltfInfo", "Part", "read", "plan_write", "write_positions", "gltf_bytes", "write_gltf", "is_gltf",
           "EXTENSIONS"]
