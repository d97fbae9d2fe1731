"""Time `meshmark compare` after simplification (issue 23): the fandisk at 50 %, and 20 other shared
meshes at 50 % and 25 % of their faces (`meshmark attack --type simplify`). Prints per pair the wall
time of the whole `meshmark compare --json` command (a fresh process, as a user runs it), the bounded
Hausdorff distance [lower, upper], whether it converged within the work cap, and (--queries) the distance queries used per direction.

    .venv/bin/python bench/compare_simplified.py [--out out/compare_simplified.csv] [--fractions 0.5 0.25]
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

import meshmark
from meshmark import metrics

from _common import SHARED

MESHES = ["classic/bunny.obj", "classic/camelhead.off", "classic/cow.obj", "classic/elephant.off",
          "classic/fertility.off", "classic/hand.obj", "classic/homer.obj", "classic/horse.ply", "classic/spot.obj",
          "classic/suzanne.obj", "classic/teapot.obj", "corpus/odedstein_boot.obj", "corpus/vhacd_sword.off",
          "corpus/vhacd_octopus.off", "corpus/vhacd_drum.off", "corpus/libigl_truck.obj", "corpus/vtk_42400-IDGH.stl",
          "corpus/pmp_fairing-cross.off", "corpus/vhacd_block.off", "corpus/vtk_trumpet.obj"]
MM = [sys.executable, "-m", "meshmark.cli"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--out", default="out/compare_simplified.csv")
    ap.add_argument("--fractions", type=float, nargs="+", default=[0.5, 0.25])
    ap.add_argument("--meshes", nargs="*", default=None)
    ap.add_argument("--queries", action="store_true", help="also count the distance queries (runs the bound again)")
    a = ap.parse_args()
    pairs = [("classic/fandisk.obj", 0.5)] + [(m, f) for m in (a.meshes or MESHES) for f in a.fractions]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for rel, frac in pairs:
            src = str(SHARED / rel)
            out = os.path.join(tmp, f"s{len(rows)}.ply")
            subprocess.run(MM + ["attack", src, out, "--type", "simplify", "--fraction", str(frac)], check=True,
                           capture_output=True)
            t0 = time.time()
            r = subprocess.run(MM + ["compare", src, out, "--json"], capture_output=True, text=True)
            wall = time.time() - t0
            if r.returncode:
                rows.append({"mesh": rel, "fraction": frac, "seconds": round(wall, 2), "error": r.stderr.strip()[:200]})
                print(rows[-1], flush=True)
                continue
            d = json.loads(r.stdout)
            hab = hba = {"n_queries": ""}
            if a.queries:
                A, B = meshmark.read_mesh(src), meshmark.read_mesh(out)
                hab, hba = metrics.hausdorff_distance(A, B), metrics.hausdorff_distance(B, A)
            rows.append({"mesh": rel, "fraction": frac, "faces": d["n_faces"][0], "seconds": round(wall, 2),
                         "hausdorff_rel": d["hausdorff_rel"], "upper_rel": d["hausdorff_upper_rel"],
                         "converged": d["hausdorff_converged"], "queries_ab": hab["n_queries"],
                         "queries_ba": hba["n_queries"], "error": ""})
            print(f"{rel:34s} {frac:4.2f} {wall:6.1f} s  H/diag [{d['hausdorff_rel']:.4e}, {d['hausdorff_upper_rel']:.4e}]"
                  f"  converged {d['hausdorff_converged']}  queries {hab['n_queries']} {hba['n_queries']}",
                  flush=True)
    ok = [r for r in rows if not r["error"]]
    print(f"{len(ok)}/{len(rows)} ran; slowest {max(r['seconds'] for r in rows):.1f} s; "
          f"{sum(r['seconds'] > 30 for r in rows)} over 30 s; {sum(not r['converged'] for r in ok)} not converged")
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(ok[0] if ok else rows[0]), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)
    print("wrote", a.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
