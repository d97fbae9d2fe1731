"""Writing files so that a failure leaves nothing behind: each file is written to a temporary name in
its own folder and renamed over the target only when every file of the group has been written.

``write_all([(path, writer), ...])`` is what ``meshmark embed`` uses for the marked mesh and its
keyfile together: both folders are checked before any work is done (a missing keyfile folder is an
error before OUT is written), both files are written to temporary names, and only then renamed.
"""
from __future__ import annotations

import os
import secrets

from ._core import MeshError


def _shown(path) -> str:
    return os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def check_writable(path, what: str = "file") -> None:
    """MeshError unless ``path`` can be created: its folder exists and is writable, and it is not a folder."""
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.isdir(path):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': it is a folder")
    if not os.path.isdir(folder):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': the folder '{_shown(folder)}' does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': the folder '{_shown(folder)}' is not writable")


def temp_path(path) -> str:
    """A fresh temporary name beside ``path``, keeping its extension (the mesh writer needs it)."""
    path = os.fspath(path)
    folder, base = os.path.split(path)
    ext = os.path.splitext(base)[1]
    return os.path.join(folder, f".{base}.meshmark-tmp-{os.getpid()}-{secrets.token_hex(4)}{ext}")


def write_all(items, what=None) -> None:
    """Write every ``(path, writer)`` pair or none: ``writer(tmp_path)`` writes the content to the
    temporary path it is given; when all writers succeeded the temporaries are renamed onto their
    targets (in the order given). On any failure every temporary is removed and the error re-raised."""
    items = list(items)
    for i, (path, _) in enumerate(items):
        check_writable(path, what[i] if what else "file")
    temps = []
    try:
        for path, writer in items:
            tmp = temp_path(path)
            temps.append(tmp)
            writer(tmp)
        for (path, _), tmp in zip(items, temps):
            os.replace(tmp, path)
    except OSError as exc:
        raise MeshError(f"cannot write '{_shown(exc.filename or '')}': {exc.strerror or exc}") from None
    finally:
        for tmp in temps:
            if os.path.exists(tmp):
                os.remove(tmp)


def write_text(path, text: str) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically: a temporary file, fsync, then a rename."""
    path = os.fspath(path)
    tmp = temp_path(path)
    try:
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except OSError as exc:
        raise MeshError(f"cannot write '{_shown(path)}': {exc.strerror or exc}") from None
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
