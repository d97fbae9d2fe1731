"""Writing files so that a failure, a signal or a kill leaves nothing half-done behind.

* Every file is written to a temporary name in its target's folder, ``.meshmark-tmp-<pid>-<hex>-<name>``,
  created private (mode 0600, ``O_CREAT|O_EXCL``) before anything is written into it, fsynced, and
  renamed over the target only when every file of the group is complete (:func:`write_all`,
  :class:`Staged`). The renames happen in the order given, each followed by an fsync of its folder:
  ``meshmark embed`` renames the keyfile first and the marked mesh last, so a marked mesh never
  stands at its path without the keyfile that reads it (after a kill between the two renames the
  old mesh stands beside the new keyfile).
* SIGINT and SIGTERM while temporaries exist remove them, then end the process by the same signal
  (exit status 130 / 143 in a shell).
* Temporaries whose process is gone (SIGKILL, power loss) are removed the next time meshmark writes
  into that folder (:func:`clean_stale`).
* :func:`create_private` creates a file 0600 whatever the umask (keyfiles, registries);
  :func:`refuse_existing` is the one "exists; pass --force" check of every command that writes.
"""
from __future__ import annotations

import os
import re
import secrets
import shutil
import signal
import threading

from ._core import MeshError

PREFIX = ".meshmark-tmp-"
# ours (.meshmark-tmp-<pid>-<hex8>...), the native writer's (.<name>.meshmark-tmp-<pid>.<ext>) and
# earlier versions' (.<name>.meshmark-tmp-<pid>-<hex8><ext>): the pid is group 1
_STALE = re.compile(r"^\.(?:.*\.)?meshmark-tmp-(\d+)(?:-[0-9a-f]{8})?(?:[-.]|$)")
PRIVATE_MODE = 0o600


def _shown(path) -> str:
    return os.fsdecode(path).encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace")


def _folder(path) -> str:
    return os.path.dirname(os.path.abspath(os.fspath(path)))


# --- private files ----------------------------------------------------------------------------------

def create_private(path) -> int:
    """Create ``path`` (it must not exist) readable and writable by its owner only (0600), whatever
    the umask, and return the open descriptor (``O_RDWR``; close it, or wrap it with ``os.fdopen``).
    FileExistsError if it exists: nothing else is ever replaced through it."""
    fd = os.open(os.fspath(path), os.O_RDWR | os.O_CREAT | os.O_EXCL | getattr(os, "O_CLOEXEC", 0), PRIVATE_MODE)
    try:
        os.fchmod(fd, PRIVATE_MODE)  # the umask may have removed bits (umask 0277 gives 0400)
    except BaseException:
        os.close(fd)
        raise
    return fd


def make_private(path) -> None:
    """chmod 0600 an existing file (one created by a library that does not take a mode)."""
    os.chmod(os.fspath(path), PRIVATE_MODE)


