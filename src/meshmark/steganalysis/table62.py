"""Thesis Table 6.2: the §6.4 steganalyzer against Cho's mean method and against Yang's method.

The ``cho_table`` part of the steganalysis study kind (:mod:`meshmark.steganalysis.study`;
``meshmark study run examples/studies/steganalysis.toml``; ``examples/steganalysis_table.py`` is a
wrapper). Moved here from that script unchanged in what it computes.

Every model under each folder (recursively; default ../shared/meshes/corpus and
../shared/meshes/corpus-large) is analysed clean, marked with Cho's mean method as published (alpha =
0.04, delta_k = 0.001, bins = bits, no re-synchronisation) and marked with Yang's method (K = 400,
n_thr from the rule), with 64 and with 100 bits. Messages are balanced (a random permutation of equal
numbers of 0 and 1): with eps' = 0.03, eq. 6.4.17 accepts only a 32/32 split at K' = 64
(docs/radial.md §3), so Table 6.2's 94.6% detection implies balanced messages. A model counts as
marked ("can carry the mark") when the embedding reports no failed bin (Cho) / enough embeddable
pairs (Yang) and the blind extraction returns every bit.

Variants of Cho's 64-bit mark, for the investigation of the low K accuracy (docs/radial.md §9):
a uniformly random message instead of a balanced one (eq. 6.4.17), the robust mode (guard 0.005 and
20 centre re-synchronisations: no centroid drift), and alpha = 0.02 / 0.06 (the ends of the range
§8.2 draws alpha from).

Three decisions per row: ``marked_margin`` (the detector's default margin rule, false-alarm level 1 %
over the K scan; docs/radial.md §3.2), ``marked`` (the thesis' rule with the binomial balance test,
false-reject 1 %) and ``marked_thesis`` (the thesis' rule with eq. 6.4.17 literally, eps' = 0.03;
docs/steganalysis.md §5). ``k_estimate`` is the thesis' K' (eq. 6.4.15), ``k_margin`` the margin rule's.

Writes OUT.csv (one row per model and case: D at K' and at the true K, eqs. 6.4.16/17, ...),
OUT_summary.csv (per folder, combined and per size class) and OUT.png (K accuracy and detection
against the number of vertices per bin), and prints the tables. Thesis: Cho 64 bits 443 models,
96.84% / 94.58%; 100 bits 386, 96.63% / 93.01%; Yang 64 bits 377, 0.65% / 6.63%; 100 bits 371, 0 /
6.74%. The meshes of corpus-large may not be copied into the repository (its SOURCES.md); only
derived numbers are written.
"""
from __future__ import annotations

import csv
import pathlib
import time

import numpy as np

import meshmark
from meshmark.steganalysis import cho as stega
from meshmark.watermark import cho, radial

SUFFIXES = {".obj", ".off", ".ply", ".stl"}
THESIS = {("cho", 64): (443, 96.84, 94.58), ("cho", 100): (386, 96.63, 93.01),
          ("yang", 64): (377, 0.65, 6.63), ("yang", 100): (371, 0.0, 6.74)}
# case -> (method, bits, alpha, balanced message, robust mode)
MAIN = {"cho": ("cho", None, 0.04, True, False), "yang": ("yang", None, None, True, False)}
VARIANTS = {"cho-random": ("cho", 64, 0.04, False, False), "cho-random-100": ("cho", 100, 0.04, False, False),
            "cho-random-a0.06": ("cho", 64, 0.06, False, False), "cho-robust": ("cho", 64, 0.04, True, True),
            "cho-a0.02": ("cho", 64, 0.02, True, False), "cho-a0.06": ("cho", 64, 0.06, True, False)}
SIZE_CLASSES = [(0, 50), (50, 100), (100, 200), (200, 400), (400, np.inf)]  # vertices per bin at K = 64


def referenced(m):
    used = np.zeros(m.n_vertices, bool)
    used[m.face_indices] = True
    return np.ascontiguousarray(m.V[used])


