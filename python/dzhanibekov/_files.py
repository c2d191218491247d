"""Files in and out, the one way every reader and writer of the package does it (a leaf).

Writing is all or nothing (:func:`replacing`): the new content goes to a temporary file in the
destination's folder, which is renamed over the destination only once it is complete and on
disk. A full disk, a file-size limit, an error of the writer, Ctrl-C or SIGTERM leave the
previous file as it was and no partial file behind. A process killed outright (SIGKILL, an
abort) cannot clean up: its temporary file names its host and process (:func:`partial_prefix`),
and the next write to the same path removes those whose process is gone
(:func:`remove_stale`).

Reading refuses what is not a regular file before reading a byte (:func:`open_regular`): a
FIFO would block for ever waiting for a writer, and a device such as ``/dev/zero`` gives
bytes for ever. :func:`describe` says what a file that is not the expected kind looks like
(an AEM given to :func:`dzhanibekov.load`, a netCDF file given to ``read_aem``).
"""

from __future__ import annotations

import contextlib
import os
import re
import shutil
import signal
import socket
import stat
import tempfile
import threading
from collections.abc import Iterator
from pathlib import Path
from types import FrameType
from typing import IO, Any

from .errors import DzhanibekovError

__all__ = ["ReadError", "as_path", "replacing", "write_text", "save_figure", "open_regular",
           "size_of", "describe", "HDF5_SIGNATURE", "partial_prefix", "remove_stale"]

HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"
"""The first 8 bytes of an HDF5 file, hence of a netCDF-4 file (HDF5 file format
specification, "Format Signature")."""


class ReadError(DzhanibekovError):
    """A file that cannot be read as what was asked for: missing, not a regular file, larger
    than the reader's bound, of another format, or holding what the package never writes.
    The message names the file and what is expected; ``.path`` is the file and ``.why``
    what is wrong with it, in a few words.

    A :class:`~dzhanibekov.DzhanibekovError`, so a :class:`ValueError`.
    """

    def __init__(self, message: str, row: int | None = None,
                 index: tuple[int, ...] | None = None, *, path: str = "",
                 why: str = "") -> None:
        super().__init__(message, row, index)
        self.path = path
        self.why = why or message

    def at(self, row: int, index: tuple[int, ...] | None = None) -> ReadError:
        return ReadError(self.message, row, index, path=self.path, why=self.why)


def as_path(path: Any, name: str = "path") -> Path:
    """`path` as a Path: a str or os.PathLike naming a file (not empty, no NUL)."""
    if isinstance(path, bytes) or not isinstance(path, (str, os.PathLike)):
        raise TypeError(f"`{name}` must be a file path (str or pathlib.Path), got "
                        f"{type(path).__name__}")
    text = os.fspath(path)
    if not isinstance(text, str):
        raise TypeError(f"`{name}` must be a file path (str or pathlib.Path), got "
                        f"{type(path).__name__} of {type(text).__name__}")
    if not text.strip():
        raise ValueError(f"`{name}` must name a file, got {text!r}")
    if "\0" in text:
        raise ValueError(f"`{name}` must not hold a NUL character, got {text!r}")
    return Path(text)


# -- writing --------------------------------------------------------------------------------


def _umask() -> int:
    """The process's umask, read without changing it where the system allows."""
    try:
        with open("/proc/self/status", encoding="ascii") as f:
            for line in f:
                if line.startswith("Umask:"):
                    return int(line.split()[1], 8)
    except (OSError, ValueError):
        pass
    mask = os.umask(0o022)  # pragma: no cover - other systems: read it by setting it back
    os.umask(mask)  # pragma: no cover
    return mask  # pragma: no cover


class _Interrupts:
    """Notes every SIGINT that arrives while a file is written (and raises KeyboardInterrupt as
    Python's own handler does), so that an interrupt swallowed inside the writer (h5py and
    xarray run code in ``__del__`` and weak-reference callbacks, where an exception is only
    printed: "Exception ignored in …") still stops the write before anything is replaced.
    SIGTERM (a scheduler's, ``kill``'s) is taken the same way, then sent again once the
    temporary file is gone (:meth:`resend`), so that the process ends as it would have, with
    nothing left behind (it left a hidden ``.partial.nc`` two times in three). Only in the
    main thread, and only for a signal whose handler is Python's default."""

    _DEFAULTS = ((signal.SIGINT, signal.default_int_handler),
                 (signal.SIGTERM, signal.SIG_DFL))

    def __init__(self) -> None:
        self.seen = False
        self.terminated = False
        self._previous: dict[int, Any] = {}

    def __enter__(self) -> _Interrupts:
        if threading.current_thread() is threading.main_thread():
            for signum, default in self._DEFAULTS:
                if signal.getsignal(signum) is default:
                    self._previous[signum] = signal.signal(signum, self._handler)
        return self

    def _handler(self, signum: int, frame: FrameType | None) -> None:
        self.seen = True
        self.terminated = self.terminated or signum == signal.SIGTERM
        raise KeyboardInterrupt

    def __exit__(self, *exc: object) -> None:
        for signum, previous in self._previous.items():
            signal.signal(signum, previous)
        self._previous = {}

    def resend(self) -> None:
        """SIGTERM again, to the handler it had, if one came during the write."""
        if self.terminated:
            signal.raise_signal(signal.SIGTERM)


