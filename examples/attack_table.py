"""The distortion of every attack at every listed strength on shared meshes: a CSV and a Markdown table.

    .venv/bin/python examples/attack_table.py [--out out/attack_table] [--workers N]
                                              [--csv attack_table.csv] [--markdown attack_table.md] [--quick]

``--quick``: the same attacks on the Fandisk only (6,475 vertices).

The study is examples/studies/attack_table.toml (run by meshmark.study; rerunning resumes from
--out). Columns: vertex RMSE and Hausdorff / RMS surface distance relative to the bounding-box
diagonal of the original, and the mean normal degradation dis^av of eq. 3.2.2 in degrees. RMSE and
normal degradation need the same vertices and faces, so they are "-" for attacks that change the
connectivity. Meshes are compacted first (unreferenced vertices dropped: the bunny has 1,113).
Similarity, rotation and reordering are measured after undoing them (their rows show the round-off of
the round trip). Surface distances: all vertices plus 2 x triangles area samples in each direction,
seed 0 (RMS); Hausdorff bounded within 1 % (metrics.hausdorff_distance). docs/attacks.md shows the output.
"""
import argparse
import pathlib

from meshmark.study import load_results, load_spec, run

SPEC = pathlib.Path(__file__).resolve().parent / "studies" / "attack_table.toml"


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def table(out, sp=None):
    """(CSV rows in the published order, Markdown lines) from the results under ``out`` (of the spec ``sp``)."""
    sp = sp or load_spec(SPEC)
    by = {(r["mesh"], r["attack"]): r for r in load_results(out).to_pylist()}
    rows = []
    for mesh, _ in sp.meshes:
        for av in sp.attacks:
            r = dict(by[(mesh, av.label)])
            if r["status"] != "ok":  # e.g. the bounded Hausdorff search not converging on a round-off distance
                print(f"warning: {mesh} {av.label}: {r['status']}: {r['error'].splitlines()[0]}")
                r.update(rmse_rel=None, hausdorff_rel=None, rms_rel=None, normal_deg_mean=None)
            name, param = av.label.split(" | ")
            rows.append({"mesh": mesh, "attack": name, "parameter": param, "n_vertices": r["n_vertices"],
                         "n_faces": r["n_faces"], "rmse_rel": r["rmse_rel"], "hausdorff_rel": r["hausdorff_rel"],
                         "rms_rel": r["rms_rel"], "normal_deg_mean": r["normal_deg_mean"], "attack_seconds": r["t_attack"]})
    names = [pathlib.Path(m).stem for m, _ in sp.meshes]
    head = "| attack | parameter | " + " | ".join(f"{n} RMSE | {n} Hausdorff | {n} dis_av (deg)" for n in names) + " |"
    lines = [head, "|" + "---|" * (2 + 3 * len(names))]
    n = len(sp.attacks)
    for i in range(n):
        cells = []
        for k in range(len(names)):
            r = rows[k * n + i]
            cells += [fmt(r["rmse_rel"], ".2e"), fmt(r["hausdorff_rel"], ".2e"), fmt(r["normal_deg_mean"], ".3f")]
        lines.append(f"| {rows[i]['attack']} | {rows[i]['parameter']} | " + " | ".join(cells) + " |")
    return rows, lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="out/attack_table", help="study results folder (resumed if present)")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--csv", default="attack_table.csv")
    ap.add_argument("--markdown", default="attack_table.md")
    ap.add_argument("--quick", action="store_true", help="the Fandisk only (the test suite runs it)")
    args = ap.parse_args()
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from _common import quick_spec, write_csv
    sp = quick_spec(SPEC, ["../../../shared/meshes/classic/fandisk.obj"]) if args.quick else load_spec(SPEC)
    run(sp, args.out, workers=0 if args.quick and args.workers is None else args.workers, progress=False)
    rows, lines = table(args.out, sp)
    write_csv(rows, args.csv)
    pathlib.Path(args.markdown).write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"wrote {args.csv} and {args.markdown}")


if __name__ == "__main__":
    main()