def message(n, balanced, rng):
    return rng.permutation(np.repeat([0, 1], n // 2)) if balanced else rng.integers(0, 2, n)


def mark(V, method, bits, alpha, robust):
    """(marked V or None, carried)."""
    n = len(bits)
    try:
        if method == "cho":
            kw = dict(guard=0.005, center_iters=20) if robust else {}
            Vm, info = cho.embed_bits(V, None, bits, method="mean", alpha=alpha, **kw)
            return Vm, not info["failed_bins"] and np.array_equal(cho.extract_bits(Vm, None, n)[0], bits)
        Vm, _ = radial.embed_bits(V, None, bits, K=400)
        return Vm, np.array_equal(radial.extract_bits(Vm, None, n, K=400)[0], bits)
    except meshmark.MeshError:
        return None, False


def analyse_row(V, true_k):
    r = stega.analyze(V)
    D, lp = np.asarray(r["D"]), np.asarray(r["log10_p"])
    at = (lambda a: float(a[true_k - 1]) if 0 < true_k <= len(a) else float("nan"))  # noqa: E731 (K_min = 1)
    return {"k_estimate": r["k_thesis"], "D": r["bhattacharyya"], "D_true": at(D), "marked": bool(r["marked_thesis"]),
            "marked_thesis": bool(r["eq_6_4_16"] and r["eq_6_4_17"]), "k_margin": r["k_margin"],
            "marked_margin": bool(r["marked_margin"]), "p_value": r["p_value"], "log10_p_true": at(lp),
            "p_balance": r["p_balance"],
            "eq_6_4_16": bool(r["eq_6_4_16"]), "eq_6_4_17": bool(r["eq_6_4_17"]), "min_C": r["min_C"],
            "max_Ctilde": r["max_Ctilde"], "size_C": r["size_C"], "size_Ctilde": r["size_Ctilde"]}


def models(folder: pathlib.Path):
    return sorted(p for p in folder.rglob("*") if p.is_file() and p.suffix.lower() in SUFFIXES)


FIELDS = ["folder", "path", "model", "n_vertices", "case", "bits", "alpha", "ones", "carried", "k_estimate", "D",
          "D_true", "marked", "marked_thesis", "k_margin", "marked_margin", "p_value", "log10_p_true", "p_balance", "eq_6_4_16", "eq_6_4_17", "min_C", "max_Ctilde", "size_C", "size_Ctilde"]


def pct(flags):
    return 100.0 * float(np.mean(flags)) if len(flags) else float("nan")


def _rates(car, bits):
    """K accuracy and detection of the marked models ``car`` under the three decisions; ``wrong_k_margin``:
    % of the margin rule's detections that report another K than the embedding one."""
    det = [r for r in car if r["marked_margin"]]
    return {"k_accuracy": pct([r["k_estimate"] == bits for r in car]), "detection": pct([r["marked"] for r in car]),
            "detection_thesis": pct([r["marked_thesis"] for r in car]),
            "k_accuracy_margin": pct([r["k_margin"] == bits for r in car]),
            "detection_margin": pct([r["marked_margin"] for r in car]),
            "wrong_k_margin": pct([r["k_margin"] != bits for r in det]), "false_positives": "",
            "false_positives_thesis": "", "false_positives_margin": ""}


def summarise(rows, cases):
    """(group, case, bits) -> n models, n carried, K accuracy %, detection % (and FP % for clean)."""
    out = []
    groups = {"combined": rows}
    for g in sorted({r["folder"] for r in rows}):
        groups[g] = [r for r in rows if r["folder"] == g]
    psb = [r for r in rows if "/psb-seg/" in r["path"]]
    if psb:
        groups["corpus-large/psb-seg"] = psb
    for g, rs in groups.items():
        clean = [r for r in rs if r["case"] == "clean"]
        out.append({"group": g, "case": "clean", "bits": 0, "models": len(clean), "marked_models": "",
                    "k_accuracy": "", "detection": "", "detection_thesis": "", "k_accuracy_margin": "",
                    "detection_margin": "", "wrong_k_margin": "",
                    "false_positives": pct([r["marked"] for r in clean]),
                    "false_positives_thesis": pct([r["marked_thesis"] for r in clean]),
                    "false_positives_margin": pct([r["marked_margin"] for r in clean])})
        for case, bits in cases:
            sel = [r for r in rs if r["case"] == case and r["bits"] == bits]
            car = [r for r in sel if r["carried"]]
            out.append({"group": g, "case": case, "bits": bits, "models": len(sel), "marked_models": len(car),
                        **_rates(car, bits)})
    for lo, hi in SIZE_CLASSES:  # Cho as published by vertices per bin, all folders
        for case, bits in cases:
            if not case.startswith("cho"):
                continue
            car = [r for r in rows if r["case"] == case and r["bits"] == bits and r["carried"]
                   and lo <= r["n_vertices"] / bits < hi]
            out.append({"group": f"{lo}-{hi} vertices/bin", "case": case, "bits": bits, "models": len(car),
                        "marked_models": len(car), **_rates(car, bits)})
    return out


def plot(rows, cases, path):
    from ..optional import pyplot
    plt = pyplot("the Table 6.2 plot")

    fig, axes = plt.subplots(1, 2, figsize=(12, 4.5))
    edges = np.array([10, 25, 50, 100, 200, 400, 800, 1600])
    for case, bits in cases:
        if case == "yang":
            continue
        car = [r for r in rows if r["case"] == case and r["bits"] == bits and r["carried"]]
        if not car:
            continue
        vpb = np.array([r["n_vertices"] / bits for r in car])
        for kkey, dkey, style, rule in (("k_margin", "marked_margin", "o-", "margin"), ("k_estimate", "marked", "s--", "thesis")):
            kok = np.array([r[kkey] == bits for r in car], float)
            det = np.array([r[dkey] for r in car], float)
            centres, ka, de = [], [], []
            for lo, hi in zip(edges[:-1], edges[1:]):
                m = (vpb >= lo) & (vpb < hi)
                if m.sum() >= 3:
                    centres.append(np.sqrt(lo * hi))
                    ka.append(100 * kok[m].mean())
                    de.append(100 * det[m].mean())
            label = f"{case} {bits} bits, {rule} rule"
            axes[0].plot(centres, ka, style, label=label)
            axes[1].plot(centres, de, style, label=label)
    for ax, title in zip(axes, ("accuracy of K (margin: argmin p_K; thesis: eq. 6.4.15)",
                                "detection (margin 1 % scan; thesis: eqs. 6.4.16-17)")):
        ax.set_xscale("log")
        ax.set_xticks([12, 25, 50, 100, 200, 400])
        ax.set_xticklabels(["12", "25", "50", "100", "200", "400"])
        ax.minorticks_off()
        ax.set_xlabel("vertices per bin (n / number of bits)")
        ax.set_ylabel("% of the marked models")
        ax.set_ylim(-3, 103)
        ax.axhline(96.8 if "accuracy" in title else 94.6, color="k", ls=":", lw=1, label="thesis, Cho 64 bits")
        ax.set_title(title)
        ax.grid(alpha=0.3)
    axes[1].legend(fontsize=8, loc="lower right")
    fig.suptitle("§6.4 steganalyzer vs Cho's mean method (bins of >= 3 models)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def run(folders, out, limit: int = 0, variants: bool = True, log=print) -> list[str]:
    """Analyse every model under ``folders``; write OUT.csv, OUT_summary.csv, OUT.png; return the tables
    (markdown lines)."""
    out = pathlib.Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    cases = {**MAIN, **(VARIANTS if variants else {})}
    rows = []
    t0 = time.perf_counter()
    for folder in map(pathlib.Path, folders):
        if not folder.is_dir():
            raise meshmark.MeshError(f"cho_table: no such folder: {folder}")
        files = models(folder)[: limit or None]
        for i, path in enumerate(files):
            try:
                V = referenced(meshmark.read_mesh(path))
            except meshmark.MeshError as exc:
                log(f"skip {path.name}: {exc}")
                continue
            base = {"folder": folder.name, "path": str(path.relative_to(folder.parent)), "model": path.name,
                    "n_vertices": len(V)}
            rng = np.random.default_rng(i)
            rows.append({**base, "case": "clean", "bits": 0, "alpha": "", "ones": 0, "carried": True,
                         **analyse_row(V, 0)})
            for case, (method, nbits, alpha, balanced, robust) in cases.items():
                for n in ((64, 100) if nbits is None else (nbits,)):
                    bits = message(n, balanced, rng)
                    Vm, carried = mark(V, method, bits, alpha, robust)
                    res = analyse_row(Vm, n) if carried else {"k_estimate": 0, "D": float("nan"),
                                                             "D_true": float("nan"), "marked": False,
                                                             "marked_thesis": False, "k_margin": 0,
                                                             "marked_margin": False}
                    rows.append({**base, "case": case, "bits": n, "alpha": alpha or "", "ones": int(bits.sum()),
                                 "carried": carried, **res})
            log(f"[{folder.name} {i + 1}/{len(files)}] {path.name} ({len(V)} v) {time.perf_counter() - t0:.0f} s")
    with open(f"{out}.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=FIELDS, restval="")
        w.writeheader()
        w.writerows(rows)
    case_bits = [(c, n) for c, (_, nb, *_rest) in cases.items() for n in ((64, 100) if nb is None else (nb,))]
    summary = summarise(rows, case_bits)
    with open(f"{out}_summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(summary[0]))
        w.writeheader()
        w.writerows(summary)
    plot(rows, case_bits, f"{out}.png")

    L = []
    fmt = lambda v: "" if v == "" else ("-" if v != v else f"{v:.1f}%")  # noqa: E731 (NaN: no model)
    L.append("margin: the default rule (1 % false-alarm level over the K scan, docs/radial.md §3.2); thesis: "
             "K' of eq. 6.4.15 with the binomial balance rule (false-reject 1 %); literal: eq. 6.4.17 with eps' = 0.03")
    L.append("\n| models | method | #bits | #marked models (of) | K acc. margin | det. margin | wrong K | "
             "K acc. thesis | det. thesis | literal | thesis Table 6.2 (#, K acc, det.) |")
    L.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for s in summary:
        if s["case"] in MAIN and "vertices/bin" not in s["group"]:
            t = THESIS[(s["case"], s["bits"])]
            label = "Cho's" if s["case"] == "cho" else "Ours (Yang)"
            L.append(f"| {s['group']} | {label} | {s['bits']} | {s['marked_models']} ({s['models']}) | "
                     f"{fmt(s['k_accuracy_margin'])} | {fmt(s['detection_margin'])} | {fmt(s['wrong_k_margin'])} | "
                     f"{fmt(s['k_accuracy'])} | {fmt(s['detection'])} | {fmt(s['detection_thesis'])} | "
                     f"{t[0]}, {t[1]}%, {t[2]}% |")
    L.append("\n| models | false positives on clean models, margin | thesis (binomial) | literal |\n|---|---:|---:|---:|")
    for s in summary:
        if s["case"] == "clean":
            L.append(f"| {s['group']} ({s['models']}) | {fmt(s['false_positives_margin'])} | "
                     f"{fmt(s['false_positives'])} | {fmt(s['false_positives_thesis'])} |")
    if variants:
        L.append("\n| Cho 64 bits, combined | #marked models | K acc. margin | det. margin | K acc. thesis | det. thesis | "
                 "literal |\n|---|---:|---:|---:|---:|---:|---:|")
        for s in summary:
            if s["group"] == "combined" and s["case"].startswith("cho") and s["bits"] == 64:
                L.append(f"| {s['case']} | {s['marked_models']} | {fmt(s['k_accuracy_margin'])} | "
                         f"{fmt(s['detection_margin'])} | {fmt(s['k_accuracy'])} | {fmt(s['detection'])} | "
                         f"{fmt(s['detection_thesis'])} |")
    L.append("\n| vertices per bin | case | #bits | #marked models | K acc. margin | det. margin | K acc. thesis | "
             "det. thesis |\n|---|---|---:|---:|---:|---:|---:|---:|")
    for s in summary:
        if "vertices/bin" in s["group"] and s["case"] in ("cho", "cho-a0.06"):
            L.append(f"| {s['group'].split()[0]} | {s['case']} | {s['bits']} | {s['marked_models']} | "
                     f"{fmt(s['k_accuracy_margin'])} | {fmt(s['detection_margin'])} | {fmt(s['k_accuracy'])} | "
                     f"{fmt(s['detection'])} |")
    L.append(f"\nwrote {out}.csv, {out}_summary.csv, {out}.png ({time.perf_counter() - t0:.0f} s)")
    return L
