"""The robustness table: what each method survives, blind and as copy tracing (issue 22).

    meshmark study run examples/studies/robustness.toml --out out/robustness    # the full study
    .venv/bin/python examples/robustness_table.py --results out/robustness      # table, plot, verdicts
    .venv/bin/python examples/robustness_table.py --quick                       # run + table, 1 mesh
    .venv/bin/python examples/robustness_table.py --results out/robustness --docs   # into docs/attacks.md

Reads the study's results (Parquet under RESULTS/results, or a CSV of them) and writes:

* ``robustness.md``: the markdown table (rows: attack x strength in the spec's order; per method:
  blind *detected* and *message* recovered, and copy tracing's *right copy* and *wrong copy*; the
  informed-tracing columns last), each cell ``percent (trials)``, then the verdicts below;
* ``robustness.csv``: the counts behind every cell; ``robustness.png``: the same as a heat map.

Trials are the rows with status ``ok``; rows whose mesh could not take the mark or whose attack
refused the mesh (``mesh_error``: e.g. remeshing a non-manifold mesh) are left out and counted under
the table. Verdicts (derived from the numbers, thresholds as the acceptance of issue 22): a method
**survives** an attack when its mark is detected on >= 95 % of the trials (tracing: the right copy on
>= 95 % and a wrong copy never), **partly** from 50 % (tracing: right >= 50 %, never wrong), else it
**does not survive**; a wrong copy named even once is reported as such.

Quick mode (``--quick``, the CI test): the same spec on ``classic/spot.obj`` only (2,930 vertices), seed 0,
10 copies per traced asset, run in this process.
"""
from __future__ import annotations

import argparse
import csv
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
SPEC = ROOT / "examples" / "studies" / "robustness.toml"
METHODS = ["laplacian", "cho-mean", "cho-variance", "radial"]
SURVIVE, PARTLY = 0.95, 0.50
QUICK_MESH = "../../../shared/meshes/classic/spot.obj"


def load_raw(path=SPEC) -> dict:
    import tomllib
    return tomllib.loads(pathlib.Path(path).read_text())


def quick_raw(path=SPEC, n_copies: int = 10) -> dict:
    """The spec in quick mode: one small mesh, seed 0, ``n_copies`` copies per traced asset."""
    raw = load_raw(path)
    raw["meshes"] = {"paths": [QUICK_MESH]}
    raw["study"]["seeds"] = [0]
    for m in raw["methods"]:
        if m["name"] == "trace":
            m["params"]["n_copies"] = n_copies
    return raw


def run_study(raw: dict, out, workers=None):
    from meshmark.study import load_spec, run
    return run(load_spec(raw, base=SPEC.parent), out, workers=workers, progress=False)


def read_rows(results) -> list:
    p = pathlib.Path(results)
    if p.suffix == ".csv":
        with open(p, newline="") as f:
            rows = list(csv.DictReader(f))
        for r in rows:  # CSV text back to values
            for k in ("detected", "message_ok"):
                r[k] = {"True": True, "False": False}.get(r.get(k), None)
        return rows
    from meshmark.study import load_results
    return load_results(p).to_pylist()


def attack_order(raw: dict) -> list:
    from meshmark.study import load_spec
    return [a.label for a in load_spec(raw, base=SPEC.parent).attacks]


def columns() -> list:
    """(column key, header): per method blind detected / message, tracing right / wrong; informed last."""
    cols = []
    for m in METHODS:
        cols += [((m, "detected"), f"{m} detected"), ((m, "message"), f"{m} message"),
                 ((f"trace {m}", "right"), f"{m} right copy"), ((f"trace {m}", "wrong"), f"{m} wrong copy")]
    cols += [(("trace-informed laplacian", "right"), "informed laplacian right copy"),
             (("trace-informed laplacian", "wrong"), "informed laplacian wrong copy")]
    return cols


