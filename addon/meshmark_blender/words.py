"""Figures in an artist's words (bpy-free).

The core reports probabilities and rates ("P(false alarm) 3.3e-23", "score 0.36"); the panel says what
they mean: how likely an unmarked mesh would read like this, how sure a detector is. Every function
returns a short phrase that fits a sidebar line.
"""
from __future__ import annotations

import math

_BIG = [(1e-18, "a billion billion"), (1e-15, "a million billion"), (1e-12, "a trillion"), (1e-9, "a billion"),
        (1e-6, "a million"), (1e-3, "a thousand")]


def chance(p: float) -> str:
    """A probability as words: ``3.3e-23`` -> "less than 1 in a billion billion", ``0.004`` ->
    "about 1 in 250", ``0.3`` -> "30 %"."""
    p = float(p)
    if not math.isfinite(p) or p >= 0.05:
        return f"{100 * min(max(p, 0.0), 1.0):.0f} %" if math.isfinite(p) else "unknown"
    if p <= 0.0:
        return "none"
    for limit, name in _BIG:
        if p < limit:
            return f"less than 1 in {name}"
    return f"about 1 in {int(round(1 / p)):,}"


def false_alarm(p: float) -> str:
    """What ``p_false_alarm`` means for a verdict: how often an unmarked mesh would read like this."""
    return f"an unmarked mesh reads like this: {chance(p)}"


def bits_matching(cdr: float) -> str:
    return f"Bits matching {100 * cdr:.0f}%" if cdr < 0.995 or cdr == 1.0 else f"Bits matching {100 * cdr:.1f}%"


def percent(x: float) -> str:
    return f"{100 * x:.0f} %"


def score(p: float) -> str:
    """A detector's score (0..1) as words."""
    if p >= 0.9:
        return "very high"
    if p >= 0.7:
        return "high"
    if p >= 0.4:
        return "middling"
    if p >= 0.15:
        return "low"
    return "very low"


def plural(n: int, one: str, many: str | None = None) -> str:
    return f"{n} {one if n == 1 else (many or one + 's')}"


def names(items, limit: int = 3) -> str:
    """``['A', 'B', 'C', 'D']`` -> "A, B, C and 1 more"."""
    items = list(items)
    if len(items) <= limit:
        return ", ".join(items[:-1]) + (" and " if len(items) > 1 else "") + (items[-1] if items else "")
    return ", ".join(items[:limit]) + f" and {len(items) - limit} more"
