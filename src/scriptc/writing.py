"""The one writer of files: every verb that writes (`compile`, `decompile`, `fmt`, `lint --fix`,
`init`, `run --trace` and `--plot`, the cache) goes through here, so what a path *is* decides
how it is written, the same way everywhere:

- `-` is stdout;
- a symbolic link is followed: its target is written as below, and the link stays a link;
- a regular file (or a new one) is replaced atomically: a temporary file in the same folder,
  written, flushed to disk, given the old file's permission bits (and owner, where that is
  allowed), then renamed over the target. Readers see the old file or the whole new one, and a
  failure part way (a full disk, Ctrl-C) leaves the old file as it was and no temporary file;
- a character or block device (`/dev/null`) and a FIFO are opened and written to directly,
  never replaced; a Unix socket is connected to and sent the data;
- a folder, a missing parent folder or a parent that cannot be written is a `WriteError`,
  which `check_target` raises *before* the work whose result the file will hold.

A new file gets the usual permissions (0666 less the umask). Text is written as UTF-8, exactly
(no newline translation); `scriptc.encoding.encode_like` keeps the byte order mark of the file
it replaces.
Ctrl-C is held back while a file is put in place (`scriptc.interrupt.deferred`), so it never
leaves a temporary file or half a file. This module imports only the standard library and
`scriptc.interrupt`, so anything may use it.
"""

from __future__ import annotations

import os
import stat
import sys
import threading
from collections.abc import Iterator
from contextlib import contextmanager, suppress
from typing import BinaryIO

from scriptc.interrupt import deferred

STDOUT = "-"

class WriteError(Exception):
    """A file that cannot be written; the message names it and says what to do."""


def _reason(exc: OSError) -> str:
    return exc.strerror.lower() if exc.strerror else str(exc)


def _folder_of(path: str) -> str:
    return os.path.dirname(path) or "."


def _names_a_descriptor(path: str) -> bool:
    """Whether `path` leads, link by link, to an open file descriptor (`/dev/stdout` is a link
    to `/proc/self/fd/1`; `/dev/fd/N`): writing it means writing to that descriptor, whatever
    it is open on (a pipe, a terminal, a file the shell redirected, perhaps to append)."""
    path = os.path.abspath(path)
    for _hop in range(40):
        if path.startswith(("/proc/", "/dev/fd/")):
            return True
        try:
            link = os.readlink(path)
        except OSError:
            return False
        path = os.path.normpath(os.path.join(os.path.dirname(path), link))
    return False


def _plan(path: str) -> tuple[bool, str, os.stat_result | None]:
    """How `path` is written: (direct, target, stat). `direct` for a device, FIFO, socket or
    open descriptor, written to as it is (`target` is `path`); otherwise a regular file, or a
    new one, replaced atomically at `target`, the end of its links. Raises WriteError for a
    folder, and for a file whose folder is missing, not a folder or not writable."""
    try:
        st = os.stat(path)  # links followed, the system's own (/dev/stdout) included
    except (FileNotFoundError, NotADirectoryError):
        st = None  # a new file (or a link to one): its folder is checked below
    except OSError as exc:
        raise WriteError(f"cannot write `{path}`: {_reason(exc)}") from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise WriteError(f"cannot write `{path}`: it is a folder (give the path of a file)")
    if st is not None and (not stat.S_ISREG(st.st_mode) or _names_a_descriptor(path)):
        return True, path, st
    # A regular file, new or replaced, is written through a temporary file beside it.
    target = os.path.realpath(path)
    shown = _folder_of(path) if target == os.path.abspath(path) else _folder_of(target)
    folder = _folder_of(target)
    if not os.path.isdir(folder):
        if os.path.lexists(folder):
            raise WriteError(f"cannot write `{path}`: `{shown}` is not a folder (choose "
                             "another path)")
        raise WriteError(f"cannot write `{path}`: the folder `{shown}` does not exist "
                         f"(create it first: mkdir -p {shown})")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise WriteError(f"cannot write `{path}`: permission denied in the folder `{shown}` "
                         "(a file is replaced through a temporary file beside it)")
    return False, target, st


def check_target(path: str) -> None:
    """Raise WriteError when `path` cannot receive an output: a folder, a parent folder that is
    missing, not a folder, or not writable. Call it before the work whose result the file will
    hold, so that nothing is computed for nothing. `-` (stdout) always passes."""
    if path != STDOUT:
        _plan(path)


