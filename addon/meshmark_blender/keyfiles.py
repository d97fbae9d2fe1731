"""Which keyfile belongs to which object: one keyfile per object (or per character) by default.

The default keyfile of an object is ``//<object>.meshmark.json`` beside the .blend (for a character
taken as one carrier, ``//<shared name>.meshmark.json``, e.g. ``Knight`` for ``Knight_Body``,
``Knight_Head``, ...). Embed writes there unless another path is chosen, so marking HeroA and then
HeroB gives two keyfiles. The path used is remembered twice: on the objects (``Object.meshmark_keyfile``,
a path saved with the .blend; never the key) and in the session (:data:`session.KEYFILES`, which undo
does not roll back), so the Keyfile field keeps showing the object's keyfile after Ctrl+Z.
"""
from __future__ import annotations

import os

import bpy

from meshmark import MeshError

from . import session, words

PROP = "meshmark_keyfile"
SUFFIX = ".meshmark.json"


def abspath(path: str) -> str | None:
    """Absolute form of a panel path: ``~`` expanded, ``//`` relative to the .blend; None when the path
    is relative to the .blend and the .blend has not been saved yet (no folder to put it in)."""
    if not path:
        return ""
    path = os.path.expanduser(path)
    if path.startswith("//"):
        if not bpy.data.filepath:
            return None
        path = bpy.path.abspath(path)
    return os.path.abspath(path)


def resolve(path: str, what: str = "keyfile") -> str:
    """:func:`abspath`, with a MeshError in words when it cannot be resolved."""
    p = abspath(path)
    if p is None:
        raise MeshError(f"the .blend is not saved yet, so the {what} '{path}' has no folder: save the .blend "
                        f"first, or choose the {what} with a full path")
    return p


def _blend() -> str:
    return bpy.data.filepath or ""


def shared_name(names) -> str:
    """A file name for objects marked together: their common prefix (``Knight`` for ``Knight_Body``
    and ``Knight_Head``) if it has 3 letters or more, else the first name."""
    names = list(names)
    prefix = os.path.commonprefix(names).rstrip("_.- ")
    return bpy.path.clean_name(prefix if len(names) > 1 and len(prefix) >= 3 else names[0])


def default_path(names) -> str:
    return "//" + shared_name(names) + SUFFIX


def of_object(obj) -> str:
    """The keyfile remembered for ``obj`` (this session first, then the path saved on it), or ""."""
    return session.KEYFILES.get((_blend(), obj.name)) or getattr(obj, PROP, "") or ""


def for_objects(objects) -> str:
    """The keyfile of a set of objects: the one they all share, else the default for them."""
    paths = {of_object(o) for o in objects}
    if len(paths) == 1 and "" not in paths:
        return paths.pop()
    return default_path([o.name for o in objects])


def remember(objects, path: str, on_objects: bool = True) -> None:
    """Remember ``path`` as the keyfile of ``objects`` (session; and on the objects if ``on_objects``)."""
    for o in objects:
        session.KEYFILES[(_blend(), o.name)] = path
        if on_objects:
            try:
                setattr(o, PROP, path)
            except (AttributeError, RuntimeError):  # a restricted context or a linked object
                pass


def display(path: str) -> str:
    """``path`` as the panel shows it: relative to the .blend when it is beside it."""
    if bpy.data.filepath and path and not path.startswith("//"):
        try:
            return bpy.path.relpath(path)
        except ValueError:  # another drive (Windows)
            return path
    return path


def what_is_lost(path: str, key: str | None = None) -> list:
    """Lines saying what replacing the keyfile at ``path`` loses (read from the file itself)."""
    from meshmark.watermark import load_keyfile
    from meshmark.watermark.keyfile import KeyRequired
    name = os.path.basename(path)
    try:
        try:
            kf = load_keyfile(path)
        except KeyRequired:
            kf = load_keyfile(path, key=key) if key else None
    except MeshError:
        return [f"'{name}' exists but meshmark cannot read it.", "Replacing it deletes it."]
    if kf is None:
        return [f"'{name}' holds the key to a mark (its key is not stored in it).",
                "Without this file that mark can no longer be read."]
    from . import targets
    parts = [p["object"] for p in targets.recorded_parts(kf)]
    whose = f"the mark in {words.names(parts)}" if parts else "a mark"
    msg = ""
    if kf.payload.get("kind") == "text":
        from meshmark.watermark.payload import Payload
        msg = f" (message '{Payload('text', Payload.from_bits(kf.payload['bits']).data).message()}')"
    return [f"'{name}' holds {whose}{msg}.", "Without it that mark can no longer be read:",
            "save a copy first (Keyfile > Save) to keep it."]
