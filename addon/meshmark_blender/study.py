"""The deformation study's outputs (bpy-free): CSV rows, a matplotlib plot and a summary.

A row is a dict with ``frame, nc, cdr, matches, bits, detected, message_ok, max_disp_rel, n_vertices``
(``max_disp_rel``: largest vertex displacement from the marked rest mesh divided by its bounding
box diagonal, NaN when the vertex counts differ; ``n_vertices``: the vertices extraction saw, after
welding if the keyfile welds).
"""
from __future__ import annotations

import csv
import math
import os

COLUMNS = ["frame", "nc", "cdr", "matches", "bits", "detected", "message_ok", "max_disp_rel", "n_vertices"]


def write_csv(rows: list, path: str) -> None:
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({**r, "detected": int(r["detected"]), "message_ok": int(r["message_ok"]),
                        "nc": f"{r['nc']:.6f}", "cdr": f"{r['cdr']:.6f}", "max_disp_rel": f"{r['max_disp_rel']:.6f}"})


def write_plot(rows: list, path: str, title: str = "") -> str | None:
    """PNG of NC and CDR per frame with the relative displacement on a second axis. Returns None
    when written, else why not (matplotlib missing)."""
    try:
        import matplotlib
        matplotlib.use("Agg", force=True)
        import matplotlib.pyplot as plt
    except Exception as exc:  # Blender's own Python may not have matplotlib
        return f"no plot: matplotlib is not available ({exc})"
    fr = [r["frame"] for r in rows]
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=100)
    ax.plot(fr, [r["nc"] for r in rows], "o-", label="NC", color="tab:blue")
    ax.plot(fr, [r["cdr"] for r in rows], "s-", label="CDR", color="tab:green")
    miss = [r["frame"] for r in rows if not r["detected"]]
    if miss:
        ax.plot(miss, [0.0] * len(miss), "x", color="tab:red", label="not detected")
    ax.set_xlabel("frame")
    ax.set_ylabel("NC / CDR")
    ax.set_ylim(-1.05, 1.05)
    ax.grid(True, alpha=0.3)
    ax2 = ax.twinx()
    ax2.plot(fr, [100 * r["max_disp_rel"] for r in rows], "--", color="tab:gray", label="max displacement")
    ax2.set_ylabel("max vertex displacement (% of bbox diagonal)")
    h1, l1 = ax.get_legend_handles_labels()
    h2, l2 = ax2.get_legend_handles_labels()
    ax.legend(h1 + h2, l1 + l2, loc="lower left")
    ax.set_title(title or "meshmark deformation study")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return None


def summarize(rows: list) -> dict:
    n = len(rows)
    if n == 0:
        return {"frames": 0}
    mean = lambda k: sum(r[k] for r in rows) / n
    disp = [r["max_disp_rel"] for r in rows if not math.isnan(r["max_disp_rel"])]
    return {"frames": n, "detected_frames": sum(bool(r["detected"]) for r in rows),
            "message_frames": sum(bool(r["message_ok"]) for r in rows),
            "mean_nc": mean("nc"), "min_nc": min(r["nc"] for r in rows),
            "mean_cdr": mean("cdr"), "min_cdr": min(r["cdr"] for r in rows),
            "max_disp_rel": max(disp) if disp else float("nan")}


def format_table(rows: list) -> str:
    lines = [f"{'frame':>6} {'NC':>7} {'CDR':>7} {'bits':>9} {'detected':>9} {'message':>8} {'max disp':>9}"]
    for r in rows:
        lines.append(f"{r['frame']:>6} {r['nc']:7.3f} {r['cdr']:7.3f} {r['matches']:>4}/{r['bits']:<4} "
                     f"{'yes' if r['detected'] else 'NO':>9} {'ok' if r['message_ok'] else '-':>8} "
                     f"{100 * r['max_disp_rel']:8.1f}%")
    return "\n".join(lines)


def output_paths(output_dir: str, stem: str) -> tuple[str, str]:
    os.makedirs(output_dir, exist_ok=True)
    return os.path.join(output_dir, stem + ".csv"), os.path.join(output_dir, stem + ".png")
