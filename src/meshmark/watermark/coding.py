"""Channel coding of the payload: a keyed check and a tail-biting convolutional code, soft-decoded.

A payload of k data bits becomes ``k + CHECK_BITS`` information bits::

    [ data: k bits ][ check: 20 bits = HMAC-SHA256(key, method, kind, data) truncated ]

and is encoded with the rate-1/3, constraint-length-7 convolutional code of LTE (generators 133, 171,
165 octal; 3GPP TS 36.212 §5.1.3.1), tail-biting (no tail bits: 3 (k + 20) code bits). The code bits
are then *rate-matched* to the C carriers the mesh offers (:func:`rate_match`): in priority order
(all of generator 0, then generators 1 and 2 each in a low-discrepancy order of positions) and
cyclically repeated when C > 3 (k + 20), punctured when C < 3 (k + 20) (at least
:func:`min_carriers` = 1.5 (k + 20) carriers, rate 2/3). Decoding sums the carriers' signed
reliabilities per code bit and runs a soft Viterbi decoder (native, wrap-around for tail-biting,
``meshmark._core.viterbi_decode``); the message is accepted only if the recomputed check matches.

Nothing is framed that the keyfile already knows: the data length k is in the keyfile.

Why 20 check bits: a wrong message needs a decoding error *and* a check collision; the check is a
keyed MAC, so a collision has probability 2^-20 = 9.5e-7 whatever the error pattern, and a wrong
message is rarer than 1e-6 per attempt even if every decoding failed. The framework also never
returns a message without a detection (p_false_alarm < 1e-6). docs/coding.md has the measured curve
beside the old repetition code.
"""
from __future__ import annotations

import hashlib
import hmac
import math

import numpy as np

from .. import _core
from .._core import MeshError

SCHEME = "tbcc7-r13-mac20"
GENERATORS = (0o133, 0o171, 0o165)
CONSTRAINT = 7
CHECK_BITS = 20
MIN_RATE_DEN = 1.5  # at least 1.5 carriers per information bit (punctured rate 2/3)
WRAP = 6 * (CONSTRAINT - 1) + 6  # wrap-around depth of the tail-biting decoder (steps)
_PHI = (math.sqrt(5.0) - 1.0) / 2.0


def info_bits(n_data: int) -> int:
    return int(n_data) + CHECK_BITS


def min_carriers(n_data: int) -> int:
    """Fewest carriers that take a payload of ``n_data`` bits (punctured rate 2/3)."""
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


def rate_match(L: int, C: int) -> np.ndarray:
    """(C,) index into the 3L interleaved code bits (c[3t + j]) carried by each of the C carriers."""
    n = len(GENERATORS)
    order = np.concatenate([np.arange(L) * n] + [_spread(L) * n + j for j in range(1, n)])
    return order[np.arange(C) % order.size]


def encode(data: np.ndarray, kind: str, key: str, method: str, C: int) -> np.ndarray:
    """(C,) coded bits (0/1) carrying ``data`` with its keyed check."""
    data = np.asarray(data, np.uint8)
    if C < min_carriers(data.size):
        raise MeshError(f"{data.size} payload bits need at least {min_carriers(data.size)} carriers, got {C}")
    u = np.concatenate([data, check(key, method, kind, data)])
    c = np.asarray(_core.conv_encode(u, list(GENERATORS), CONSTRAINT, True))
    return c[rate_match(u.size, C)]


def decode_bits(llr: np.ndarray, n_data: int) -> np.ndarray:
    """Soft Viterbi decoding of the (C,) carrier reliabilities (> 0 means 1) into the
    n_data + CHECK_BITS information bits."""
    L = info_bits(n_data)
    llr = np.asarray(llr, np.float64)
    acc = np.bincount(rate_match(L, llr.size), weights=llr, minlength=len(GENERATORS) * L)
    return np.asarray(_core.viterbi_decode(acc, list(GENERATORS), CONSTRAINT, L, True, WRAP))


def decode(llr: np.ndarray, n_data: int, kind: str, key: str, method: str):
    """(data bits or None, reason): the decoded data if its keyed check matches."""
    if llr.size < min_carriers(n_data):
        return None, f"{llr.size} carriers cannot hold {n_data} payload bits"
    u = decode_bits(llr, n_data)
    data, chk = u[:n_data], u[n_data:]
    if not np.array_equal(check(key, method, kind, data), chk):
        return None, "check mismatch (too many carrier errors to decode the message)"
    return data, ""
