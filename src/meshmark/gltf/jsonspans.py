"""Byte spans inside a glTF JSON text, so that the writer can replace a few values (an accessor's
``min``/``max``, a buffer's ``uri``) and leave every other byte, key order, spacing and number
spelling included, exactly as it was.

The scan matches only strings and brackets (numbers, literals, commas and colons are skipped by the
regular expression, so long number arrays cost nothing) and is run on text that ``json.loads`` has
already accepted. Duplicate keys resolve as in ``json.loads``: the last one wins.
"""
from __future__ import annotations

import re

_TOKENS = re.compile(rb'"(?:[^"\\]|\\.)*"|[{}\[\]]')
_COLON = re.compile(rb"\s*:")


def max_depth(text: bytes) -> int:
    """The deepest nesting of ``{``/``[`` in ``text`` (brackets inside strings skipped)."""
    depth = best = 0
    for m in _TOKENS.finditer(text):
        c = m.group()[0]
        if c in b"{[":
            depth += 1
            best = max(best, depth)
        elif c in b"}]":
            depth -= 1
    return best


def find_spans(text: bytes, tops=("accessors", "buffers", "images"), keys=("min", "max", "uri")) -> dict:
    """Spans ``(start, end)`` of:

    * ``(top, i)``: the i-th object of the top-level array ``top`` (its braces included);
    * ``(top, i, key)``: the value of ``key`` in that object (an array with its brackets, or a string
      with its quotes).
    """
    spans: dict = {}
    # stack entries: [kind, start, path, pending key (objects) / child count (arrays)]
    stack: list = []
    pending_key = None
    for m in _TOKENS.finditer(text):
        tok = m.group()
        c = tok[0]
        if c == 0x22:  # a string: a key (followed by ':') or a value
            if stack and stack[-1][0] == "o" and _COLON.match(text, m.end()):
                pending_key = tok[1:-1].decode("utf-8", "replace")
                continue
            if stack and stack[-1][0] == "o" and pending_key is not None:
                path = stack[-1][2] + (pending_key,)
                if len(path) == 3 and path[0] in tops and path[2] in keys:
                    spans[path] = (m.start(), m.end())
            pending_key = None
            continue
        if c in b"{[":
            if not stack:
                path = ()
            elif stack[-1][0] == "o":
                path = stack[-1][2] + (pending_key,)
            else:
                path = stack[-1][2] + (stack[-1][3],)
                stack[-1][3] += 1
            stack.append(["o" if c == 0x7B else "a", m.start(), path, 0])
            pending_key = None
            continue
        kind, start, path, _ = stack.pop()
        pending_key = None
        if path and path[0] in tops and (len(path) == 2 or (len(path) == 3 and path[2] in keys)):
            spans[path] = (start, m.end())
    return spans
