"""Known answers for what must not change between versions: a keyfile written today must read back
tomorrow, so the key derivations (docs/security.md) and the keyfile's integrity tag are pinned to
literal values here, and recomputed from their documented definitions with hashlib / hmac."""
import hashlib
import hmac
import json

import numpy as np

from meshmark.watermark import keyfile, keys


def test_carrier_permutation_and_whitening_are_shake256_of_the_documented_labels():
    # the literal values: a change of label, hash or byte order changes them
    assert keys.permutation("s3cret", "laplacian", 12).tolist() == [2, 8, 10, 6, 4, 5, 9, 0, 1, 11, 7, 3]
    assert keys.whitening("s3cret", "laplacian", 16).tolist() == [1, 0, 0, 1, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 1]
    # the module docstring's definitions, recomputed
    words = np.frombuffer(hashlib.shake_256(b"meshmark/v1/laplacian/perm/s3cret").digest(8 * 12), "<u8")
    np.testing.assert_array_equal(keys.permutation("s3cret", "laplacian", 12), np.argsort(words, kind="stable"))
    raw = np.frombuffer(hashlib.shake_256(b"meshmark/v1/radial/white/k").digest(5), np.uint8)
    np.testing.assert_array_equal(keys.whitening("k", "radial", 40), np.unpackbits(raw))
    # another method's stream is another permutation (domain separation)
    assert keys.permutation("s3cret", "radial", 12).tolist() != keys.permutation("s3cret", "laplacian", 12).tolist()


def test_key_bins_known_answers():
    assert (keys.key_bins("s3cret", "laplacian", 400), keys.key_bins("other", "radial", 400)) == (379, 444)  # 400 moved by 3-12 % of K, down or up


def test_keyfile_tag_is_hmac_sha256_of_the_canonical_json():
    d = {"format": "meshmark-keyfile", "version": 3, "method": "laplacian", "n": [1, 2.5, "x"], "tag": "ignored"}
    assert keyfile.keyfile_tag(d, "s3cret") == "8e5f5857ee1c501cfa4da0e97ab4ed0b122cc9218fc9f64c535861f923124056"
    body = json.dumps({k: v for k, v in d.items() if k != "tag"}, sort_keys=True, separators=(",", ":")).encode()
    want = hmac.new(b"s3cret", b"meshmark-keyfile-tag/v1\0" + body, hashlib.sha256).hexdigest()
    assert keyfile.keyfile_tag(d, "s3cret") == want
    assert keyfile.keyfile_tag(dict(d, tag="other"), "s3cret") == want  # the tag field itself is not covered
    assert keyfile.keyfile_tag(dict(d, version=2), "s3cret") != want
