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
"""
from __future__ import annotations

import os
import struct

from cryptography.exceptions import InvalidTag
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
    if len(head) < HEADER:
        return None
    salt, nonce, ct = head[:SALT], head[SALT:SALT + NONCE], head[SALT + NONCE:HEADER]
    dkey = derive(key, salt)
    try:
        n = struct.unpack(">I", AESGCM(dkey).decrypt(nonce, ct, AAD))[0]
    except InvalidTag:
        return None
    return n, dkey


def open_body(frame: bytes, n: int, dkey: bytes) -> bytes | None:
    """The message from a whole frame (HEADER + n + TAG bytes), or None if it does not authenticate."""
    if len(frame) < HEADER + n + TAG:
        return None
    nonce = frame[SALT:SALT + NONCE]
    try:
        return AESGCM(dkey).decrypt(_nonce2(nonce), frame[HEADER:HEADER + n + TAG], AAD)
    except InvalidTag:
        return None
