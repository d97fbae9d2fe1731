"""Steganalysis feature vectors (thesis §8.1 and the later literature; docs/steganalysis.md).

* ``yang208`` — thesis §8.1 exactly: PCA normalisation into the unit cube, calibration by one
  Kirchhoff Laplacian smoothing step, 26 difference vectors x 8 statistics (native:
  ``native/src/yang208_features.cpp``);
* ``lfs76`` — Li and Bors 2017 as the authors' code computes it (zl991/LFS76), with the corrected PCA
  projection: 19 vectors x 4 log-moments (``native/src/lfs76_features.cpp``);
* ``nvt36`` — Zhou et al. 2019 as the authors' code computes it (RyanHangZhou/NVTplus): eigenvalue
  differences of three normal voting tensors, 9 x 4 (``native/src/nvt36_features.cpp``);
* ``lfs76s``, ``nvt36s`` — the stabilised variants the protocol and the default model use: the same
  vectors, invariant to similarity transforms, element order and rounding (docs/steganalysis.md §3)
  (``native/src/{lfs76s,nvt36s}_features.cpp``);
* combinations joined by ``+`` (``yang208+lfs76s+nvt36s``).

Every set is computed natively from ``(V, triangles)``; :func:`features` takes a :class:`meshmark.Mesh`,
a path or ``(V, F)``, triangulates polygons and returns a float64 vector. :data:`FEATURE_SETS` maps a
set name to its length; :func:`feature_names` gives a readable name per component.
"""
from __future__ import annotations

import os

import numpy as np

from .. import _core
from .._core import MeshError
from ..mesh import Mesh, as_mesh

_STATS = ["log_mean", "log_var", "log_skew", "log_kurt", "hist_mean", "hist_var", "hist_skew", "hist_kurt"]
_YANG_VECTORS = [f"{cls}_{space}_{comp}" for cls in ("val<6", "val=6", "val>6") for space in ("cart", "lap")
                 for comp in ("dx", "dy", "dz", "len")] + ["dihedral", "face_normal"]


def _yang208(V, T):
    return _core.yang208_features(V, T)


_LFS_VECTORS = ["cart_dx", "cart_dy", "cart_dz", "cart_norm", "lap_dx", "lap_dy", "lap_dz", "lap_norm", "face_normal",
                "dihedral", "vertex_normal", "gauss_curv", "curv_ratio", "sph_az", "sph_elev", "sph_rho",
                "edge_az", "edge_elev", "edge_rho"]
_LFS_PUBLISHED = ([f"cart_{c}:{s}" for s in ("log_mean", "log_var", "log_skew", "log_kurt") for c in ("dx", "dy", "dz")]
                  + [f"cart_norm:{s}" for s in ("log_mean", "log_var", "log_skew", "log_kurt")]
                  + [f"lap_{c}:{s}" for s in ("log_mean", "log_var", "log_skew", "log_kurt") for c in ("dx", "dy", "dz")]
                  + [f"lap_norm:{s}" for s in ("log_mean", "log_var", "log_skew", "log_kurt")]
                  + [f"{v}:{s}" for v in ["face_normal", "dihedral", "vertex_normal", "gauss_curv", "curv_ratio", "sph_az",
                                          "sph_elev", "sph_rho", "edge_az", "edge_elev", "edge_rho"]
                     for s in ("log_mean", "log_var", "log_skew", "log_kurt")])
_NVT_VECTORS = [f"{t}_lambda{k}" for t in ("face_edge", "vertex", "face_ring") for k in (1, 2, 3)]
_STATS4 = ["log_mean", "log_var", "log_skew", "log_kurt"]


def _lfs76(V, T):
    return _core.lfs76_features(V, T, 0.3, 3.0)


def _nvt36(V, T):
    return _core.nvt36_features(V, T)


def _lfs76s(V, T):
    return _core.lfs76s_features(V, T, 0.3, 3.0)


def _nvt36s(V, T):
    return _core.nvt36s_features(V, T)


#: set name -> (length, native function of (V (n,3) float64, T (t,3) int32))
_SETS = {"yang208": (208, _yang208), "lfs76": (76, _lfs76), "nvt36": (36, _nvt36), "lfs76s": (76, _lfs76s),
         "nvt36s": (36, _nvt36s)}

#: The feature set of the protocol and of the default model (the invariant variants; docs/steganalysis.md §3).
PROTOCOL_SET = "yang208+lfs76s+nvt36s"

#: Bumped whenever a definition changes: cached datasets and model files record it and are refused otherwise.
FEATURES_VERSION = 3


def feature_sets() -> dict:
    """Set name -> number of features."""
    return {k: v[0] for k, v in _SETS.items()}


def feature_names(name: str) -> list[str]:
    """A readable name for every component of set ``name``."""
    if name == "yang208":
        return [f"{v}:{s}" for v in _YANG_VECTORS for s in _STATS]
    if name in _NAMES:
        return _NAMES[name]()
    if "+" in name:
        return [f"{part}/{n}" for part in name.split("+") for n in feature_names(part)]
    raise MeshError(f"unknown feature set {name!r}; choose from {', '.join(sorted(_SETS))} or a '+' combination")


_NAMES: dict = {"lfs76": lambda: list(_LFS_PUBLISHED),  # published order: 1-12 and 17-28 grouped by statistic
                "lfs76s": lambda: [f"{v}:{s}" for v in _LFS_VECTORS for s in _STATS4],
                "nvt36": lambda: [f"{v}:{s}" for v in _NVT_VECTORS for s in _STATS4],
                "nvt36s": lambda: [f"{v}:{s}" for v in _NVT_VECTORS for s in _STATS4]}


def _as_mesh(mesh) -> Mesh:
    if isinstance(mesh, (str, os.PathLike)):
        from ..io import read_mesh
        return read_mesh(mesh)
    if isinstance(mesh, tuple):
        return as_mesh(*mesh)
    return as_mesh(mesh)


def features(mesh, name: str = "yang208") -> np.ndarray:
    """The feature vector ``name`` of ``mesh`` (a Mesh, a path, or ``(V, F)``).

    ``name`` is one set (``yang208``, ``lfs76``, ``nvt36``, ``lfs76s``, ``nvt36s``) or a combination joined
    by ``+`` (``yang208+lfs76s+nvt36s``: the vectors concatenated). MeshError for an unknown set or a mesh too small for
    the features.
    """
    m = _as_mesh(mesh)
    T = np.ascontiguousarray(m.triangles, dtype=np.int32)
    parts = name.split("+")
    out = []
    for p in parts:
        if p not in _SETS:
            raise MeshError(f"unknown feature set {p!r}; choose from {', '.join(sorted(_SETS))} or a '+' combination")
        out.append(np.asarray(_SETS[p][1](m.V, T), dtype=np.float64))
    return out[0] if len(out) == 1 else np.concatenate(out)


def feature_length(name: str) -> int:
    return sum(_SETS[p][0] if p in _SETS else len(feature_names(p)) for p in name.split("+"))
