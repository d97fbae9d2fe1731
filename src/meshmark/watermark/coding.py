"""Channel coding of the payload: three schemes, chosen by the payload length and stored in the keyfile.

* :data:`KEYED` (payloads of 1-24 bits): the keyed random code of :mod:`.keyed_code`, maximum-likelihood
  decoded over all 2^k words with an exact 1e-6 acceptance threshold; no check bits.
* :data:`TBCC9` (longer payloads): data + 20-bit keyed check, tail-biting convolutional code of rate 1/4
  and constraint length 9 (below).
* :data:`TBCC` (every keyfile written before the two above): the same frame with LTE's rate-1/3,
  constraint-length-7 code. Still read; no longer written.

The convolutional schemes: a payload of k data bits becomes ``k + CHECK_BITS`` information bits::

    [ data: k bits ][ check: 20 bits = HMAC-SHA256(key, method, kind, data) truncated ]

encoded tail-biting (the encoder starts in the state its last K - 1 inputs leave it in: no tail bits,
n (k + 20) code bits for a rate-1/n code) with

* TBCC: generators 133, 171, 165 octal, K = 7 (3GPP TS 36.212 §5.1.3.1, free distance 15);
* TBCC9: generators 463, 535, 733, 745 octal, K = 9 (the maximum-free-distance rate-1/4 code of
  Larsen 1973, free distance 24; Proakis, Digital Communications, table of rate-1/4 codes).

The code bits are *rate-matched* to the C carriers the mesh offers (:func:`rate_match`): in priority
order (all of generator 0, then every further generator in a low-discrepancy order of positions) and
cyclically repeated when C > n (k + 20), punctured below (at least :func:`min_carriers` = 1.5 (k + 20)
carriers, rate 2/3, for every scheme). Decoding sums the carriers' signed reliabilities per code bit
and runs a soft Viterbi decoder (native, wrap-around for tail-biting, ``meshmark._core.viterbi_decode``);
the message is accepted only if the recomputed check matches.

Nothing is framed that the keyfile already knows: the data length k is in the keyfile.

Why 20 check bits: a wrong message needs a decoding error *and* a check collision; the check is a
keyed MAC, so a collision has probability 2^-20 = 9.5e-7 whatever the error pattern, and a wrong
message is rarer than 1e-6 per attempt even if every decoding failed. The keyed code reaches the same
bound without check bits (:mod:`.keyed_code`). The framework also never returns a message without a
detection (p_false_alarm < 1e-6). docs/coding.md has the measured curves of all three beside the old
repetition code.
"""
from __future__ import annotations

import hashlib
import hmac
import math

import numpy as np

from .. import _core
from .._core import MeshError
from . import keyed_code
from .._typing import UInt8Array

TBCC = "tbcc7-r13-mac20"
TBCC9 = "tbcc9-r14-mac20"
KEYED = "keyed-aes-ml-v1"
SCHEMES = (KEYED, TBCC9, TBCC)
CONVOLUTIONAL = {  # scheme -> (generators, constraint length)
    TBCC: ((0o133, 0o171, 0o165), 7),
    TBCC9: ((0o463, 0o535, 0o733, 0o745), 9),
}
GENERATORS, CONSTRAINT = CONVOLUTIONAL[TBCC]  # the LTE code (keyfiles before the keyed code)
CHECK_BITS = 20
MIN_RATE_DEN = 1.5  # at least 1.5 carriers per information bit (punctured rate 2/3)
WRAP = 6 * (CONSTRAINT - 1) + 6  # wrap-around depth of the tail-biting decoder for TBCC (steps)
_PHI = (math.sqrt(5.0) - 1.0) / 2.0


def wrap_depth(constraint: int) -> int:
    """Wrap-around depth (steps) of the tail-biting Viterbi decoder for constraint length K."""
    return 6 * (int(constraint) - 1) + 6


def scheme_for(n_data: int) -> str:
    """The scheme new keyfiles use for ``n_data`` payload bits: the keyed code up to 24 bits, then the
    K = 9 rate-1/4 convolutional code (each decodes more frames than LTE's K = 7 code at the carrier
    counts measured, docs/coding.md)."""
    return KEYED if 1 <= int(n_data) <= keyed_code.MAX_DATA_BITS else TBCC9


def coding_field(n_data: int, n_coded: int) -> dict:
    """The keyfile's ``coding`` field for a new embedding."""
    scheme = scheme_for(n_data)
    if scheme == KEYED:
        return {"scheme": KEYED, "info_bits": int(n_data), "check_bits": 0, "n_coded": int(n_coded)}
    return {"scheme": scheme, "info_bits": info_bits(n_data), "check_bits": CHECK_BITS, "n_coded": int(n_coded)}


