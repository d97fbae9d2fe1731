"""Message success against raw bit-error rate: the old repetition code (8-bit length, data, CRC-8,
repeated, majority vote), the first soft coding (data + 20-bit keyed check, tail-biting K=7 rate-1/3
LTE code, soft Viterbi: ``tbcc7``) and today's default (the keyed random code up to 20 bits, the K=9
rate-1/4 convolutional code with the same check above: ``default``), through the framework's own coding
functions, whitening and key permutation.

    .venv/bin/python examples/coding_curve.py [--frames 10000] [--out examples/out/coding_curve] [--quick]

Channels (applied to the carriers in carrier order, before the key's permutation is undone):

* ``uniform``: each carrier bit flips with probability p (hard decisions: every |soft| = 1);
* ``bursty``: a two-state Gilbert-Elliott chain over the carriers (mean burst 8 carriers, flip
  probability 0.5 in a burst, 0 outside), with the stationary flip rate p;
* ``soft``: Gaussian margins, soft = sign * (mu + N(0, 1)) clipped to [-1, 1] scaled by mu, with mu
  chosen so that P(flip) = p (what the methods' signed reliabilities give the decoder).

A frame succeeds when the exact payload comes back (the old code: length and CRC agree and the data
is right; the others: the decoder accepts and the data is right); a *wrong* message (accepted but
different) is counted separately. Writes a CSV, a Markdown table and a plot.

Configurations: k payload bits on C carriers, among them every k at exactly a third of the capacity
``meshmark capacity`` reports (C = 1.5 (3 k + 20)) and at (k + 20) / C = 1/3.
"""
from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

from meshmark.watermark import coding, keys  # noqa: E402
from meshmark.watermark.payload import Payload, decode as old_decode, repeat_to  # noqa: E402

# (payload bits, carriers)
CONFIGS = [(16, 54), (16, 72), (16, 102), (16, 108), (16, 144), (32, 174), (64, 252), (64, 318)]
# 21-24 bits use the keyed code with a streamed codebook (0.1-0.3 s per frame): run them apart, e.g.
# --configs 24:138 --bers 0.1 --frames 1000 (docs/coding.md)
BERS = [0.02, 0.05, 0.08, 0.10, 0.12, 0.15]
CHANNELS = ["uniform", "bursty", "soft"]


def _qinv(p: float) -> float:
    from statistics import NormalDist
    return NormalDist().inv_cdf(1 - p)


def channel(kind: str, p: float, C: int, rng) -> np.ndarray:
    """(C,) signed soft values of the all-ones word (positive = right) in carrier order."""
    if kind == "uniform":
        return np.where(rng.random(C) < p, -1.0, 1.0)
    if kind == "bursty":
        burst, flip = 8.0, 0.5
        pi_bad = min(1.0, p / flip)  # stationary share of the bad state
        q_bg = 1.0 / burst  # bad -> good
        q_gb = q_bg * pi_bad / max(1e-12, 1 - pi_bad)  # good -> bad
        state = rng.random() < pi_bad
        u = rng.random(C)
        v = rng.random(C)
        out = np.ones(C)
        for i in range(C):  # C <= 252 per frame: a short chain, not a mesh loop
            out[i] = -1.0 if (state and v[i] < flip) else 1.0
            state = (u[i] >= q_bg) if state else (u[i] < q_gb)
        return out
    mu = _qinv(p)
    return np.clip((mu + rng.normal(size=C)) / max(mu, 1e-9), -1.0, 1.0)


def run_point(k: int, C: int, kind: str, p: float, frames: int, rng):
    old_ok = new_ok = old_wrong = new_wrong = k7_ok = k7_wrong = 0
    for f in range(frames):
        key = f"k{f % 8}"  # 8 keys in turn: the keyed codebooks stay cached (the noise is fresh per frame)
        data = rng.integers(0, 2, k).astype(np.uint8)
        pl = Payload("bits", data)
        order = keys.permutation(key, "laplacian", C)
        s = channel(kind, p, C, rng)[order]  # carrier order -> coded-bit order
        # default, and the K = 7 convolutional code it replaced
        c = coding.encode(data, "bits", key, "laplacian", C)
        got, _ = coding.decode((2.0 * c - 1) * s, k, "bits", key, "laplacian")
        if got is not None:
            if np.array_equal(got, data):
                new_ok += 1
            else:
                new_wrong += 1
        c = coding.encode(data, "bits", key, "laplacian", C, coding.TBCC)
        got, _ = coding.decode((2.0 * c - 1) * s, k, "bits", key, "laplacian", coding.TBCC)
        if got is not None:
            if np.array_equal(got, data):
                k7_ok += 1
            else:
                k7_wrong += 1
        # old
        if C >= pl.frame_bits:
            co = repeat_to(pl.frame(), C)
            y = (2.0 * co - 1) * s
            found, _, _ = old_decode((y > 0).astype(np.uint8), np.abs(y), pl.frame_bits, "bits")
            if found is not None:
                if np.array_equal(found.data, data):
                    old_ok += 1
                else:
                    old_wrong += 1
    return old_ok / frames, k7_ok / frames, new_ok / frames, old_wrong, k7_wrong, new_wrong


