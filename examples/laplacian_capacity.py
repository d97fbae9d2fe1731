"""Capacity of the Laplacian watermark beside Table 7.1 (writes CSV): carrier bits with the thesis'
parameters (``params="thesis"``: K = ceil(N/70), n_thr = 46, n_robust = 5; the figure to compare with
the table's C) and with the automatic ones (``params="auto"``, the default of the API and the CLI).

    .venv/bin/python examples/laplacian_capacity.py [--out out/laplacian_capacity.csv] [--corpus] [--quick]

``--quick``: the Bunny and the Horse only.
"""
import argparse

import meshmark
from _common import SHARED, write_csv
from meshmark.watermark import laplacian as L
from meshmark.watermark.auto import choose

# Table 7.1: model -> (N, K, n_thr, n_robust, C)
TABLE_7_1 = {"bunny": (34835, 498, 46, 5, 21), "rabbit": (70658, 1010, 46, 5, 102), "horse": (19851, 284, 46, 5, 22),
             "dragon": (50000, 715, 46, 5, 103), "elephant": (24955, 498, 46, 5, 25), "hand": (17117, 245, 46, 5, 52),
             "hank": (15488, 150, 70, 5, 30)}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/laplacian_capacity.csv")
    ap.add_argument("--corpus", action="store_true", help="also the corpus/ meshes")
    ap.add_argument("--quick", action="store_true", help="the Bunny and the Horse only")
    a = ap.parse_args(argv)
    dirs = ["classic"] + (["corpus"] if a.corpus else [])
    files = sorted(p for d in dirs for p in (SHARED / d).iterdir() if p.suffix.lower() in {".obj", ".off", ".ply", ".stl"})
    if a.quick:
        files = [p for p in files if p.stem in ("bunny", "horse")]
    rows = []
    for p in files:
        m = meshmark.read_mesh(p)
        try:
            prm, ids, _, _ = choose(m, L.METHOD, "thesis", {}, None)  # what capacity(params="thesis") uses
            cap = L.capacity(m, params="thesis")
            auto = L.capacity(m)
        except meshmark.MeshError as exc:
            prm, cap, auto = {"K": "-"}, f"error: {exc}", ""
        n_ref = int((meshmark.valence(m) > 0).sum())
        t = TABLE_7_1.get(p.stem)
        rows.append({"mesh": f"{p.parent.name}/{p.name}", "N": n_ref, "K": prm["K"], "n_thr": 46, "capacity": cap,
                     "capacity_auto": auto,
                     "thesis_N": t[0] if t else "", "thesis_K": t[1] if t else "", "thesis_C": t[4] if t else ""})
    write_csv(rows, a.out)
    print("Thesis parameters (params='thesis') beside Table 7.1; automatic parameters (the default) last\n")
    print("| mesh | N | K | capacity (thesis) | thesis N | thesis K | thesis C | capacity (auto) |\n"
          "|---|---:|---:|---:|---:|---:|---:|---:|")
    for r in rows:
        print(f"| {r['mesh']} | {r['N']} | {r['K']} | {r['capacity']} | {r['thesis_N']} | {r['thesis_K']} | "
              f"{r['thesis_C']} | {r['capacity_auto']} |")
    return rows


if __name__ == "__main__":
    main()
