"""The decoders at the issue's 1/3 point, their wrong-message guarantee, and what maximum-likelihood
decoding of the convolutional frame would give (docs/coding.md, "One candidate per attempt").

k = 16 data bits on C = 108 carriers: (k + 20) / C = 1/3; and on C = 102, where the payload is exactly
a third of what `meshmark capacity` reports (k_max = floor(C / 1.5) - 20 = 48). A 16-bit payload is coded
with the keyed random code (the default up to 16 bits); the tail-biting convolutional code with its
20-bit keyed check (TBCC, the scheme for longer payloads and older keyfiles) is tested beside it.
"""
import numpy as np
import pytest

from meshmark.watermark import coding

K_DATA, C, P = 16, 108, 0.10
KEY, METHOD, KIND = "guarantee-key", "laplacian", "bits"


def _frames(n, p, seed, C=C):
    rng = np.random.default_rng(seed)
    data = rng.integers(0, 2, (n, K_DATA)).astype(np.uint8)
    flips = np.where(rng.random((n, C)) < p, -1.0, 1.0)
    return data, flips


def _decode_all(data, flips, scheme=None):
    ok = wrong = 0
    C = flips.shape[1]
    for d, f in zip(data, flips):
        c = coding.encode(d, KIND, KEY, METHOD, C, scheme)
        got, _ = coding.decode((2.0 * c - 1) * f, K_DATA, KIND, KEY, METHOD, scheme)
        if got is not None:
            ok += bool(np.array_equal(got, d))
            wrong += not np.array_equal(got, d)
    return ok, wrong


def test_one_third_point_on_fixed_frames():
    """2,000 frames, 10 % uniform hard flips. The keyed code (default for 16 bits) keeps >= 99 % at both
    readings of "a third of the capacity" (analytically P(Bin(108, 0.1) <= 20) = 99.78 % and
    P(Bin(102, 0.1) <= 18) = 99.43 %, its acceptance radii); TBCC keeps 97.5-98 % at C = 108 (10^4
    frames in examples/coding_curve.py: 97.5 %). No wrong message from either."""
    data, flips = _frames(2000, P, seed=10)
    ok, wrong = _decode_all(data, flips)
    assert wrong == 0
    assert ok >= 1980, ok  # 99 %; measured 1,995 of 2,000
    ok, wrong = _decode_all(data, flips, coding.TBCC)
    assert wrong == 0
    assert ok >= 1940, ok  # measured 1,961 of 2,000: below the 99 % target, why the keyed code exists
    data, flips = _frames(2000, P, seed=12, C=102)
    ok, wrong = _decode_all(data, flips)
    assert wrong == 0
    assert ok >= 1980, ok  # measured 1,986 of 2,000


def test_whole_frame_ml_would_reach_the_target_but_has_no_guarantee():
    """(TBCC.) Maximum likelihood over all 2^16 data words of the concatenated code (data -> data||check ->
    tail-biting code) decodes every one of 1,000 of the same frames: the 20 check bits are worth a lot
    as redundancy. It is not used, because it compares the received word with 2^16 candidates, and the
    bound on a wrong message is (candidates within the acceptance region) x 2^-20 (docs/coding.md):
    here the best *wrong* word on pure noise is as close as the true word on a 10 %-noise frame."""
    words = ((np.arange(2 ** K_DATA)[:, None] >> np.arange(K_DATA)[::-1]) & 1).astype(np.uint8)
    book = np.empty((words.shape[0], C), np.float32)
    for i, w in enumerate(words):
        book[i] = 2.0 * coding.encode(w, KIND, KEY, METHOD, C, coding.TBCC) - 1
    data, flips = _frames(1000, P, seed=10)
    truth = data @ (1 << np.arange(K_DATA)[::-1])
    R = book[truth] * flips
    S = book @ R.T  # (2^16, frames) correlations
    best = S.argmax(axis=0)
    unique = (S == S.max(axis=0)).sum(axis=0) == 1
    assert np.all((best == truth) & unique)
    # pure noise (an adversary's or a wrong key's word): the best of the 2^16 correlations is high
    noise = np.where(np.random.default_rng(11).random((C, 200)) < 0.5, -1.0, 1.0).astype(np.float32)
    best_noise = (book @ noise).max(axis=0)
    true_at_p = S[truth, np.arange(truth.size)]
    # agreement a = (C + corr) / 2: on pure noise the best of the 2^16 words agrees on 76 of 108
    # (median; a 30 %-noise word), a 10 %-noise frame's true word on about 97. The bound on a wrong
    # message is the number of tail-biting codewords within the acceptance radius times 2^-20; at a
    # radius that keeps ML's gain (18 errors: 99 % of 10 %-noise frames) that number is about 0.35
    # for a random centre and unbounded in the worst case, so ML is not certified (docs/coding.md)
    assert np.median((C + best_noise) / 2) >= 74
    assert np.median((C + true_at_p) / 2) >= 95


@pytest.mark.parametrize("scheme", [coding.KEYED, coding.TBCC])
def test_no_wrong_message_on_heavy_noise_and_random_words(scheme):
    """Heavy flips (20-50 %) and random soft words: a wrong word is accepted with probability <= 1e-6
    per attempt (TBCC: the 20-bit keyed check, 2^-20; keyed code: the union bound over the 2^16 - 1
    other codewords); none in 12,000 attempts of each."""
    wrong = 0
    for p, seed in ((0.2, 20), (0.3, 21), (0.5, 22)):
        data, flips = _frames(3000, p, seed)
        wrong += _decode_all(data, flips, scheme)[1]
    rng = np.random.default_rng(23)
    for _ in range(3000):
        got, _ = coding.decode(rng.normal(size=C), K_DATA, KIND, KEY, METHOD, scheme)
        wrong += got is not None
    assert wrong == 0

