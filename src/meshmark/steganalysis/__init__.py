"""Steganalysis: detecting that a mesh carries hidden information.

* :mod:`~meshmark.steganalysis.cho` — the specific steganalyzer against Cho et al.'s mean method
  (thesis §6.4).
"""
from . import cho

__all__ = ["cho"]
