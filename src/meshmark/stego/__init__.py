"""Steganography in the vertex coordinates (thesis ch. 4 §4.3.2) and the Chao et al. 2009 baseline.

* :func:`embed` / :func:`extract` / :func:`capacity` — adaptive high-capacity LSB hiding under a
  normal-degradation budget, blind and permutation invariant, encrypted and authenticated;
* :mod:`meshmark.stego.chao` — Chao, Lin, Yu and Lee's multi-layer PCA-interval method (TVCG 2009).

Design notes and measurements: ``docs/stego.md``.
"""
from .lsb import NO_MESSAGE, PRECISIONS, TOO_SMALL, EmbedResult, ExtractResult, capacity, embed, extract, level_function
from . import chao

__all__ = ["NO_MESSAGE", "TOO_SMALL", "PRECISIONS", "EmbedResult", "ExtractResult", "capacity", "embed", "extract", "level_function", "chao"]