def _default_mode() -> int:
    """The mode ``open()`` would give a new file: 0666 minus the umask."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return 0o666 & ~int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    with _lock:
        mask = os.umask(0o022)
        os.umask(mask)
    return 0o666 & ~mask


# --- checks before any work ------------------------------------------------------------------------

def check_writable(path, what: str = "file") -> None:
    """MeshError unless ``path`` can be created: its folder exists and is writable, and it is not a folder."""
    path = os.fspath(path)
    folder = _folder(path)
    if os.path.isdir(path):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': it is a folder")
    if not os.path.isdir(folder):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': the folder '{_shown(folder)}' does not exist")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise MeshError(f"cannot write the {what} '{_shown(path)}': the folder '{_shown(folder)}' is not writable")


def refuse_existing(path, force: bool, what: str = "file", how: str = "--force") -> None:
    """MeshError (exit 2) if ``path`` exists and ``force`` is not set: nothing is overwritten silently."""
    if not force and os.path.lexists(os.fspath(path)):
        raise MeshError(f"the {what} '{_shown(path)}' already exists; pass {how} to overwrite it")


def check_output(path, force: bool, what: str = "file", how: str = "--force") -> None:
    """Both checks every command runs on each output path before it starts working."""
    check_writable(path, what)
    refuse_existing(path, force, what, how)


# --- temporaries: names, the live set, signals, stale ones -------------------------------------------

_lock = threading.RLock()
_live: set = set()  # temporaries of this process not yet renamed or removed
_saved: dict = {}   # signal -> the handler before ours, while _live is not empty
_cleaned: set = set()  # folders already cleaned of stale temporaries by this process


def temp_path(path) -> str:
    """A fresh temporary name beside ``path``, keeping its extension (the mesh writer needs it)."""
    folder, base = os.path.split(os.fspath(path))
    stem, ext = os.path.splitext(base)
    return os.path.join(folder, f"{PREFIX}{os.getpid()}-{secrets.token_hex(4)}-{stem[:80]}{ext[:20]}")


def _remove(tmp) -> None:
    try:
        if os.path.isdir(tmp) and not os.path.islink(tmp):
            shutil.rmtree(tmp, ignore_errors=True)
        else:
            os.remove(tmp)
    except FileNotFoundError:
        pass
    except OSError:
        pass
    # the native writer's own temporary inside ours (killed between its write and its rename)
    folder, base = os.path.split(tmp)
    try:
        for name in os.listdir(folder or "."):
            if name.startswith("." + base + ".meshmark-tmp-"):
                os.remove(os.path.join(folder, name))
    except OSError:
        pass


def _on_signal(signum, frame) -> None:
    with _lock:
        for tmp in list(_live):
            _remove(tmp)
        _live.clear()
    signal.signal(signum, signal.SIG_DFL)
    os.kill(os.getpid(), signum)  # end by the same signal: the conventional exit status


def _register(tmp) -> None:
    with _lock:
        if not _live and threading.current_thread() is threading.main_thread():
            for s in (signal.SIGINT, signal.SIGTERM):
                try:
                    _saved[s] = signal.signal(s, _on_signal)
                except (ValueError, OSError):  # not the main interpreter thread
                    pass
        _live.add(tmp)


def _unregister(tmp) -> None:
    with _lock:
        _live.discard(tmp)
        if not _live and _saved and threading.current_thread() is threading.main_thread():
            for s, h in _saved.items():
                signal.signal(s, h if h is not None else signal.SIG_DFL)
            _saved.clear()


def _alive(pid: int) -> bool:
    if pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # someone else's live process
        return True
    except OverflowError:
        return False
    return True


def clean_stale(folder, force: bool = False) -> list:
    """Remove from ``folder`` the meshmark temporaries whose process is no longer running (left by
    SIGKILL or a power loss). Done once per folder and process unless ``force``; returns the names
    removed. A temporary of a live process (this one included) is left alone."""
    folder = os.path.abspath(os.fspath(folder))
    with _lock:
        if folder in _cleaned and not force:
            return []
        _cleaned.add(folder)
    removed = []
    try:
        names = os.listdir(folder)
    except OSError:
        return removed
    for name in names:
        m = _STALE.match(name)
        if m is None or _alive(int(m.group(1))):
            continue
        p = os.path.join(folder, name)
        try:
            if os.path.isdir(p) and not os.path.islink(p):
                shutil.rmtree(p)
            else:
                os.remove(p)
            removed.append(name)
        except OSError:
            pass
    return removed


def _fsync_file(path) -> None:
    fd = os.open(path, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(folder) -> None:
    try:
        fd = os.open(folder, os.O_RDONLY | getattr(os, "O_DIRECTORY", 0))
    except OSError:
        return
    try:
        os.fsync(fd)
    except OSError:  # some file systems cannot fsync a folder
        pass
    finally:
        os.close(fd)


class Staged:
    """Temporaries for the group of ``paths``, renamed onto them by :meth:`commit` (in the order
    given), removed on any failure or signal::

        with Staged([out, keyfile], private=[False, True]) as st:
            write(st.temps[0]); write(st.temps[1])
            st.commit()

    Every temporary is created empty and private (0600) before the writers run; a non-private
    target gets the usual mode (0666 minus the umask) just before its rename, a private one stays 0600.
    """

    def __init__(self, paths, what=None, private=None, overwrite: bool = True):
        self.paths = [os.fspath(p) for p in paths]
        self.what = list(what) if what else ["file"] * len(self.paths)
        self.private = list(private) if private else [False] * len(self.paths)
        self.overwrite = overwrite
        self.temps: list = []
        self.done = False

    def __enter__(self):
        if len({os.path.realpath(p) for p in self.paths}) != len(self.paths):
            raise MeshError("the output files must be different paths: "
                            + ", ".join(f"{w} '{_shown(p)}'" for w, p in zip(self.what, self.paths)))
        for p, w in zip(self.paths, self.what):
            check_writable(p, w)
            if not self.overwrite:
                refuse_existing(p, False, w)
        for folder in dict.fromkeys(_folder(p) for p in self.paths):
            clean_stale(folder)
        try:
            for p in self.paths:
                tmp = temp_path(p)
                _register(tmp)
                self.temps.append(tmp)
                os.close(create_private(tmp))
        except OSError as exc:
            self._cleanup()
            raise MeshError(f"cannot write '{_shown(exc.filename or '')}': {exc.strerror or exc}") from None
        except BaseException:
            self._cleanup()
            raise
        return self

    def commit(self) -> None:
        try:
            mode = _default_mode()
            for tmp, private in zip(self.temps, self.private):
                os.chmod(tmp, PRIVATE_MODE if private else mode)
                _fsync_file(tmp)
            for p, tmp in zip(self.paths, self.temps):
                os.replace(tmp, p)
                _unregister(tmp)
                _fsync_dir(_folder(p))  # this rename is on disk before the next one
        except OSError as exc:
            raise MeshError(f"cannot write '{_shown(exc.filename or '')}': {exc.strerror or exc}") from None
        self.done = True

    def _cleanup(self) -> None:
        for tmp in self.temps:
            if os.path.lexists(tmp):
                _remove(tmp)
            _unregister(tmp)

    def __exit__(self, *exc) -> None:
        self._cleanup()


def write_all(items, what=None, private=None, overwrite: bool = True) -> None:
    """Write every ``(path, writer)`` pair or none: ``writer(tmp_path)`` writes the content to the
    temporary path it is given; when all writers succeeded the temporaries are renamed onto their
    targets in the order given (put first the file that must exist whenever the others do). On any
    failure every temporary is removed and the error re-raised. ``private[i]``: the file holds a key
    (0600). ``overwrite=False``: MeshError if a target exists (checked before any writer runs)."""
    items = list(items)
    with Staged([p for p, _ in items], what, private, overwrite) as st:
        try:
            for (_, writer), tmp in zip(items, st.temps):
                writer(tmp)
        except OSError as exc:
            raise MeshError(f"cannot write '{_shown(exc.filename or '')}': {exc.strerror or exc}") from None
        st.commit()


def text_writer(text: str):
    """A writer for :func:`write_all` that writes ``text`` (UTF-8) into the temporary it is given,
    keeping that file (and its private mode)."""
    data = text.encode("utf-8")

    def write(tmp):
        with open(tmp, "r+b") as f:
            f.truncate(0)
            f.write(data)
    return write


def write_text(path, text: str, private: bool = False) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically: a temporary file, fsync, then a rename;
    ``private``: the file holds a key (0600 from its creation)."""
    write_all([(path, text_writer(text))], private=[private])