def cells(rows: list) -> dict:
    """(attack, method label, what) -> dict(k, n, excluded, unavailable)."""
    out: dict = {}

    def cell(a, m, w):
        return out.setdefault((a, m, w), {"k": 0, "n": 0, "excluded": 0, "unavailable": 0})

    for r in rows:
        a, m = r["attack"], r["method"]
        whats = ("right", "wrong") if m.startswith("trace") else ("detected", "message")
        for w in whats:
            c = cell(a, m, w)
            if r["status"] != "ok":
                c["excluded"] += 1
                continue
            if m.startswith("trace"):
                if r.get("trace_informed") == "unavailable":
                    c["unavailable"] += 1
                    continue
                c["n"] += 1
                c["k"] += r.get("trace_outcome") == w
            else:
                c["n"] += 1
                c["k"] += bool(r["detected"] if w == "detected" else r["message_ok"])
    return out


def fmt(c: dict | None) -> str:
    if c is None:
        return "-"
    if c["n"] == 0:
        return "unavailable" if c["unavailable"] else "-"
    return f"{100 * c['k'] / c['n']:.0f} ({c['n']})"


def markdown(rows: list, order: list) -> str:
    cs, cols = cells(rows), columns()
    lines = ["| attack | " + " | ".join(h for _, h in cols) + " |", "|---|" + "---:|" * len(cols)]
    for a in order:
        lines.append(f"| {a} | " + " | ".join(fmt(cs.get((a, m, w))) for (m, w), _ in cols) + " |")
    n_rows = len(rows)
    excl = [r for r in rows if r["status"] != "ok"]
    meshes = sorted({r["mesh"] for r in rows})
    seeds = sorted({int(r["seed"]) for r in rows})
    lines += ["", f"Cells: percent of the trials (trials). {n_rows} tasks on {len(meshes)} meshes, seeds "
                  f"{', '.join(map(str, seeds))}; {len(excl)} left out (mesh_error)" + (":" if excl else ".")]
    why: dict = {}
    for r in excl:  # grouped by method and message (numbers as N), with the meshes
        msg = re.sub(r"\d+", "N", (r.get("error") or "").split(";")[0].split(" (")[0])[:90]
        n, where = why.get((r["method"], msg), (0, set()))
        why[(r["method"], msg)] = (n + 1, where | {r["mesh"].split("/")[-1]})
    for (m, msg), (n, where) in sorted(why.items(), key=lambda x: (-x[1][0], x[0])):
        lines.append(f"* {n} x {m}: {msg} ({', '.join(sorted(where))})")
    return "\n".join(lines)


def verdict(c: dict | None, wrong: dict | None = None, tracing: bool = False) -> str | None:
    if c is None or c["n"] == 0:
        return None
    f = c["k"] / c["n"]
    if tracing and wrong is not None and wrong["k"]:
        return "wrong"
    return "survives" if f >= SURVIVE else "partly" if f >= PARTLY else "lost"


def verdicts(rows: list, order: list) -> str:
    """Plain sentences per method: what it survives, partly survives and does not, blind and traced."""
    cs = cells(rows)
    out = [f"Thresholds: survives = detected (tracing: right copy) on >= {SURVIVE:.0%} of the trials, "
           f"partly >= {PARTLY:.0%}, else does not survive; a wrong copy named once is listed as such."]
    for m in METHODS:
        for label, key, tracing in ((f"**{m}**, blind (keyfile only)", m, False),
                                    (f"**{m}**, copy tracing", f"trace {m}", True)):
            groups: dict = {"survives": [], "partly": [], "lost": [], "wrong": []}
            for a in order:
                if a == "no attack":
                    continue
                w = "right" if tracing else "detected"
                v = verdict(cs.get((a, key, w)), cs.get((a, key, "wrong")), tracing)
                if v:
                    groups[v].append(a)
            parts = []
            if groups["survives"]:
                parts.append("survives " + ", ".join(groups["survives"]))
            if groups["partly"]:
                parts.append("partly survives " + ", ".join(groups["partly"]))
            if groups["lost"]:
                parts.append("does not survive " + ", ".join(groups["lost"]))
            if groups["wrong"]:
                parts.append("NAMES A WRONG COPY after " + ", ".join(groups["wrong"]))
            if parts:
                out.append(f"* {label}: " + "; ".join(parts) + ".")
    inf = [cs.get((a, "trace-informed laplacian", "right")) for a in order]
    if inf and all(c is not None and c["n"] == 0 and c["unavailable"] for c in inf):
        out.append("* **informed tracing**: unavailable in this meshmark (`tracing.trace` takes no `original`).")
    return "\n".join(out)