def write_file(path: str, data: str | bytes, *, exclusive: bool = False) -> None:
    """Write `data` (text as UTF-8) to `path` as its kind asks (see the module's docstring).
    With `exclusive` the file is created and never replaces anything: FileExistsError when
    something is at `path` already (a link too). Raises WriteError otherwise."""
    if isinstance(data, str):
        data = data.encode("utf-8")
    if path == STDOUT:
        stream = sys.stdout.buffer
        stream.write(data)
        stream.flush()
        return
    if exclusive and os.path.lexists(path):
        raise FileExistsError(path)
    direct, target, st = _plan(path)
    try:
        if not direct:
            if exclusive:
                create_file(target, data)
            else:
                replace_file(target, data, keep=st)
        elif st is not None and stat.S_ISSOCK(st.st_mode):  # (direct: st is known)
            _send(target, data)
        else:
            # A device, a FIFO, a descriptor: its reader gets the bytes; it is never replaced
            # (appending: a descriptor may name a file the shell opened to append to).
            with open(target, "ab", buffering=0) as f:
                _write_all(f, data)
    except FileExistsError:
        raise
    except OSError as exc:
        raise WriteError(f"cannot write `{path}`: {_reason(exc)}") from None


def _write_all(f: BinaryIO, data: bytes) -> None:
    view = memoryview(data)
    while view:
        view = view[f.write(view):]


def _send(target: str, data: bytes) -> None:
    """Send `data` to the Unix socket `target`: a stream socket, else a datagram one."""
    import errno
    import socket

    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        try:
            sock.connect(target)
        except OSError as exc:
            if exc.errno != errno.EPROTOTYPE:
                raise
        else:
            sock.sendall(data)
            return
    with socket.socket(socket.AF_UNIX, socket.SOCK_DGRAM) as sock:
        sock.connect(target)
        sock.send(data)


_umask: int | None = None
_lock = threading.Lock()


def _new_file_mode() -> int:
    """0666 less the umask: what `open` gives a new file (read once per process)."""
    global _umask  # noqa: PLW0603  # the process's umask, read once (tests clear it)
    if _umask is None:
        with _lock:
            _umask = os.umask(0)
            os.umask(_umask)
    return 0o666 & ~_umask


@contextmanager
def _temporary_copy(target: str, data: bytes, mode: int, durable: bool = True
                    ) -> Iterator[str]:
    """A temporary file beside `target` holding `data` with `mode` (flushed to disk when
    `durable`), for the block to put in place; whatever is left of it is removed at the end,
    and Ctrl-C is held back meanwhile (`scriptc.interrupt.deferred`)."""
    import tempfile

    folder, name = os.path.split(target)
    with deferred():
        fd, tmp = tempfile.mkstemp(dir=folder or ".", prefix=f".{name}.", suffix=".tmp")
        try:
            with os.fdopen(fd, "wb") as f:
                _write_all(f, data)
                if durable:
                    f.flush()
                    os.fsync(f.fileno())
            os.chmod(tmp, mode)
            yield tmp
        finally:
            with suppress(OSError):  # renamed into place already
                os.unlink(tmp)


def replace_file(target: str, data: bytes, *, durable: bool = True,
                 keep: os.stat_result | None = None) -> None:
    """Put `data` at the regular file `target` atomically (a temporary file beside it, renamed
    over it), keeping the permission bits and owner of `keep` (the stat of the file replaced;
    a new file gets 0666 less the umask). `durable` flushes the data to disk before the rename
    (the cache does without). Raises OSError; on any failure, or an interrupt, the old file is
    as it was and no temporary file is left."""
    mode = stat.S_IMODE(keep.st_mode) if keep is not None else _new_file_mode()
    with _temporary_copy(target, data, mode, durable) as tmp:
        if keep is not None and (keep.st_uid, keep.st_gid) != (os.geteuid(), os.getegid()):
            try:
                os.chown(tmp, keep.st_uid, keep.st_gid)
                os.chmod(tmp, mode)  # chown clears the set-user-ID and set-group-ID bits
            except OSError:
                pass  # only root may give a file away: it becomes ours, as with any editor
        os.replace(tmp, target)


def create_file(target: str, data: bytes) -> None:
    """Create the regular file `target` with `data`, whole or not at all, never over anything
    that is there (FileExistsError, even when another process made it meanwhile): the data is
    written to a temporary file, which is then hard-linked into place."""
    with _temporary_copy(target, data, _new_file_mode()) as tmp:
        try:
            os.link(tmp, target)
        except FileExistsError:
            raise
        except OSError:
            # A file system without hard links: exclusive creation, then the data.
            with open(target, "xb") as f:
                _write_all(f, data)
