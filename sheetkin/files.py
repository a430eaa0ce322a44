"""Files read and written by the commands, bounded and safe (issue 23; docs/reliability.md).

Reading: `read_bytes(path, cap)` opens without blocking (a FIFO given as a file would
otherwise wait forever for a writer), refuses anything but a regular file (a FIFO, a
device such as /dev/zero, a socket) before reading a byte, refuses a file larger than
`cap` from its size on disk, and never reads more than cap + 1 bytes even if the file
grows meanwhile: the work is bounded by the cap, not by what the file holds.

Names: `shown(path)` is a file name fit for a message, an HTML page or a CSV cell: bytes
that are not UTF-8 (a name made on another system) appear as \\xNN escapes instead of
failing when the text is encoded after all the work is done; controls, bidi overrides and
zero-width characters as escapes too (sheetkin.untrusted).

Only the standard library: every stage may import this module (it sits beside the
stages, as sheetkin.lazy does).
"""
from __future__ import annotations

import contextlib
import errno
import os
import stat

# The caps of the small text inputs (bytes on disk); the workbooks' own caps are
# sheetkin.xlsx.package.Limits and the scene's are sheetkin.kinematics.caps.
MAX_KEY_BYTES = 4_096               # a key is one line of 32-64 hex digits
MAX_CLASS_LIST_BYTES = 5_000_000    # Moodle's export of a class of 30 is a few KB
MAX_AT_FILE_BYTES = 20_000_000      # --at-file: a million angles of 20 characters (~250 MB to read)


class RefusedFile(OSError):
    """A file refused before (or while) reading it: not a regular file, or over its cap.
    An OSError, so every reader's `except OSError` names the file in its one line; its
    strerror says what is wrong."""


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "not a regular file"


def read_bytes(path: str | os.PathLike, cap: int, what: str = "file") -> bytes:
    """The bytes of the regular file at `path`, at most `cap` of them (RefusedFile past
    it); FileNotFoundError / IsADirectoryError / PermissionError as open() raises them."""
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_BINARY", 0)
    fd = os.open(path, flags)
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "Is a directory", os.fspath(path))
        if not stat.S_ISREG(st.st_mode):
            raise RefusedFile(errno.EINVAL, f"{_kind(st.st_mode)}, not a regular file; expected a {what}",
                              os.fspath(path))
        if st.st_size > cap:
            raise RefusedFile(errno.EFBIG, f"{st.st_size:,} bytes; a {what} may hold at most {cap:,}",
                              os.fspath(path))
        chunks, total = [], 0
        while True:
            block = os.read(fd, min(1 << 20, cap + 1 - total))
            if not block:
                break
            chunks.append(block)
            total += len(block)
            if total > cap:       # it grew since the fstat
                raise RefusedFile(errno.EFBIG, f"more than {cap:,} bytes; a {what} may hold at most {cap:,}",
                                  os.fspath(path))
        return b"".join(chunks)
    finally:
        os.close(fd)


def read_text(path: str | os.PathLike, cap: int, what: str = "file", encoding: str = "utf-8-sig") -> str:
    """read_bytes, decoded (UnicodeDecodeError as bytes.decode raises it)."""
    return read_bytes(path, cap, what).decode(encoding)


def shown(path: str | os.PathLike) -> str:
    """The name of `path` (or any text from a student) as text that always encodes and
    cannot forge or hide text: undecodable bytes (which Python keeps as lone surrogates)
    become \\xNN escapes, and so do controls (ESC, CR, LF), bidi overrides and zero-width
    characters (sheetkin.untrusted.shown_text: a forged "all correct" line is impossible)."""
    from .untrusted import shown_text
    text = os.fspath(path)
    if isinstance(text, bytes):
        return shown_text(text.decode("utf-8", "backslashreplace"))
    try:
        text.encode("utf-8")
        return shown_text(text)
    except UnicodeEncodeError:
        try:
            return shown_text(text.encode("utf-8", "surrogateescape").decode("utf-8", "backslashreplace"))
        except UnicodeEncodeError:    # a surrogate not from a file name's bytes
            return shown_text(text.encode("utf-8", "backslashreplace").decode("utf-8"))


# --------------------------------------------------------------------------- writing
# The temporary files being written now: a second Ctrl-C (or SIGTERM) during clean-up ends
# the process at once, and removes these first (remove_temporaries).
_TEMPORARIES: set[str] = set()


