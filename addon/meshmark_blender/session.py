"""What the add-on keeps for this Blender session only (bpy-free).

Nothing here is written into the .blend (or its autosave, which is a copy of the undo memory), and
Ctrl+Z does not touch it, because none of it is Blender ID data: the panel's fields that hold secrets
or session state (Key, the text to hide, the result of the last operator, the keyfile chosen for an
object) are properties with a getter and a setter that read and write these dicts (properties.py).

* :data:`KEY`: the secret key typed in the panel (one per session).
* :data:`TEXT`: texts typed in the panel that must not reach the file (the text to hide).
* :data:`RESULT`: the last operator's result as JSON (a revealed text, figures).
* :data:`KEYFILES`: ``(blend file, object name) -> keyfile path`` chosen or written in this session; it
  wins over the path recorded on the object (which undo may roll back) and over the default
  ``//<object>.meshmark.json``.
* :data:`LAST`: the keyfile of the last Embed (for "Save keyfile").
* :data:`CACHE`: computed panel figures (capacity, the automatic choice) by signature.
* :data:`JOB`: the running modal job (one at a time), for the panel and the tests.
"""
from __future__ import annotations

KEY = {"value": ""}
TEXT: dict = {}
RESULT = {"json": ""}
KEYFILES: dict = {}
LAST = {"keyfile": None}
CACHE: dict = {}
JOB = {"running": None}
CACHE_MAX = 64


def remember(key, value):
    """Put ``value`` in :data:`CACHE` under ``key`` (the oldest entries go beyond CACHE_MAX)."""
    if len(CACHE) >= CACHE_MAX:
        for k in list(CACHE)[: len(CACHE) - CACHE_MAX + 1]:
            del CACHE[k]
    CACHE[key] = value
    return value


def forget() -> None:
    """Drop everything (on unregister)."""
    KEY["value"] = ""
    TEXT.clear()
    RESULT["json"] = ""
    KEYFILES.clear()
    LAST["keyfile"] = None
    CACHE.clear()
    JOB["running"] = None
