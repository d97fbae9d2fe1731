"""Watermarking: methods, and the framework they share.

* :mod:`~meshmark.watermark.laplacian` — thesis ch. 7, Laplacian-coordinate histogram (robust to
  skeletal deformation);
* :mod:`~meshmark.watermark.cho` — Cho et al.'s vertex-norm mean and variance methods (``cho-mean``,
  ``cho-variance``; thesis §2.2.2, ch. 6);
* :mod:`~meshmark.watermark.radial` — Yang's radial histogram with a PCA origin (``radial``; §6.1-6.2);
* :mod:`~meshmark.watermark.payload` — framing (length, CRC-8) and repetition coding of messages;
* :mod:`~meshmark.watermark.keys` — key-derived permutation and whitening of the carriers;
* :mod:`~meshmark.watermark.keyfile` — the versioned JSON keyfile that ``extract`` needs;
* :mod:`~meshmark.watermark.framework` — embed/extract/detect for any method.

Generic entry points: :func:`embed`, :func:`extract`, :func:`capacity` with ``method=`` one of
:data:`METHODS`.
"""
from .framework import METHODS, embed, extract, capacity, EmbedResult, ExtractResult
from .keyfile import Keyfile, load_keyfile, save_keyfile
from . import laplacian, cho, radial

__all__ = ["METHODS", "embed", "extract", "capacity", "EmbedResult", "ExtractResult", "Keyfile",
           "load_keyfile", "save_keyfile", "laplacian", "cho", "radial"]
