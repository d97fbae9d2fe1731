"""Payload framing and error correction.

A message (UTF-8 text, or a raw bit string) becomes a *frame*::

    [ length: 8 bits ][ data: length bits ][ CRC-8 over length and data ]

``length`` counts data bits (1..255), so a text message carries at most 31 bytes. The CRC is CRC-8
with polynomial 0x07 (CRC-8/SMBUS). The frame is then repeated to fill every carrier the mesh offers
(a repetition code, decoded by majority vote with soft tie-breaking): with capacity C and frame length
L, frame bit i is carried ``ceil`` or ``floor`` of C / L times. Extraction returns the exact message
only when the CRC and the length agree.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core import MeshError

HEADER_BITS = 8
CRC_BITS = 8
OVERHEAD_BITS = HEADER_BITS + CRC_BITS
MAX_DATA_BITS = 255


def crc8(bits: np.ndarray) -> np.ndarray:
    """CRC-8 (poly x^8 + x^2 + x + 1, init 0) of a 0/1 bit array, as 8 bits MSB first."""
    reg = 0
    for b in bits.astype(np.uint8).tolist():  # frames are at most 271 bits
        top = ((reg >> 7) & 1) ^ b
        reg = (reg << 1) & 0xFF
        if top:
            reg ^= 0x07
    return np.array([(reg >> (7 - i)) & 1 for i in range(8)], np.uint8)


@dataclass(frozen=True)
class Payload:
    """A message as bits. ``kind`` is ``"text"`` (UTF-8) or ``"bits"``."""
    kind: str
    data: np.ndarray  # (n,) uint8 0/1

    @classmethod
    def from_text(cls, text: str) -> "Payload":
        if not isinstance(text, str) or text == "":
            raise MeshError("the message must be a non-empty string")
        from ..ranges import check_text
        raw = np.frombuffer(check_text("message", text).encode("utf-8"), np.uint8)
        bits = np.unpackbits(raw)
        if bits.size > MAX_DATA_BITS:
            raise MeshError(f"the message is {raw.size} bytes ({bits.size} bits); at most {MAX_DATA_BITS // 8} bytes fit a frame")
        return cls("text", bits)

    @classmethod
    def from_bits(cls, bits) -> "Payload":
        if isinstance(bits, str):
            s = bits.strip()
            if not s or set(s) - {"0", "1"}:
                raise MeshError(f"a bit string holds only 0 and 1, got {bits!r}")
            arr = np.frombuffer(s.encode(), np.uint8) - ord("0")
        else:
            arr = np.asarray(bits)
            if arr.ndim != 1 or arr.size == 0 or not np.isin(arr, (0, 1)).all():
                raise MeshError("bits must be a non-empty 1-D sequence of 0 and 1")
            arr = arr.astype(np.uint8)
        if arr.size > MAX_DATA_BITS:
            raise MeshError(f"{arr.size} bits given; at most {MAX_DATA_BITS} fit a frame")
        return cls("bits", arr)

    @classmethod
    def coerce(cls, payload) -> "Payload":
        """A Payload from a Payload, a text str, or a bit sequence (numpy/list of 0/1)."""
        if isinstance(payload, Payload):
            return payload
        if isinstance(payload, str):
            return cls.from_text(payload)
        return cls.from_bits(payload)

    def frame(self) -> np.ndarray:
        n = self.data.size
        header = np.array([(n >> (7 - i)) & 1 for i in range(8)], np.uint8)
        body = np.concatenate([header, self.data])
        return np.concatenate([body, crc8(body)])

    @property
    def frame_bits(self) -> int:
        return self.data.size + OVERHEAD_BITS

    def bitstring(self) -> str:
        return "".join("1" if b else "0" for b in self.data.tolist())

    def message(self):
        """The text (kind "text") or the bit string (kind "bits")."""
        if self.kind == "text":
            return np.packbits(self.data).tobytes().decode("utf-8")
        return self.bitstring()


def repeat_to(frame: np.ndarray, n: int) -> np.ndarray:
    """Repetition code: the frame repeated to exactly n bits (n >= len(frame))."""
    return np.resize(frame, n).astype(np.uint8)


def decode(coded_bits: np.ndarray, soft: np.ndarray, frame_len: int, kind: str):
    """Majority-vote the repetitions of a frame; return (Payload or None, frame bits, reason).

    ``soft`` gives each coded bit's reliability (>= 0); ties go to the more reliable side.
    """
    n = coded_bits.size
    idx = np.arange(n) % frame_len
    signed = np.where(coded_bits > 0, 1.0, -1.0) * (1.0 + 1e-3 * np.minimum(soft, 1e3))
    votes = np.bincount(idx, weights=signed, minlength=frame_len)
    frame = (votes > 0).astype(np.uint8)
    length = int("".join(map(str, frame[:8].tolist())), 2)
    if length + OVERHEAD_BITS != frame_len:
        return None, frame, f"length field reads {length} bits, expected {frame_len - OVERHEAD_BITS}"
    body, crc = frame[: 8 + length], frame[8 + length:]
    if not np.array_equal(crc8(body), crc):
        return None, frame, "CRC mismatch"
    data = body[8:]
    try:
        p = Payload(kind, data)
        p.message()
    except UnicodeDecodeError:
        return None, frame, "the recovered bytes are not valid UTF-8"
    return p, frame, ""
