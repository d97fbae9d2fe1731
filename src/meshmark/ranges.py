"""Documented ranges of every numeric parameter, checked in the core (each method's ``resolve``).

A value outside its range, of the wrong type (``K=4.5``, ``thesis_exact='no'``) or not finite is a
:class:`ParameterError`, a MeshError that carries the parameter's name so the CLI can name its option
(``--n-robust``). The ranges (inclusive unless marked open):

============== ============================ ==========================================================
parameter      range                        why the bound
============== ============================ ==========================================================
K              4 .. 1,048,576 bins          the histogram is allocated per bin; the Cho and radial
                                            methods also need K <= referenced vertices
n_thr          1 .. 1,000,000,000           a count of elements (32-bit in the native code)
n_robust       1 .. 1,000,000,000           eq. 7.2.16 margin divisor (32-bit)
eps            (0, 1]                       eq. 7.1.4 regularisation
alpha          (0, 0.5) mean, (0, 1/3) var  Cho et al.'s strength factor
delta_k        (0, 1)                       step of the exponent k
guard          [0, 0.25)                    fraction of a bin kept free at its ends
center_iters   0 .. 1,000                   each round re-runs the whole embedding
origin_iters   0 .. 1,000                   each round re-runs the whole embedding
thesis_exact   True / False                 a flag; strings such as 'no' are refused
weld           True / False                 a flag
============== ============================ ==========================================================
"""
from __future__ import annotations

import math
import numbers

from ._core import MeshError

MAX_K = 1 << 20
MAX_COUNT = 1_000_000_000
MAX_ITERS = 1_000

RANGES = {  # name -> (low, high) for integers, documented above
    "K": (4, MAX_K),
    "n_thr": (1, MAX_COUNT),
    "n_robust": (1, MAX_COUNT),
    "center_iters": (0, MAX_ITERS),
    "origin_iters": (0, MAX_ITERS),
}

MAX_SEED = 2 ** 63 - 1  # numpy generators take any non-negative int; 63 bits fit every binding


def check_seed(value, name: str = "seed") -> int:
    """A random seed: an integer in 0 .. 2^63 - 1."""
    return check_int(name, value, 0, MAX_SEED)


UNITS = {"K": " bins", "center_iters": " rounds", "origin_iters": " rounds"}


class ParameterError(MeshError):
    """A parameter outside its documented range; ``param`` is its API name."""

    def __init__(self, param: str, message: str):
        super().__init__(message)
        self.param = param


def check_int(name: str, value, low: int | None = None, high: int | None = None, note: str = "") -> int:
    """``value`` as an int in [low, high] (defaults from :data:`RANGES`); integral floats are accepted."""
    if low is None and high is None:
        low, high = RANGES[name]
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, f"{name} must be an integer in {low}..{high}, got {value!r}")
    if isinstance(value, numbers.Integral):
        v = int(value)
    else:
        f = float(value)
        if not math.isfinite(f) or f != int(f):
            raise ParameterError(name, f"{name} must be an integer in {low}..{high}, got {value!r}")
        v = int(f)
    unit = UNITS.get(name, "")
    if v < low:
        raise ParameterError(name, f"{name} must be at least {low}{unit}, got {v}{note} (range {low}..{high})")
    if v > high:
        raise ParameterError(name, f"{name} must be at most {high}{unit}, got {v}{note} (range {low}..{high})")
    return v


def check_float(name: str, value, low: float, high: float, *, low_open: bool = False, high_open: bool = False) -> float:
    """``value`` as a finite float in the interval (open ends as marked)."""
    lo_b, hi_b = "(" if low_open else "[", ")" if high_open else "]"
    span = f"{lo_b}{low:g}, {high:g}{hi_b}"
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ParameterError(name, f"{name} must be a number in {span}, got {value!r}")
    v = float(value)
    ok = math.isfinite(v) and (v > low if low_open else v >= low) and (v < high if high_open else v <= high)
    if not ok:
        raise ParameterError(name, f"{name} must be in {span}, got {value!r}")
    return v


def check_bool(name: str, value) -> bool:
    """``value`` as a bool: True/False (numpy booleans too); anything else, 'no' or 1 included, is refused."""
    if isinstance(value, bool):
        return value
    try:
        import numpy as np
        if isinstance(value, np.bool_):
            return bool(value)
    except ImportError:  # pragma: no cover
        pass
    raise ParameterError(name, f"{name} must be True or False, got {value!r}")


def check_text(name: str, value: str) -> str:
    """A str that encodes as UTF-8: command-line bytes that are not UTF-8 arrive as surrogate
    escapes, and are refused with the bytes shown."""
    try:
        value.encode("utf-8")
    except UnicodeEncodeError:
        shown = value.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
        raise ParameterError(name, f"the {name} is not valid UTF-8: '{shown}'") from None
    return value


# The Laplacian carrier names (``laplacian.CARRIERS`` maps each to its native kind; kept here so that
# the keyfile schema can check a carrier without importing the method).
LAPLACIAN_CARRIERS = ("thesis", "local", "normal", "cot_local", "cot_normal", "normal_global")
