"""Train the default steganalysis model shipped with meshmark (``meshmark steganalysis detect`` without
``--model``) on the openly licensed meshes of ../shared/meshes only (SOURCES.md):

    .venv/bin/python examples/steganalysis_default_model.py [--out src/meshmark/steganalysis/default_model.npz]

Covers: CC0 / public-domain / CC-BY files (CC-BY-SA, GPL, non-commercial, "no licence stated" and
everything in corpus-large are left out; attribution is in the model's metadata and
docs/steganalysis.md §4). Each cover is marked by every registered stego method with ``--versions``
independent messages and strengths. Cover variety (``--augment``, default on): besides each file, two
patches (the mesh cropped by 35 % along its first and third principal axes: open sub-meshes) and one
level of Loop subdivision (meshes under 20k vertices) are further covers; no re-meshing. Models trained on research-only data are made with
``meshmark steganalysis train`` and stay out of the repository.
"""
from __future__ import annotations

import argparse
import pathlib

import numpy as np

import meshmark
from meshmark import attacks
from meshmark.steganalysis import protocol as P
from meshmark.steganalysis.model import Model, corpus_hash

ROOT = pathlib.Path(__file__).resolve().parents[1]
SHARED = ROOT.parent / "shared" / "meshes"
OPEN = {  # file -> licence as stated in SOURCES.md
    "classic/spot.obj": "public domain (Keenan Crane)",
    "classic/hand.obj": "CC-BY 4.0 (SMPL woman mesh, Max Planck Society; odedstein/meshes)",
    "corpus/odedstein_boot.obj": "CC-BY 4.0 (inciprocal / Oded Stein)",
    "corpus/odedstein_cat-low-resolution.obj": "CC-BY 4.0 (billyd, Thingiverse 1565405)",
    "corpus/odedstein_demosthenes-low-res.obj": "CC-BY 4.0 (ryanfb)",
    "corpus/odedstein_fish_low_resolution.obj": "public domain (Keenan Crane)",
    "corpus/odedstein_goathead.obj": "CC-BY 3.0 (hugoelec, Thingiverse 42256)",
    "corpus/odedstein_koala_low_resolution.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182225)",
    "corpus/odedstein_penguin.obj": "CC-BY 4.0 (odedstein/meshes)",
    "corpus/odedstein_plane.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182252)",
    "corpus/odedstein_skull_low_resolution.obj": "CC-BY 3.0 (YahooJAPAN, Thingiverse 182365)",
    "corpus/odedstein_torus.obj": "CC-BY 4.0 (odedstein/meshes)",
    "corpus/vtk_Vase.stl": "CC-BY (Alzibiff, Victorian Goblet face illusion)",
    "corpus/thingi10k_59758.stl": "CC-BY (DigitalBytes, Thingiverse 18471)",
    "corpus/thingi10k_63448.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_63451.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_63452.stl": "CC-BY (pmoews, Thingiverse 20012)",
    "corpus/thingi10k_65583.stl": "CC-BY (pmoews, Thingiverse 20976)",
    "corpus/thingi10k_68435.stl": "CC-BY (EdinKali, Thingiverse 22236)",
    "corpus/thingi10k_73338.stl": "CC-BY (anneyfresh, Thingiverse 24228)",
    "corpus/thingi10k_73342.stl": "CC-BY (anneyfresh, Thingiverse 24228)",
    "corpus/thingi10k_50736.stl": "public domain (chris, Thingiverse 15346)",
    "corpus/thingi10k_97171.stl": "public domain (chris, Thingiverse 33696)",
}


def augmented(paths):
    """(name, mesh) covers: each open file, two patches of it and its Loop subdivision (docs/steganalysis.md §4)."""
    out = []
    for p in paths:
        m = meshmark.read_mesh(p)
        out.append((str(p), m))
        used = np.zeros(m.n_vertices, bool)
        used[m.face_indices] = True
        Vc = m.V[used] - m.V[used].mean(0)
        axes = np.linalg.svd(Vc, full_matrices=False)[2]
        for k in (0, 2):
            try:
                c = attacks.crop(m, fraction=0.35, normal=axes[k])
                if c.n_vertices >= 50:
                    out.append((f"{p}#crop{k}", c))
            except meshmark.MeshError:
                pass
        if m.n_vertices < 20000:
            try:
                out.append((f"{p}#loop1", attacks.subdivide(m, scheme="loop", levels=1)))
            except meshmark.MeshError:
                pass
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=str(ROOT / "src" / "meshmark" / "steganalysis" / "default_model.npz"))
    ap.add_argument("--set", dest="feature_set", default="yang208+lfs76+nvt36")
    ap.add_argument("--versions", type=int, default=3, help="stego versions per (cover, method)")
    ap.add_argument("--learners", type=int, default=31)
    ap.add_argument("--no-augment", action="store_true", help="only the 23 files themselves as covers")
    a = ap.parse_args()
    paths = [SHARED / p for p in OPEN]
    covers = paths if a.no_augment else augmented(paths)
    Xs, ys, labs = [], [], []
    with P.one_thread():
        for v in range(a.versions):
            ds = P.build_dataset(covers, None, (a.feature_set,), seed=v)
            keep = np.ones(len(ds["method"]), bool) if v == 0 else ds["method"] != "cover"
            Xs.append(ds["X"][a.feature_set][keep])
            ys.append(ds["method"][keep] != "cover")
            labs += list(ds["method"][keep])
        X, y = np.vstack(Xs), np.concatenate(ys)
        training = {"corpus_hash": corpus_hash(paths), "n_covers": int((~y).sum()), "n_stego": int(y.sum()),
                    "methods": sorted({l for l in labs if l != "cover"}), "versions": a.versions,
                    "augmentation": None if a.no_augment else "each file + 2 patches (35 % crops along principal axes 1, 3) + Loop subdivision (< 20k vertices)",
                    "covers": {p: lic for p, lic in OPEN.items()},
                    "note": "openly licensed meshes of ../shared/meshes only; see docs/steganalysis.md"}
        model = Model.train(X, y, labs, a.feature_set, "ensemble", training, n_learners=a.learners)
    model.save(a.out)
    print(f"wrote {a.out} ({pathlib.Path(a.out).stat().st_size / 1024:.0f} KB): {training['n_covers']} covers, "
          f"{training['n_stego']} stego, {', '.join(training['methods'])}")


if __name__ == "__main__":
    main()
