"""Maximum-likelihood decoding of the whole frame (data -> data || 20-bit check -> tail-biting code)
over all 2^16 data words, beside the shipped decoder, at the issue's 1/3 point (k = 16, C = 108) under
uniform hard flips (docs/coding.md, "One candidate per attempt"). ML is a measurement of what the frame
could carry, not a decoder that is used: its wrong-message probability cannot be bounded for every
noise.

    .venv/bin/python examples/coding_frame_ml.py [--frames 10000] [--p 0.10] [--quick]

Parameters: k = 16 data bits, C = 108 carriers, key "ml-frame", the default code (coding.encode). ``--quick``: 250 frames.

Ties for the best correlation count as a fraction (1 / number tied) in the second figure.
"""
import argparse
import time

import numpy as np

from meshmark.watermark import coding

K_DATA, C = 16, 108
KEY, METHOD, KIND = "ml-frame", "laplacian", "bits"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=10_000)
    ap.add_argument("--p", type=float, default=0.10)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="250 frames (the test suite runs it)")
    a = ap.parse_args()
    if a.quick:
        a.frames = 250
    t0 = time.time()
    words = ((np.arange(2 ** K_DATA)[:, None] >> np.arange(K_DATA)[::-1]) & 1).astype(np.uint8)
    book = np.empty((words.shape[0], C), np.float32)  # the 2^16 frames' code words, +-1
    for i, w in enumerate(words):
        book[i] = 2.0 * coding.encode(w, KIND, KEY, METHOD, C) - 1
    rng = np.random.default_rng(a.seed)
    truth = rng.integers(0, 2 ** K_DATA, a.frames)
    R = book[truth] * np.where(rng.random((a.frames, C)) < a.p, -1.0, 1.0).astype(np.float32)
    ml = ml_ties = ours = wrong = 0.0
    for b in range(0, a.frames, 250):
        S = book @ R[b:b + 250].T  # (2^16, frames) correlations
        top = S.max(axis=0)
        for j in range(S.shape[1]):
            tr = truth[b + j]
            n_top = int((S[:, j] == top[j]).sum())
            if S[tr, j] == top[j]:
                ml += n_top == 1
                ml_ties += 1.0 / n_top
            got, _ = coding.decode(R[b + j].astype(np.float64), K_DATA, KIND, KEY, METHOD)
            if got is not None:
                ok = np.array_equal(got, words[tr])
                ours += ok
                wrong += not ok
    n = a.frames
    print(f"k={K_DATA} C={C} p={a.p} frames={n}: whole-frame ML {ml / n:.4f} (ties shared {ml_ties / n:.4f}); "
          f"shipped decoder {ours / n:.4f}, wrong messages {int(wrong)}  ({time.time() - t0:.0f} s)")


if __name__ == "__main__":
    main()