class Output:
    """An output file written safely. A new or regular file (also behind a symbolic link,
    which is written through: the link stays, its target gets the new content) is written
    to a temporary file beside it and renamed over it by commit(): an interruption, a full
    disk or an error leaves the old file as it was and no temporary file (abandon()).
    A FIFO or a device (/dev/null, /dev/stdout) is written as it is; a FIFO without a
    reader is refused at once (OSError ENXIO), never waited for. `.file` is binary."""

    def __init__(self, path: str | os.PathLike, suffix: str = ".part"):
        import tempfile
        self.path = os.fspath(path)
        self.tmp: str | None = None
        self.special = False
        try:
            st = os.stat(self.path)            # through links
        except FileNotFoundError:
            st = None
        if st is not None and stat.S_ISDIR(st.st_mode):
            raise IsADirectoryError(errno.EISDIR, "Is a directory", self.path)
        if st is not None and not stat.S_ISREG(st.st_mode):
            # by its own name: /dev/stdout resolves to /proc/PID/fd/pipe:[N], no path to open
            self.special = True
            self.file = _open_special(self.path, self.path)
            return
        real = os.path.realpath(self.path)
        folder = os.path.dirname(real)
        if not os.path.isdir(folder):
            raise FileNotFoundError(errno.ENOENT, "No such file or directory (the folder does not exist)",
                                    self.path)
        self.final = real
        self.mode = stat.S_IMODE(st.st_mode) if st is not None else 0o666 & ~_umask()
        try:
            fd, self.tmp = tempfile.mkstemp(prefix=".sheetkin-", suffix=suffix, dir=folder)
        except OSError as e:     # named by the output, not by the temporary .sheetkin-XXXX.part
            raise OSError(e.errno, e.strerror or str(e), self.path) from None
        _TEMPORARIES.add(self.tmp)
        self.file = os.fdopen(fd, "wb")

    def commit(self) -> None:
        try:
            self.file.close()                  # its last block may meet a full disk here
            if self.tmp is not None:
                os.chmod(self.tmp, self.mode)
                os.replace(self.tmp, self.final)
                _TEMPORARIES.discard(self.tmp)
        except OSError as e:
            raise OSError(e.errno, e.strerror or str(e), self.path) from None

    def abandon(self) -> None:
        with contextlib.suppress(OSError):
            self.file.close()          # may fail again (a full disk): the first error counts
        if self.tmp is not None:
            _unlink(self.tmp)


def _open_special(real: str, shown_as: str):
    """A FIFO or a device opened for writing, without blocking on a FIFO nobody reads."""
    flags = os.O_WRONLY | getattr(os, "O_NONBLOCK", 0)
    try:
        fd = os.open(real, flags)
    except OSError as e:
        if e.errno == errno.ENXIO:
            raise OSError(errno.ENXIO, "a FIFO with no reader (start the reader first)", shown_as) from None
        raise OSError(e.errno, e.strerror, shown_as) from None
    if hasattr(os, "set_blocking"):
        os.set_blocking(fd, True)       # now that a reader is there, wait for it as a pipe does
    return os.fdopen(fd, "wb")


def check_output(path: str | os.PathLike, what: str = "output") -> None:
    """Before the work: an output whose folder is missing or cannot take a new file (read
    only, a read-only file system, no permission) is one line naming the output, not the
    temporary .sheetkin-XXXX.part after minutes of work. A device or FIFO is left to
    Output. Tried for real (a file made and removed): permissions alone lie to root and
    say nothing of a read-only mount."""
    import tempfile
    p = os.fspath(path)
    try:
        st = os.stat(p)
    except FileNotFoundError:
        st = None
    except OSError as e:
        raise OSError(e.errno, e.strerror or str(e), p) from None
    if st is not None and stat.S_ISDIR(st.st_mode):
        raise IsADirectoryError(errno.EISDIR, "Is a directory", p)
    if st is not None and not stat.S_ISREG(st.st_mode):
        return
    folder = os.path.dirname(os.path.realpath(p))
    if not os.path.isdir(folder):
        raise FileNotFoundError(errno.ENOENT, "No such file or directory (the folder does not exist)", p)
    try:
        fd, probe = tempfile.mkstemp(prefix=".sheetkin-", suffix=".probe", dir=folder)
    except OSError as e:
        raise OSError(e.errno, f"{e.strerror or e} (its folder cannot take the {what})", p) from None
    os.close(fd)
    _unlink(probe)


def write_file(path: str | os.PathLike, data: bytes | str) -> None:
    """Write `data` (str: as UTF-8) to `path` through Output: all or nothing."""
    out = Output(path)
    try:
        # backslashreplace: a lone surrogate (a file name that is not UTF-8, see shown()) that
        # slipped through becomes \udcff, never an error after all the work is done
        out.file.write(data.encode("utf-8", "backslashreplace") if isinstance(data, str) else data)
        out.commit()
    except BaseException:
        out.abandon()
        raise


def _unlink(path: str) -> None:
    with contextlib.suppress(OSError):
        os.unlink(path)
    _TEMPORARIES.discard(path)


def remove_temporaries() -> None:
    """Remove every temporary output file still open (for a second signal's fast exit)."""
    for path in list(_TEMPORARIES):
        _unlink(path)


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


# --------------------------------------------------------------------------- children
# Processes of ours that a fast exit (a second signal) must not leave behind: the
# validation pool's workers. (LibreOffice runs are killed by sheetkin.xlsx.libreoffice
# itself when anything interrupts them.)
_CHILDREN: set[int] = set()


def child_started(pid: int) -> None:
    _CHILDREN.add(pid)


def child_ended(pid: int) -> None:
    _CHILDREN.discard(pid)


def kill_children(grace: float = 1.0) -> None:
    """End every child still registered (a second Ctrl-C): SIGTERM, which lets a worker
    kill a LibreOffice run of its own and remove its folders; SIGKILL for any still there
    after `grace` seconds."""
    import signal
    import time
    pids = list(_CHILDREN)
    for pid in pids:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGTERM)
    end = time.monotonic() + grace
    left = set(pids)
    while left and time.monotonic() < end:
        for pid in list(left):
            try:
                if os.waitpid(pid, os.WNOHANG)[0] == pid:
                    left.discard(pid)
            except ChildProcessError:
                left.discard(pid)
        time.sleep(0.02)
    for pid in left:
        with contextlib.suppress(OSError):
            os.kill(pid, signal.SIGKILL)
    _CHILDREN.difference_update(pids)
