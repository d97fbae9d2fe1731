"""The one JSON writer of every ``--json`` output (docs/json.md).

JSON has no Infinity or NaN, so :func:`dumps` never writes them: a non-finite number becomes
``null`` and the dict field that held it (directly or anywhere inside a list or nested value) gets a
sibling ``"<field>_reason"`` saying what it was, e.g. ``"bbox_min": [null, 0.0, 1.5],
"bbox_min_reason": "not finite: [0] -inf"``. numpy scalars and arrays are written as numbers and
lists. The result always passes ``json.loads`` of a strict parser.

Every command's ``--json`` object goes through :func:`emit` (success: ``"ok": true`` first) or, from
meshmark.cli's one error handler, :func:`error_object` (``"ok": false`` and an ``error`` object). The
vocabulary and the schemas are in docs/json.md and docs/schemas/.
"""
from __future__ import annotations

import json
import math
import numbers

import click

_MAX_SHOWN = 8  # positions named in one reason; the rest are counted


def _fmt(x: float) -> str:
    return "nan" if math.isnan(x) else ("inf" if x > 0 else "-inf")


def _clean(x, where: str, bad: list):
    """``x`` with non-finite floats replaced by None; their positions (relative to the field) and
    values appended to ``bad``."""
    if isinstance(x, dict):
        return _clean_dict(x)
    if isinstance(x, (list, tuple)):
        return [_clean(v, f"{where}[{i}]", bad) for i, v in enumerate(x)]
    if hasattr(x, "tolist") and hasattr(x, "dtype"):  # numpy array or scalar
        return _clean(x.tolist(), where, bad)
    if isinstance(x, bool) or x is None or isinstance(x, str):
        return x
    if isinstance(x, numbers.Integral):
        return int(x)
    if isinstance(x, numbers.Real):
        f = float(x)
        if math.isfinite(f):
            return f
        bad.append(f"{where} {_fmt(f)}".strip())
        return None
    return x


def _clean_dict(d: dict) -> dict:
    out = {}
    for k, v in d.items():
        bad: list = []
        out[k] = _clean(v, "", bad)
        if bad:
            shown = ", ".join(bad[:_MAX_SHOWN]) + (f" and {len(bad) - _MAX_SHOWN} more" if len(bad) > _MAX_SHOWN else "")
            out[f"{k}_reason"] = f"not finite: {shown}"
    return out


def sanitize(obj):
    """``obj`` as plain JSON values: non-finite floats -> null plus ``<field>_reason`` (see above)."""
    bad: list = []
    out = _clean(obj, "", bad)
    if bad and not isinstance(obj, dict):  # a bare non-finite value or list: wrap to keep the reason
        return {"value": out, "value_reason": "not finite: " + ", ".join(bad[:_MAX_SHOWN])}
    return out


def dumps(obj, indent: int | None = 2) -> str:
    """Strict JSON text of ``obj`` (``allow_nan=False`` after :func:`sanitize`)."""
    return json.dumps(sanitize(obj), indent=indent, allow_nan=False, default=str)


def option(help: str = "Print the result as JSON."):
    """The ``--json`` flag of a command (parameter ``as_json``). Eager, so that the error handler of
    meshmark.cli knows the mode even when a later option fails to convert."""
    def remember(ctx, param, value):
        ctx.meta["meshmark.json"] = bool(value)
        return value
    return click.option("--json", "as_json", is_flag=True, is_eager=True, callback=remember, help=help)


def safe(text) -> str:
    """``text`` printable as UTF-8: bytes from argv that are not UTF-8 (surrogate escapes) are shown
    as \\xNN instead of failing to print."""
    text = str(text)
    try:
        return text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")
    except UnicodeEncodeError:
        return text.encode("utf-8", "backslashreplace").decode("utf-8")


def result(d: dict, aliases: dict | None = None) -> dict:
    """The ``--json`` object of a command that ran: ``"ok": true``, then ``d``. ``aliases`` maps an
    old key name to the vocabulary's name (docs/json.md): the value of ``d[new]`` is written under the
    old name too, for one release, and ``"deprecated"`` lists ``{old: new}``."""
    out = {"ok": True, **d}
    if aliases:
        for old, new in aliases.items():
            out[old] = d.get(new)
        out["deprecated"] = dict(aliases)
    return out


def error_object(code: int, kind: str, message: str) -> dict:
    """The ``--json`` object of a command that failed (exit status ``code``: 2 bad input or usage,
    3 internal error, 130 interrupted); ``kind`` is "input", "usage", "internal" or "interrupted"."""
    return {"ok": False, "error": {"code": int(code), "kind": kind, "message": safe(message)}}


def emit(d: dict, as_json: bool, text: str, aliases: dict | None = None, indent: int | None = 2) -> None:
    """Print :func:`result` of ``d`` as JSON with ``as_json``, else ``text`` (every command)."""
    click.echo(dumps(result(d, aliases), indent=indent) if as_json else safe(text))

