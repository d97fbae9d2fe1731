"""``meshmark steganalysis cho``: the §6.4 detector of Cho et al.'s mean method (registered on the
``steganalysis`` group of meshmark.cli). Every option is checked against its documented range before the
mesh is read (exit status 2 naming the option); exit 0 marked, 1 not marked."""
from __future__ import annotations

import sys

import click

from .. import jsonout
from .cho import MAX_K_SCAN


def add_command(group: click.Group) -> None:
    @group.command("cho")
    @click.argument("inp", metavar="IN")
    @click.option("--k-min", "K_min", type=int, default=1, show_default=True,
                  help=f"Smallest bin number tried, 1..{MAX_K_SCAN:,}.")
    @click.option("--k-max", "K_max", type=int, default=500, show_default=True,
                  help=f"Largest bin number tried, K_MIN..{MAX_K_SCAN:,}; the scan stops at the number of vertices.")
    @click.option("--rule", type=click.Choice(["margin", "thesis"]), default=None,
                  help="Decision rule: margin (default; the margin test with a controlled false-alarm rate) or "
                       "thesis (eqs. 6.4.14-6.4.17; implied by --thesis-exact).")
    @click.option("--false-alarm", type=float, default=0.01, show_default=True,
                  help="margin: largest rate at which clean meshes are called marked, (0, 1).")
    @click.option("--trim", type=int, default=3, show_default=True,
                  help="margin: bins allowed closer to 1/2 than the margin, 0..100.")
    @click.option("--min-count", type=int, default=5, show_default=True,
                  help="margin: bins with fewer vertices are left out, 1..1e9.")
    @click.option("--eps", type=float, default=0.15, show_default=True, help="thesis: eq. 6.4.16 tolerance, [0, 0.5].")
    @click.option("--eps2", type=float, default=0.03, show_default=True,
                  help="thesis: eq. 6.4.17 balance tolerance (with --thesis-exact), [0, 1].")
    @click.option("--thesis-exact", is_flag=True, help="The thesis' rule with the literal eq. 6.4.17.")
    @click.option("--false-reject", type=float, default=0.01, show_default=True,
                  help="thesis: rate at which the balance test rejects random-message marks, (0, 1).")
    @jsonout.option()
    def steganalysis_cho(inp, K_min, K_max, rule, false_alarm, trim, min_count, eps, eps2, thesis_exact,
                         false_reject, as_json):
        """Does IN carry a watermark of Cho et al.'s mean method? (thesis §6.4; docs/radial.md §3)

        Exit status: 0 marked, 1 not marked, 2 usage/input error, 3 internal error.
        """
        from .. import read_mesh
        from .cho import analyze, check_options

        opts = dict(K_min=K_min, K_max=K_max, rule=rule, false_alarm=false_alarm, trim=trim, min_count=min_count,
                    eps=eps, eps2=eps2, thesis_exact=thesis_exact, false_reject=false_reject)
        rule = check_options(**opts)["rule"]  # before any work
        r = analyze(read_mesh(inp), **opts, fit_em=rule == "thesis")  # the EM fits only for the thesis' rule
        d = {"input": inp, "rule": r["rule"], "k_estimate": int(r["k_estimate"]), "detected": bool(r["marked"]),
             "K_max_used": int(r["K_max_used"]),
             "k_margin": int(r["k_margin"]), "marked_margin": bool(r["marked_margin"]), "p_value": float(r["p_value"]),
             "n_tests": int(r["n_tests"]), "margin": float(r["margin"]), "margin_bins": int(r["margin_bins"]),
             "margin_above": int(r["margin_above"])}
        text = (f"{inp}: {'MARKED' if d['detected'] else 'clean'} (Cho mean method, {d['rule']} rule)\n"
                f"margin rule: K'' = {d['k_margin']}, p = {d['p_value']:.3g} over {d['n_tests']} K "
                f"(level {false_alarm:g}), margin {d['margin']:.4f} on {d['margin_bins']} bins "
                f"({d['margin_above']} above 1/2): {'marked' if d['marked_margin'] else 'clean'}")
        if rule == "thesis":
            d.update({"k_thesis": int(r["k_thesis"]), "marked_thesis": bool(r["marked_thesis"]),
                      "bhattacharyya": float(r["bhattacharyya"]), "eq_6_4_16": bool(r["eq_6_4_16"]),
                      "eq_6_4_17": bool(r["eq_6_4_17"]), "min_C": float(r["min_C"]),
                      "max_Ctilde": float(r["max_Ctilde"]), "size_C": int(r["size_C"]),
                      "size_Ctilde": int(r["size_Ctilde"]), "balance_test": bool(r["balance_test"]),
                      "p_balance": float(r["p_balance"]), "thesis_exact": bool(r["thesis_exact"])})
            bal = "(literal eq. 6.4.17)" if d["thesis_exact"] else f"(binomial, p = {d['p_balance']:.3g})"
            text += (f"\nthesis rule: K' = {d['k_thesis']}, Bhattacharyya D = {d['bhattacharyya']:.4g}, clusters "
                     f"{d['size_C']} / {d['size_Ctilde']}, min C {d['min_C']:.4f}, max C~ {d['max_Ctilde']:.4f}; "
                     f"eq. 6.4.16 {'holds' if d['eq_6_4_16'] else 'fails'}, eq. 6.4.17 "
                     f"{'holds' if d['eq_6_4_17'] else 'fails'}; balance rule {bal} "
                     f"{'holds' if d['balance_test'] else 'fails'}: {'marked' if d['marked_thesis'] else 'clean'}")
        jsonout.emit(d, as_json, text, aliases={"marked": "detected"})
        sys.exit(0 if d["detected"] else 1)
