"""The published LFS76 and NVT36 (``--set lfs76``, ``--set nvt36``) against the authors' own code, run under
GNU Octave 7.3 on shared meshes (numbers and provenance in tests/data/steganalysis_authors_reference.json;
docs/steganalysis.md §3)."""
import json

import numpy as np

import meshmark
from meshmark.steganalysis import features as feat
from conftest import ROOT, shared_mesh

REF = json.loads((ROOT / "tests" / "data" / "steganalysis_authors_reference.json").read_text())
ISSUE_BUNNY = [float(x) for x in (  # issue 25: NVT36 of classic/bunny.obj from the authors' code, 4 digits
    "-5.979 2.525 -0.4554 4.629 -6.091 2.585 -0.5474 7.349 -8.251 5.91 -4.943 54.04 -2.314 37.96 -5.064 27.83 "
    "-5.376 32.48 -4.8 26.04 -6.795 30.63 -4.668 24.87 -0.2228 1.446 -1.378 5.948 -3.293 2.225 -0.5099 4.055 "
    "-4.539 1.932 -0.7147 4.623").split()]


def _features(name, fset):
    m = meshmark.read_mesh(shared_mesh(name))
    return feat.features((m.V, m.triangles), fset)


def test_nvt36_equals_the_authors_code_on_the_bunny():
    """The authors' code reproduces the issue's 4-digit figures; ours equals the authors' code to 1e-6
    relative on the components that do not depend on rounding-level eigenvalue differences (a
    rank-deficient voting tensor: boundary faces, flat rings, where a difference of two nearly equal
    eigenvalues sits at log(2^-52 + noise) and the 3x3 eigen-solver's last bits move the statistic).
    On the bunny 21 of 36 components agree to 1e-6 and the rest to 1e-2 (docs/steganalysis.md §3)."""
    octave = np.array(REF["nvt36"]["classic/bunny.obj"])
    issue = np.array(ISSUE_BUNNY)
    assert (np.abs(octave - issue) / np.abs(octave)).max() <= 5e-4  # the 4-digit rounding of the issue
    F = _features("classic/bunny.obj", "nvt36")
    rel = np.abs(F - octave) / np.abs(octave)
    assert (rel <= 1e-6).sum() >= 20, rel
    assert rel.max() <= 1e-2, (int(np.argmax(rel)), rel.max())


def test_nvt36_equals_the_authors_code_on_closed_meshes():
    closed = {k: v for k, v in REF["nvt36"].items() if k != "classic/bunny.obj"}
    assert closed
    for name, octave in closed.items():
        octave = np.array(octave)
        rel = np.abs(_features(name, "nvt36") - octave) / np.maximum(np.abs(octave), 1e-300)
        assert np.median(rel) <= 1e-6, (name, rel)


def test_lfs76_rotation_invariant_components_equal_the_authors_code():
    """f37-40 (dihedral angles) and f49-52 (curvature ratio) do not depend on the published projection
    (trans * V): on closed meshes they equal the authors' code to 1e-6 relative."""
    assert len(REF["lfs76"]) >= 1
    for name, octave in REF["lfs76"].items():
        octave = np.array(octave)
        F = _features(name, "lfs76")
        inv = np.r_[36:40, 48:52]
        rel = np.abs(F[inv] - octave[inv]) / np.abs(octave[inv])
        assert rel.max() <= 1e-6, (name, rel)


def _rounding_spread(name, fset):
    """(features, largest relative change of each component under rounding-level changes of the input:
    V * (1 +- 1e-15) and V +- 1e-12)."""
    m = meshmark.read_mesh(shared_mesh(name))
    F = feat.features((m.V, m.triangles), fset)
    spread = np.zeros_like(F)
    for V in (m.V * (1 + 1e-15), m.V * (1 - 1e-15), m.V + 1e-12, m.V - 1e-12):
        spread = np.maximum(spread, np.abs(feat.features((V, m.triangles), fset) - F) / np.abs(F))
    return F, spread


def test_lfs76_with_the_corrected_projection_agrees_wherever_the_input_determines_it():
    """With the one-character fix trans' * V in preprocess.m (PCA signs as MATLAB's pca): every component
    that the float64 input determines (moves by <= 1e-9 under rounding-level changes of V) equals the
    authors' code to 1e-6 relative; the components that differ (lap_dx/dy, vertex_normal, sph_az/elev,
    edge_az on vhacd_eight: up to 1.04 relative) are exactly those that move by >= 1e-5 under
    V * (1 + 1e-15) themselves (log(|x| + 2^-52) of differences that vanish on flat patches), so no
    implementation can match them to 1e-6 (docs/steganalysis.md §3)."""
    assert REF["lfs76_fixed_projection"]
    for name, octave in REF["lfs76_fixed_projection"].items():
        octave = np.array(octave)
        F, spread = _rounding_spread(name, "lfs76")
        rel = np.abs(F - octave) / np.abs(octave)
        determined = spread <= 1e-9
        assert determined.sum() >= 40, (name, int(determined.sum()))
        assert rel[determined].max() <= 1e-6, (name, rel[determined].max())
        assert (spread[rel > 1e-6] >= 1e-5).all(), (name, np.flatnonzero(rel > 1e-6), spread[rel > 1e-6])


def test_nvt36_differs_from_the_authors_code_only_where_rounding_moves_it():
    """On the bunny the 15 NVT36 components that differ from the authors' code by more than 1e-6 each move
    by more than 1e-6 under rounding-level changes of the input (rank-deficient voting tensors)."""
    octave = np.array(REF["nvt36"]["classic/bunny.obj"])
    F, spread = _rounding_spread("classic/bunny.obj", "nvt36")
    rel = np.abs(F - octave) / np.abs(octave)
    assert (spread[rel > 1e-6] > 1e-6).all(), (np.flatnonzero(rel > 1e-6), spread[rel > 1e-6])
    assert rel[spread <= 1e-7].max() <= 1e-6


def test_published_lfs76_extends_to_open_meshes_and_names():
    """The published code stops on a boundary edge (meshDihedralAngles indexes face 0); here those edges are
    left out of 37-40 and everything else is as published."""
    F = _features("classic/camelhead.off", "lfs76")
    assert F.shape == (76,) and np.isfinite(F).all()
    names = feat.feature_names("lfs76")
    assert names[:4] == ["cart_dx:log_mean", "cart_dy:log_mean", "cart_dz:log_mean", "cart_dx:log_var"]
    assert names[36] == "dihedral:log_mean" and len(names) == 76