def info_bits(n_data: int) -> int:
    """Information bits of a convolutional frame: data + check."""
    return int(n_data) + CHECK_BITS


def min_carriers(n_data: int) -> int:
    """Fewest carriers that take a payload of ``n_data`` bits (punctured rate 2/3), for every scheme (the
    keyed code would decode noise-free from k + 20 carriers; one rule keeps the capacity that
    ``meshmark capacity`` and the automatic parameters report independent of the scheme)."""
    return int(math.ceil(MIN_RATE_DEN * info_bits(n_data)))


def max_data_bits(n_carriers: int) -> int:
    """Longest payload (bits) ``n_carriers`` carriers take (0 if none)."""
    return max(0, int(math.floor(n_carriers / MIN_RATE_DEN + 1e-9)) - CHECK_BITS)


def check(key: str, method: str, kind: str, data: np.ndarray) -> np.ndarray:
    """The keyed check: the first CHECK_BITS bits of HMAC-SHA256(key, method/kind/length/data)."""
    data = np.asarray(data, np.uint8)
    msg = f"meshmark/v1/{method}/check/{kind}/{data.size}/".encode() + np.packbits(data).tobytes()
    tag = hmac.new(key.encode("utf-8"), msg, hashlib.sha256).digest()
    return np.unpackbits(np.frombuffer(tag, np.uint8))[:CHECK_BITS]


def _spread(L: int) -> np.ndarray:
    """The positions 0..L-1 in a low-discrepancy order (every prefix is spread over the block)."""
    return np.argsort((np.arange(L) * _PHI) % 1.0, kind="stable")


def rate_match(L: int, C: int, n_generators: int = len(GENERATORS)) -> np.ndarray:
    """(C,) index into the n L interleaved code bits (c[n t + j]) carried by each of the C carriers."""
    n = int(n_generators)
    order = np.concatenate([np.arange(L) * n] + [_spread(L) * n + j for j in range(1, n)])
    return order[np.arange(C) % order.size]


def _conv(scheme: str):
    try:
        return CONVOLUTIONAL[scheme]
    except KeyError:
        raise MeshError(f"unknown coding scheme {scheme!r} (known: {', '.join(SCHEMES)})") from None


def encode(data: np.ndarray, kind: str, key: str, method: str, C: int, scheme: str | None = None) -> np.ndarray:
    """(C,) coded bits (0/1) carrying ``data`` under ``scheme`` (default :func:`scheme_for`)."""
    data = np.asarray(data, np.uint8)
    if C < min_carriers(data.size):
        raise MeshError(f"{data.size} payload bits need at least {min_carriers(data.size)} carriers, got {C}")
    scheme = scheme_for(data.size) if scheme is None else scheme
    if scheme == KEYED:
        return keyed_code.encode(data, kind, key, method, C)
    gens, K = _conv(scheme)
    u = np.concatenate([data, check(key, method, kind, data)])
    c = np.asarray(_core.conv_encode(u, list(gens), K, True))
    return c[rate_match(u.size, C, len(gens))]


def decode_bits(llr: np.ndarray, n_data: int, scheme: str = TBCC) -> np.ndarray:
    """Soft Viterbi decoding of the (C,) carrier reliabilities (> 0 means 1) into the
    n_data + CHECK_BITS information bits of a convolutional scheme."""
    gens, K = _conv(scheme)
    L = info_bits(n_data)
    llr = np.asarray(llr, np.float64)
    acc = np.bincount(rate_match(L, llr.size, len(gens)), weights=llr, minlength=len(gens) * L)
    return np.asarray(_core.viterbi_decode(acc, list(gens), K, L, True, wrap_depth(K)))


def decode(llr: np.ndarray, n_data: int, kind: str, key: str, method: str,
           scheme: str | None = None) -> tuple[UInt8Array | None, str]:
    """(data bits or None, reason): the decoded data if it is accepted (convolutional schemes: its keyed
    check matches; KEYED: the maximum-likelihood word passes the 1e-6 threshold)."""
    llr = np.asarray(llr, np.float64)
    if llr.size < min_carriers(n_data):
        return None, f"{llr.size} carriers cannot hold {n_data} payload bits"
    scheme = scheme_for(n_data) if scheme is None else scheme
    if scheme == KEYED:
        return keyed_code.decode(llr, n_data, kind, key, method)
    u = decode_bits(llr, n_data, scheme)
    data, chk = u[:n_data], u[n_data:]
    if not np.array_equal(check(key, method, kind, data), chk):
        return None, "check mismatch (too many carrier errors to decode the message)"
    return data, ""