def write_csv(rows: list, order: list, path):
    cs = cells(rows)
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["attack", "method", "what", "k", "n", "excluded", "unavailable"])
        for a in order:
            for (m, what), _ in columns():
                c = cs.get((a, m, what))
                if c is not None:
                    w.writerow([a, m, what, c["k"], c["n"], c["excluded"], c["unavailable"]])


def plot(rows: list, order: list, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np
    cs, cols = cells(rows), columns()
    Z = np.full((len(order), len(cols)), np.nan)
    for i, a in enumerate(order):
        for j, ((m, w), _) in enumerate(cols):
            c = cs.get((a, m, w))
            if c is not None and c["n"]:
                Z[i, j] = 100 * c["k"] / c["n"]
    fig, ax = plt.subplots(figsize=(1.0 + 0.45 * len(cols), 1.5 + 0.35 * len(order)))
    good = Z.copy()  # colour by how good a cell is: a wrong copy named is bad
    wrong = [j for j, ((m, w), _) in enumerate(cols) if w == "wrong"]
    good[:, wrong] = 100 - good[:, wrong]
    im = ax.imshow(good, cmap="RdYlGn", vmin=0, vmax=100, aspect="auto")
    ax.set_xticks(range(len(cols)), [h for _, h in cols], rotation=60, ha="right", fontsize=7)
    ax.set_yticks(range(len(order)), order, fontsize=7)
    for i in range(len(order)):
        for j in range(len(cols)):
            if not np.isnan(Z[i, j]):
                ax.text(j, i, f"{Z[i, j]:.0f}", ha="center", va="center", fontsize=6)
    fig.colorbar(im, ax=ax, label="% of trials (numbers); colour: green = good (wrong copy: 0 % is green)")
    ax.set_title("robustness (examples/studies/robustness.toml)", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def report(results, raw: dict, out_dir) -> dict:
    rows = [r for r in read_rows(results)]
    order = attack_order(raw)
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    md = markdown(rows, order) + "\n\n" + verdicts(rows, order) + "\n"
    (out_dir / "robustness.md").write_text(md)
    write_csv(rows, order, out_dir / "robustness.csv")
    plot(rows, order, out_dir / "robustness.png")
    return {"markdown": md, "rows": len(rows)}


BEGIN, END = "<!-- robustness table: begin (examples/robustness_table.py --docs) -->", "<!-- robustness table: end -->"


def update_docs(md: str, path=ROOT / "docs" / "attacks.md") -> None:
    """Replace the generated part of docs/attacks.md (between the BEGIN and END markers) by ``md``."""
    text = pathlib.Path(path).read_text()
    if BEGIN not in text or END not in text:
        raise SystemExit(f"{path}: no {BEGIN!r} ... {END!r} markers")
    head, rest = text.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    pathlib.Path(path).write_text(head + BEGIN + "\n" + md.rstrip() + "\n" + END + tail)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--results", default=None, help="study results folder (or a CSV of its rows)")
    ap.add_argument("--quick", action="store_true", help="run the quick mode into --results (default out/robustness-quick)")
    ap.add_argument("--run", action="store_true", help="run (or resume) the full spec into --results first")
    ap.add_argument("--workers", type=int, default=None)
    ap.add_argument("--docs", action="store_true", help="also write the table and verdicts into docs/attacks.md")
    ap.add_argument("--out", default=None, help="folder for robustness.md / .csv / .png (default: the results folder)")
    a = ap.parse_args(argv)
    raw = quick_raw() if a.quick else load_raw()
    results = a.results or ("out/robustness-quick" if a.quick else "out/robustness")
    if a.quick or a.run:
        run_study(raw, results, workers=0 if a.quick and a.workers is None else a.workers)
    d = report(results, raw, a.out or (results if not str(results).endswith(".csv") else pathlib.Path(results).parent))
    if a.docs:
        update_docs(d["markdown"])
    sys.stdout.write(d["markdown"])
    return d


if __name__ == "__main__":
    main()