def plot(rows, path):
    """Success against the bit-error rate, one panel per channel, one colour per (k, C): default solid,
    tbcc7 dotted, old dashed (legend beside the panels)."""
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        return
    channels = list(dict.fromkeys(x["channel"] for x in rows))
    configs = list(dict.fromkeys((int(x["payload_bits"]), int(x["carriers"])) for x in rows))
    fig, axes = plt.subplots(1, len(channels), figsize=(4.5 * len(channels) + 2.5, 4.2), sharey=True, squeeze=False)
    for ax, kind in zip(axes[0], channels):
        for i, (k, C) in enumerate(configs):
            r = [x for x in rows if x["channel"] == kind and int(x["payload_bits"]) == k and int(x["carriers"]) == C]
            b = [float(x["ber"]) for x in r]
            col = f"C{i}"
            ax.plot(b, [float(x["new_success"]) for x in r], "-o", ms=3, color=col, label=f"k={k}, C={C}")
            ax.plot(b, [float(x["tbcc7_success"]) for x in r], ":", color=col)
            ax.plot(b, [float(x["old_success"]) for x in r], "--", color=col, alpha=0.5)
        ax.axhline(0.99, color="k", lw=0.6)
        ax.set_title(f"{kind} bit errors")
        ax.set_xlabel("raw bit-error rate")
        ax.grid(alpha=.3)
    axes[0][0].set_ylabel(f"message success ({rows[0]['frames']} frames / point)")
    h, lab = axes[0][-1].get_legend_handles_labels()
    h += [plt.Line2D([], [], color="k", ls=s_) for s_ in ("-", ":", "--")]
    lab += ["default (solid)", "tbcc7 (dotted)", "old (dashed)"]
    fig.legend(h, lab, loc="center right", fontsize=7)
    fig.tight_layout(rect=(0, 0, 1 - 2.3 / (4.5 * len(channels) + 2.5), 1))
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv=None):
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=10_000)
    ap.add_argument("--channels", default=",".join(CHANNELS), help="comma-separated subset of " + ",".join(CHANNELS))
    ap.add_argument("--plot", nargs="+", metavar="CSV", help="only draw the plot from coding_curve.csv files")
    ap.add_argument("--bers", default="", help="subset of the bit-error rates, e.g. 0.1")
    ap.add_argument("--configs", default="", help="subset of the configurations, e.g. 24:138,64:318 (k:C)")
    ap.add_argument("--out", default=os.path.join(HERE, "out", "coding_curve"))
    ap.add_argument("--quick", action="store_true", help="300 frames, k=16 on C=108, p = 0.05 and 0.10, uniform (tested)")
    a = ap.parse_args(argv)
    if a.quick:
        a.frames, a.channels, a.configs, a.bers = 300, "uniform", a.configs or "16:108", a.bers or "0.05,0.10"
    if a.plot:
        import csv
        rows = [r for p in a.plot for r in csv.DictReader(open(p))]
        os.makedirs(a.out, exist_ok=True)
        plot(rows, os.path.join(a.out, "coding_curve.png"))
        print(f"wrote {a.out}/coding_curve.png")
        return 0
    from _common import write_csv
    rng = np.random.default_rng(2013)
    rows = []
    t0 = time.perf_counter()
    channels = [c for c in a.channels.split(",") if c]
    configs = [tuple(int(x) for x in c.split(":")) for c in a.configs.split(",") if c] or CONFIGS
    bers = [float(b) for b in a.bers.split(",") if b] or BERS
    for kind in channels:
        for k, C in configs:
            for p in bers:
                o, k7, n, ow, k7w, nw = run_point(k, C, kind, p, a.frames, rng)
                rows.append({"channel": kind, "payload_bits": k, "carriers": C, "scheme": coding.scheme_for(k),
                             "payload_per_capacity": round(k / coding.max_data_bits(C), 3),
                             "info_per_carrier": round((k + coding.CHECK_BITS) / C, 3), "ber": p, "frames": a.frames,
                             "old_success": o, "tbcc7_success": k7, "new_success": n,
                             "old_wrong": ow, "tbcc7_wrong": k7w, "new_wrong": nw})
                print(f"{kind:8s} k={k:3d} C={C:3d} p={p:.2f}: old {o:.4f} tbcc7 {k7:.4f} default {n:.4f} "
                      f"wrong {ow}/{k7w}/{nw} ({time.perf_counter() - t0:.0f} s)", flush=True)
    os.makedirs(a.out, exist_ok=True)
    write_csv(rows, os.path.join(a.out, "coding_curve.csv"))
    with open(os.path.join(a.out, "coding_curve.md"), "w") as f:
        f.write("| channel | k | C | k / capacity | (k+20)/C | " +
                " | ".join(f"p={p:.2f} old / tbcc7 / default" for p in bers) + " |\n")
        f.write("|---|---|---|---|---|" + "---|" * len(bers) + "\n")
        for kind in channels:
            for k, C in configs:
                r = [x for x in rows if x["channel"] == kind and x["payload_bits"] == k and x["carriers"] == C]
                f.write(f"| {kind} | {k} | {C} | {k / coding.max_data_bits(C):.2f} | {(k + 20) / C:.2f} | " +
                        " | ".join(f"{x['old_success']:.3f} / {x['tbcc7_success']:.3f} / {x['new_success']:.3f}"
                                   for x in r) + " |\n")
        wrong = sum(x["new_wrong"] + x["tbcc7_wrong"] for x in rows)
        f.write(f"\nWrong messages (tbcc7 + default) in {2 * len(rows) * a.frames:,} decoded frames: {wrong}\n")
    plot(rows, os.path.join(a.out, "coding_curve.png"))
    print(f"wrote {a.out}/coding_curve.{{csv,md,png}} in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
