"""Watermarking: methods, and the framework they share.

* :mod:`~meshmark.watermark.laplacian` — thesis ch. 7, Laplacian-coordinate histogram (robust to
  skeletal deformation);
* :mod:`~meshmark.watermark.cho` — Cho et al.'s vertex-norm mean and variance methods (``cho-mean``,
  ``cho-variance``; thesis §2.2.2, ch. 6);
* :mod:`~meshmark.watermark.radial` — Yang's radial histogram with a PCA origin (``radial``; §6.1-6.2);
* :mod:`~meshmark.watermark.coding` — the payload's keyed check and tail-biting convolutional code,
  soft-decoded (docs/coding.md); :mod:`~meshmark.watermark.payload` — the message as bits (and the
  earlier length/CRC-8/repetition framing, still read);
* :mod:`~meshmark.watermark.auto` — automatic parameters (``params="auto"``);
* :mod:`~meshmark.watermark.tracing` — copy tracing: ``issue`` / ``trace`` with a SQLite registry;
* :mod:`~meshmark.watermark.keys` — key-derived permutation and whitening of the carriers;
* :mod:`~meshmark.watermark.keyfile` — the versioned JSON keyfile that ``extract`` needs;
* :mod:`~meshmark.watermark.framework` — embed/extract/detect for any method;
* :mod:`~meshmark.watermark.methods` — the methods by name (:data:`METHODS`), below the keyfile and the
  framework.

Generic entry points: :func:`embed`, :func:`extract`, :func:`capacity` with ``method=`` one of
:data:`METHODS`.
"""
from .framework import METHODS, embed, extract, capacity, EmbedResult, ExtractResult
from .keyfile import Keyfile, load_keyfile, save_keyfile
from . import laplacian, cho, radial
from . import auto, coding, tracing

__all__ = ["METHODS", "embed", "extract", "capacity", "EmbedResult", "ExtractResult", "Keyfile",
           "load_keyfile", "save_keyfile", "laplacian", "cho", "radial", "auto", "coding", "tracing"]