def read_at_most(path, limit: int, what: str, too_large: str = "") -> bytes:
    """The bytes of ``path``, read with a bound: MeshError (exit 2) naming ``what`` (e.g. ``"keyfile
    'k.json'"``) when it cannot be read or holds more than ``limit`` bytes (``too_large`` is appended
    to that message)."""
    try:
        with open(path, "rb") as f:
            raw = f.read(limit + 1)
    except OSError as exc:
        raise MeshError(f"cannot read {what}: {exc.strerror or exc}") from None
    if len(raw) > limit:
        raise MeshError(f"{what} is larger than {limit >> 20} MB{too_large}")
    return raw


def write_bytes(path, data: bytes, private: bool = False, what: str = "file", overwrite: bool = True) -> None:
    """Write ``data`` to ``path`` atomically (as :func:`write_text`)."""
    def write(tmp):
        with open(tmp, "r+b") as f:
            f.truncate(0)
            f.write(data)
    write_all([(path, write)], what=[what], private=[private], overwrite=overwrite)


class temp_folder:
    """A private temporary folder beside ``path`` (``.meshmark-tmp-<pid>-<hex>-<name>``), removed on
    exit, on SIGINT/SIGTERM, or by :func:`clean_stale` after a kill::

        with temp_folder(out) as d: ...
    """

    def __init__(self, path):
        self.path = temp_path(path)

    def __enter__(self) -> str:
        check_writable(self.path, "temporary folder")
        clean_stale(_folder(self.path))
        _register(self.path)
        try:
            os.mkdir(self.path, 0o700)
        except OSError as exc:
            _unregister(self.path)
            raise MeshError(f"cannot create the temporary folder '{_shown(self.path)}': {exc.strerror or exc}") from None
        return self.path

    def __exit__(self, *exc) -> None:
        shutil.rmtree(self.path, ignore_errors=True)
        _unregister(self.path)
