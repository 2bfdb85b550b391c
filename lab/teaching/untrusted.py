"""Everything a student wrote, read as hostile input: files, JSON, text shown to the instructor.

The grader never trusts what a submission or a sandbox leaves behind.  This module holds the few
functions that read and show it, so every place uses the same rules:

* :func:`read_file`: regular files only (no symlink, FIFO or device; opened with ``O_NOFOLLOW`` and
  ``O_NONBLOCK``), at most ``limit`` bytes, checked before anything is read or parsed;
* :func:`loads`: JSON with a bounded nesting depth (a 200 000-deep line is refused, not a
  ``RecursionError``) and a bounded size;
* :func:`clean`: text for a terminal, a text report, CSV or JSON: control characters and escape
  sequences made visible (``\\x1b`` instead of ESC), shortened to a stated limit;
* :func:`csv_cell`: a spreadsheet cell that is never a formula (``= + - @`` and tab/CR quoted with ``'``);
* :func:`plain_file`: whether a path in a folder of submissions is a plain file inside it.
"""

import errno
import json
import os
import stat
from pathlib import Path

__all__ = ["MAX_TEXT", "UntrustedError", "clean", "csv_cell", "loads", "plain_file", "read_file"]

#: Longest text of one message kept from a submission (characters).
MAX_TEXT = 2000
#: Deepest nesting accepted in a JSON document from a sandbox.
MAX_DEPTH = 32


class UntrustedError(ValueError):
    """A file or document from a submission or a sandbox that is not what it should be."""


def read_file(path, limit, *, dir_fd=None):
    """The bytes of the regular file ``path``, refusing symlinks, FIFOs, devices and files over ``limit`` bytes.

    ``dir_fd``: ``path`` is relative to this open folder (``os.open`` of a folder opened without following links).

    The file is opened without following a symlink and without blocking (a FIFO never blocks the grader),
    its type and size are checked on the open descriptor, and at most ``limit`` bytes are read.
    """
    flags = os.O_RDONLY | os.O_NOFOLLOW | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0)
    try:
        fd = os.open(path, flags, dir_fd=dir_fd)
    except OSError as exc:
        if exc.errno == errno.ELOOP or (dir_fd is None and os.path.islink(path)):
            raise UntrustedError(f"{Path(path).name} is a symbolic link, not a file") from None
        raise UntrustedError(f"cannot open {Path(path).name}: {exc.strerror}") from None
    try:
        info = os.fstat(fd)
        if not stat.S_ISREG(info.st_mode):
            raise UntrustedError(f"{Path(path).name} is not a regular file ({_kind(info.st_mode)})")
        if info.st_size > limit:
            raise UntrustedError(f"{Path(path).name} has {info.st_size} bytes; at most {limit} are read")
        chunks, left = [], limit + 1
        while left > 0:
            chunk = os.read(fd, min(left, 1 << 20))
            if not chunk:
                break
            chunks.append(chunk)
            left -= len(chunk)
        data = b"".join(chunks)
        if len(data) > limit:  # grew while being read
            raise UntrustedError(f"{Path(path).name} has more than {limit} bytes")
        return data
    finally:
        os.close(fd)


def _kind(mode):
    for test, name in ((stat.S_ISFIFO, "a FIFO"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
                       (stat.S_ISSOCK, "a socket"), (stat.S_ISDIR, "a folder"), (stat.S_ISLNK, "a symbolic link")):
        if test(mode):
            return name
    return "not a regular file"


def plain_file(path, folder):
    """``None`` if ``path`` is a plain file inside ``folder``, else why not (a short English reason).

    Refused: a symbolic link (the file itself or a folder on the way below ``folder``), a FIFO, a device, a
    file with further hard links (it may be another student's or a host file), a path that leaves ``folder``.
    """
    path, folder = Path(path), Path(folder)
    try:
        rel = path.relative_to(folder)
    except ValueError:
        return "outside the folder of submissions"
    here = folder
    for part in rel.parts:
        here = here / part
        try:
            info = os.lstat(here)
        except OSError as exc:
            return f"cannot be read ({exc.strerror})"
        if stat.S_ISLNK(info.st_mode):
            return "a symbolic link" if here == path else f"inside a symbolic link ({here.relative_to(folder)})"
    if not stat.S_ISREG(info.st_mode):
        return _kind(info.st_mode)
    if info.st_nlink > 1:
        return f"a hard link ({info.st_nlink} names for one file)"
    return None


def _depth_ok(text, limit):
    """Whether the nesting of brackets outside strings in JSON ``text`` stays within ``limit``."""
    depth, in_string, escaped = 0, False, False
    for ch in text:
        if in_string:
            if escaped:
                escaped = False
            elif ch == "\\":
                escaped = True
            elif ch == '"':
                in_string = False
        elif ch == '"':
            in_string = True
        elif ch in "[{":
            depth += 1
            if depth > limit:
                return False
        elif ch in "]}":
            depth -= 1
    return True


def loads(text, *, max_depth=MAX_DEPTH, limit=None, constants=False):
    """``json.loads`` of an untrusted document: bounded size and nesting; NaN and Infinity refused unless
    ``constants`` (a student's result may be NaN: that is judged, not refused).

    Raises :class:`UntrustedError` for anything that is not such a document.
    """
    if isinstance(text, bytes):
        text = text.decode("utf-8", "replace")
    if limit is not None and len(text) > limit:
        raise UntrustedError(f"a document of {len(text)} characters; at most {limit} are read")
    if not _depth_ok(text, max_depth):
        raise UntrustedError(f"a document nested deeper than {max_depth} levels")

    def constant(name):
        raise UntrustedError(f"a document with {name}")

    try:
        return json.loads(text, parse_constant=None if constants else constant)
    except (ValueError, RecursionError) as exc:
        if isinstance(exc, UntrustedError):
            raise
        raise UntrustedError(f"not a JSON document ({type(exc).__name__})") from None


_VISIBLE = {"\t": "\\t", "\r": "\\r"}


def clean(text, limit=MAX_TEXT, *, keep_newlines=True):
    """``text`` safe to print, write to a report, a CSV cell or JSON: every control character (C0, DEL, C1,
    bidirectional overrides) is shown as an escape (``\\x1b``), and the text is cut at ``limit`` characters
    (with " … (N more characters)")."""
    text = "" if text is None else str(text)
    if len(text) > limit:
        text = text[:limit] + f" … ({len(text) - limit} more characters)"
    out = []
    for ch in text:
        code = ord(ch)
        if ch == "\n" and keep_newlines:
            out.append(ch)
        elif ch in _VISIBLE:
            out.append(_VISIBLE[ch])
        elif code < 0x20 or 0x7F <= code < 0xA0 or 0x202A <= code <= 0x202E or 0x2066 <= code <= 0x2069:
            out.append(f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}")
        else:
            out.append(ch)
    return "".join(out)


def csv_cell(value):
    """A value for a CSV cell: text cleaned (one line) and never read as a formula by a spreadsheet."""
    if isinstance(value, (int, float, bool)) or value is None:
        return "" if value is None else value
    text = clean(str(value).replace("\r\n", " ").replace("\n", " "))
    return "'" + text if text[:1] in ("=", "+", "-", "@", "\t", "\r") else text
