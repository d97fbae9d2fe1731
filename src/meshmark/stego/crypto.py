"""The encrypted, authenticated, length-framed payload of ``meshmark.stego``.

Frame (bytes, in the message-bit stream of the carrier)::

    salt (16) | nonce (12) | AES-256-GCM(len(message) as 4 bytes big endian) (4 + 16 tag)
              | AES-256-GCM(message, nonce + 1) (len + 16 tag)

The 256-bit key is stretched from the user's key (a passphrase, any bytes) with scrypt
(N = 2^15, r = 8, p = 1: 32 MiB and ~0.1 s per derivation, memory-hard so a GPU guesser pays per
guess). The header and the body are two AEAD messages under two nonces (nonce, nonce with its last
bit flipped) and both authenticate the associated data ``b"meshmark-stego-1"``. A wrong key, a
damaged file or a clean mesh fails the header's tag (probability of a false accept 2^-128), so the
extractor answers "no message", never garbage.

The corrective vector's stream in the LSBs is ``salt (16) | mask(len(e stream) as 4 bytes | deflate(e))``
(:func:`mask`, AES-CTR under a subkey of the derived key): the extractor reads the salt there, derives
the key once, and uses it for e and for the header. Without the key the LSBs are random bits.
"""
from __future__ import annotations

import hashlib
import hmac
import os
import struct

from cryptography.exceptions import InvalidTag
from cryptography.hazmat.primitives.ciphers import Cipher, algorithms, modes
from cryptography.hazmat.primitives.ciphers.aead import AESGCM
from cryptography.hazmat.primitives.kdf.scrypt import Scrypt

from .._core import MeshError

SALT = 16
NONCE = 12
TAG = 16
HEADER = SALT + NONCE + 4 + TAG  # bytes before the body ciphertext
OVERHEAD = HEADER + TAG          # frame bytes on top of the message
AAD = b"meshmark-stego-1"
SCRYPT_N, SCRYPT_R, SCRYPT_P = 2 ** 15, 8, 1


def key_bytes(key) -> bytes:
    """The user's key as bytes (str -> UTF-8). MeshError for an empty or missing key."""
    if isinstance(key, str):
        key = key.encode("utf-8")
    if not isinstance(key, (bytes, bytearray)) or len(key) == 0:
        raise MeshError("key must be a non-empty string or bytes")
    return bytes(key)


def derive(key, salt: bytes) -> bytes:
    """scrypt(key, salt) -> 32-byte AES key."""
    return Scrypt(salt=salt, length=32, n=SCRYPT_N, r=SCRYPT_R, p=SCRYPT_P).derive(key_bytes(key))


def _nonce2(nonce: bytes) -> bytes:
    return nonce[:-1] + bytes([nonce[-1] ^ 1])


def seal(message: bytes, dkey: bytes, salt: bytes, nonce: bytes | None = None) -> bytes:
    """The frame for ``message`` under the derived key (fresh random nonce unless given)."""
    if len(message) >= 2 ** 32:
        raise MeshError("message longer than 4 GiB")
    nonce = os.urandom(NONCE) if nonce is None else nonce
    a = AESGCM(dkey)
    head = a.encrypt(nonce, struct.pack(">I", len(message)), AAD)
    body = a.encrypt(_nonce2(nonce), bytes(message), AAD)
    return salt + nonce + head + body


def open_header(head: bytes, key) -> tuple[int, bytes] | None:
    """(message length, derived key) from the first HEADER bytes, or None (wrong key / no message)."""
    return open_header_with(head, derive(key, bytes(head[:SALT]).ljust(SALT, b"\0")))


def open_header_with(head: bytes, dkey: bytes) -> tuple[int, bytes] | None:
    """open_header with the key already derived (from the salt of the LSB stream, ``lsb.py``)."""
    short = len(head) < HEADER  # still check: the same work as for a full header
    head = bytes(head[:HEADER]).ljust(HEADER, b"\0")
    nonce, ct = head[SALT:SALT + NONCE], head[SALT + NONCE:HEADER]
    try:
        n = struct.unpack(">I", AESGCM(dkey).decrypt(nonce, ct, AAD))[0]
    except InvalidTag:
        return None
    return None if short else (n, dkey)


def mask(dkey: bytes, data: bytes) -> bytes:
    """AES-256-CTR of ``data`` (counter 0) under HMAC-SHA256(dkey, "meshmark-stego-e"): the corrective
    vector's stream in the LSBs, so that without the key it is indistinguishable from random bits.
    Its own involution (mask(k, mask(k, x)) == x); a fresh salt, hence a fresh key, per embedding."""
    k = hmac.new(dkey, b"meshmark-stego-e", hashlib.sha256).digest()
    c = Cipher(algorithms.AES(k), modes.CTR(bytes(16))).encryptor()
    return c.update(bytes(data)) + c.finalize()


def open_body(frame: bytes, n: int, dkey: bytes) -> bytes | None:
    """The message from a whole frame (HEADER + n + TAG bytes), or None if it does not authenticate."""
    if len(frame) < HEADER + n + TAG:
        return None
    nonce = frame[SALT:SALT + NONCE]
    try:
        return AESGCM(dkey).decrypt(_nonce2(nonce), frame[HEADER:HEADER + n + TAG], AAD)
    except InvalidTag:
        return None