def _host() -> str:
    """This machine's name as it goes in a file name: letters, digits and hyphens."""
    return re.sub(r"[^A-Za-z0-9-]", "-", socket.gethostname())[:64] or "host"


def partial_prefix(name: str) -> str:
    """The start of the name of a temporary file (or folder) written for `name` by this
    process: ``.NAME.HOST-PID.``. The next write of `name` removes those of processes of this
    host that are gone (:func:`remove_stale`)."""
    return f".{name}.{_host()}-{os.getpid()}."


def _gone(pid: int) -> bool:
    """Whether no process `pid` runs on this machine (another user's counts as running)."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return True
    except OSError:
        return False
    return False


def remove_stale(folder: Path, name: str, tail: str) -> list[Path]:
    """Removes the temporary files (or folders) in `folder` that a write of `name` left when
    its process was killed: those named ``.NAME.HOST-PID.….TAIL…`` by a process of this host
    that is gone. A write of another host, or of a process still running, is left alone.
    Returns what was removed."""
    prefix = f".{name}.{_host()}-"
    removed: list[Path] = []
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return removed
    for entry in entries:
        if not entry.name.startswith(prefix) or tail not in entry.name:
            continue
        pid, _, rest = entry.name[len(prefix):].partition(".")
        if not (pid.isdigit() and rest and _gone(int(pid))):
            continue
        path = Path(entry.path)
        with contextlib.suppress(OSError):
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(path)
            else:
                path.unlink()
            removed.append(path)
    return removed


def _destination(path: Path) -> Path:
    """The file a write to `path` replaces: the target of a symbolic link (so that the link
    is kept), checked to be in an existing folder and not a folder itself."""
    target = Path(os.path.realpath(path)) if path.is_symlink() else path
    if target.is_dir():
        raise IsADirectoryError(21, "it is a folder; give a file name", str(path))
    folder = target.parent
    if not folder.is_dir():
        why = "is a file, not a folder" if folder.exists() else "does not exist"
        raise FileNotFoundError(2, f"its folder {folder} {why}", str(path))
    return target


@contextlib.contextmanager
def replacing(path: Any, *, name: str = "path") -> Iterator[Path]:
    """A temporary file in the folder of `path` to write to; it replaces `path` when the block
    ends normally, and is removed whatever else happens.

    The temporary file is hidden (``.NAME.HOST-PID.XXXX.partial.SUFFIX``: the suffix kept,
    for writers that choose the format by it), written, flushed to disk (``fsync``), given
    the permissions `path` has (or a new file would get) and renamed over `path`: one atomic
    step on the same filesystem. A symbolic link is followed: its target is replaced and the
    link kept. SIGINT during the block raises KeyboardInterrupt, and is honoured even where
    the writer swallowed it; SIGTERM stops the write the same way, and is sent again once the
    temporary file is gone. Temporary files that killed writes of `path` left are removed
    first (:func:`remove_stale`).

    Raises
    ------
    TypeError, ValueError
        `path` is not a file path.
    OSError
        `path` is a folder, its folder does not exist, or the write failed (a full disk, a
        file-size limit, no permission): the error names `path`, which is as it was.
    """
    path = as_path(path, name)
    target = _destination(path)
    try:
        mode = stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        mode = 0o666 & ~_umask()
    remove_stale(target.parent, target.name, ".partial")
    fd, tmp_name = tempfile.mkstemp(dir=target.parent, prefix=partial_prefix(target.name),
                                    suffix=".partial" + target.suffix)
    os.close(fd)
    tmp = Path(tmp_name)
    interrupts = _Interrupts()
    try:
        with interrupts:
            yield tmp
            if interrupts.seen:  # swallowed by the writer: honour it now
                raise KeyboardInterrupt
            fd = os.open(tmp, os.O_RDWR)  # (Windows flushes only a writable descriptor)
            try:
                os.fsync(fd)
            finally:
                os.close(fd)
            os.chmod(tmp, mode)
            os.replace(tmp, target)
    except OSError as exc:
        if exc.filename is None or str(exc.filename) == str(tmp):
            exc.filename = str(path)
        raise
    finally:
        with contextlib.suppress(OSError):
            os.unlink(tmp)
        interrupts.resend()


def write_text(path: Any, text: str, *, encoding: str = "utf-8", name: str = "path") -> Path:
    """Writes `text` to `path` all or nothing (see :func:`replacing`); returns `path`."""
    with replacing(path, name=name) as tmp:
        with open(tmp, "w", encoding=encoding, newline="") as f:
            f.write(text)
    return as_path(path, name)


# -- reading --------------------------------------------------------------------------------


def open_regular(path: Any, what: str, *, name: str = "path") -> IO[bytes]:
    """`path` opened for reading in binary, refused at once unless it is a regular file.

    The file is opened without blocking (a FIFO does not wait for a writer) and checked on
    the open descriptor (no race with a rename).

    Raises
    ------
    ReadError
        Missing, unreadable, a folder, a FIFO, a device or a socket; the message names the
        file and `what` was expected.
    """
    p = as_path(path, name)
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0))
    except OSError as exc:
        why = exc.strerror or str(exc)
        raise ReadError(f"{p} cannot be read ({why}); expected {what}", path=str(p),
                        why=why) from None
    try:
        mode = os.fstat(fd).st_mode
        if not stat.S_ISREG(mode):
            kind = ("a folder" if stat.S_ISDIR(mode) else "a FIFO (named pipe)"
                    if stat.S_ISFIFO(mode) else "a device" if stat.S_ISCHR(mode)
                    or stat.S_ISBLK(mode) else "a socket" if stat.S_ISSOCK(mode)
                    else "not a regular file")
            raise ReadError(f"{p} is {kind}, not a regular file; expected {what}",
                            path=str(p), why=f"{kind}, not a regular file")
        if hasattr(os, "set_blocking"):
            os.set_blocking(fd, True)
        return os.fdopen(fd, "rb")
    except BaseException:
        os.close(fd)
        raise


def size_of(f: IO[bytes]) -> int:
    """The size in bytes of the open regular file `f`."""
    return os.fstat(f.fileno()).st_size


_KINDS: tuple[tuple[bytes, str], ...] = (
    (HDF5_SIGNATURE, "an HDF5 file (a netCDF-4 file, such as dz.save writes: read it with "
                     "dz.load)"),
    (b"CDF\x01", "a netCDF-3 (classic) file"),
    (b"CDF\x02", "a netCDF-3 (64-bit offset) file"),
    (b"CDF\x05", "a netCDF-3 (64-bit data) file"),
    (b"CCSDS_AEM_VERS", "a CCSDS AEM attitude file (read it with dz.io.read_aem)"),
    (b"CCSDS_", "a CCSDS message of another kind"),
    (b"\x89PNG", "a PNG image"),
    (b"GIF8", "a GIF image"),
    (b"\x93NUMPY", "a NumPy .npy file"),
    (b"PK\x03\x04", "a ZIP archive"),
    (b"\x1f\x8b", "a gzip file"),
    (b"solid", "an ASCII STL mesh"),
    (b"<!DOCTYPE html", "an HTML page"),
    (b"<html", "an HTML page"),
)


def describe(head: bytes) -> str:
    """What a file that begins with `head` looks like, in words ("a CCSDS AEM attitude file
    (…)", "text", "binary data")."""
    if not head:
        return "empty"
    stripped = head.lstrip(b"\xef\xbb\xbf \t\r\n")
    for signature, kind in _KINDS:
        if head.startswith(signature) or stripped.startswith(signature):
            return kind
    if stripped.startswith(b"COMMENT") and b"CCSDS_AEM_VERS" in head:
        return "a CCSDS AEM attitude file (read it with dz.io.read_aem)"
    if stripped[:1] in (b"{", b"["):
        return "text (JSON or TOML)"
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as exc:
        if exc.start < len(head) - 4:  # not a character cut at the end of `head`
            return "binary data"
    return "text"



def save_figure(fig: Any, save: Any, **kwargs: Any) -> None:
    """``fig.savefig`` to `save` all or nothing (see :func:`replacing`): a path (the format
    from its suffix), or a binary file object written to directly; None writes nothing."""
    if save is None:
        return
    if hasattr(save, "write") and not isinstance(save, (str, os.PathLike)):
        fig.savefig(save, **kwargs)
        return
    if isinstance(save, bytes) or not isinstance(save, (str, os.PathLike)):
        raise TypeError(f"`save` must be a file path (str or pathlib.Path), a binary file "
                        f"object or None, got {type(save).__name__}")
    with replacing(save, name="save") as tmp:
        fig.savefig(tmp, **kwargs)
