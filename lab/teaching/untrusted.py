"""Everything a student wrote, read as hostile input: files, JSON, text shown to the instructor.

The grader never trusts what a submission or a sandbox leaves behind.  This module holds the few
functions that read and show it, so every place uses the same rules:

* :func:`read_file`: regular files only (no symlink, FIFO or device; opened with ``O_NOFOLLOW`` and
  ``O_NONBLOCK``), at most ``limit`` bytes, checked before anything is read or parsed;
* :func:`loads`: JSON with a bounded nesting depth (a 200 000-deep line is refused, not a
  ``RecursionError``) and a bounded size;
* :func:`clean`: text for a terminal, a text report, CSV or JSON: control characters, escape sequences and
  invisible characters (line and paragraph separators, bidi controls, zero-width characters, BOMs) made
  visible (``\\x1b`` instead of ESC, ``\\u202e``), shortened to a stated limit;
* :func:`csv_cell`: a spreadsheet cell that is never a formula (``= + - @``, tab/CR and ``'`` itself quoted with
  ``'``); :func:`csv_value` reads such a cell back (exactly one leading ``'`` removed), so that two names never
  share a cell (``'bea`` is written ``''bea``, ``bea`` stays ``bea``);
* :func:`student_id`: a user name (a folder ``SUBS/<student>``, a file ``SUBS/<student>.ipynb``, a home
  ``HOMES/<student>``) that is a name and never a path: no ``.``/``..``, leading dot, separator, control,
  line-breaking or invisible character, at most :data:`MAX_ID` characters;
* :func:`open_folder` and :func:`write_at`: a file written atomically into a folder opened once, by a name that
  is one path component, never through a symbolic link (a report folder, a student's home);
* :func:`plain_file`: whether a path in a folder of submissions is a plain file inside it;
* :func:`reported_outcome`: the numbers a notebook reports, ``name = (…)``, read as written (a literal of at most
  :data:`MAX_REPORTED` characters, never run).
"""

import ast
import csv
import errno
import json
import os
import secrets
import stat
import unicodedata
from pathlib import Path

from ..i18n import _

__all__ = ["MAX_ID", "MAX_REPORTED", "MAX_TEXT", "TooLong", "UntrustedError", "assigned", "clean", "csv_cell",
           "csv_rows", "csv_value", "defines", "definitions", "file_name", "loads", "open_file", "open_folder",
           "plain_file", "read_file", "read_lines", "read_notebook", "reported_outcome", "student_id", "write_at"]

#: Longest text of one message kept from a submission (characters).
MAX_TEXT = 2000
#: Deepest nesting accepted in a JSON document from a sandbox.
MAX_DEPTH = 32
#: Longest user name accepted (characters).
MAX_ID = 100
#: Longest file name :func:`write_at` writes (bytes; its temporary name is 22 bytes longer, and 255 is the limit).
MAX_FILE_NAME = 230


class UntrustedError(ValueError):
    """A file or document from a submission or a sandbox that is not what it should be."""


def open_file(path, limit, *, dir_fd=None):
    """A descriptor of the regular file ``path`` of at most ``limit`` bytes, opened without following a symbolic link
    and without blocking (a FIFO never blocks the grader); type and size are checked on the descriptor.  Close it with
    ``os.close``.  Raises :class:`UntrustedError` for anything else.

    ``dir_fd``: ``path`` is relative to this open folder (``os.open`` of a folder opened without following links).
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
    except BaseException:
        os.close(fd)
        raise
    return fd


def read_file(path, limit, *, dir_fd=None):
    """The bytes of the regular file ``path``, refusing symlinks, FIFOs, devices and files over ``limit`` bytes
    (:func:`open_file`); at most ``limit`` bytes are read."""
    fd = open_file(path, limit, dir_fd=dir_fd)
    try:
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


class TooLong(bytes):
    """What :func:`read_lines` gives for a line over its limit: the line's first :data:`TooLong.HEAD` bytes."""

    HEAD = 64


def read_lines(path, limit, max_line, *, dir_fd=None):
    """The complete lines of the regular file ``path`` (:func:`open_file`), one at a time: ``(number, bytes)``; a line
    longer than ``max_line`` bytes comes as a :class:`TooLong` of its first bytes (the rest is skipped, never kept).
    A last piece without a newline (a line cut off when its writer was stopped) is not returned.  At most ``limit``
    bytes are read, and no more than one line is ever held: a file of any content costs ``max_line`` bytes of memory.
    """
    fd = open_file(path, limit, dir_fd=dir_fd)
    try:
        line, head, number, total = bytearray(), None, 0, 0
        while chunk := os.read(fd, 1 << 16):
            total += len(chunk)
            if total > limit:
                raise UntrustedError(f"{Path(path).name} has more than {limit} bytes")
            start = 0
            while (end := chunk.find(b"\n", start)) >= 0:
                number += 1
                if head is None and len(line) + end - start > max_line:
                    head = TooLong(bytes(line[:TooLong.HEAD]) + chunk[start:start + TooLong.HEAD])[:TooLong.HEAD]
                yield number, TooLong(head) if head is not None else bytes(line + chunk[start:end])
                line.clear()
                head, start = None, end + 1
            if head is None:
                line += chunk[start:]
                if len(line) > max_line:
                    head = TooLong(line[:TooLong.HEAD])
                    line.clear()
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


#: Characters of a cell's source searched for a definition (a longer cell is searched up to here).
MAX_SCAN = 1 << 20


def definitions(source, limit=MAX_SCAN):
    """The names a cell's ``source`` (its first ``limit`` characters) defines at the start of a line, after any
    indentation: ``def name``, ``class name``, ``name =`` (not ``name ==``), in order.

    One pass over the lines, each looked at once: a regular expression with ``^\\s*`` over a cell of a million
    newlines backtracks quadratically (hours of the grader's time for one cell).
    """
    for line in str(source)[:limit].split("\n"):
        words = line.lstrip()
        parts = words.split(None, 1)
        if len(parts) == 2 and parts[0] in ("def", "class"):
            name = _identifier(parts[1])
        else:
            name = _identifier(words)
            rest = words[len(name):].lstrip(" \t")
            if not (rest.startswith("=") and not rest.startswith("==")):
                name = ""
        if name:
            yield name


def _identifier(text):
    """The identifier at the start of ``text`` ("" if none)."""
    end = 0
    while end < len(text) and (text[end].isalnum() or text[end] == "_"):
        end += 1
    name = text[:end]
    return name if name.isidentifier() else ""


def defines(source, name, limit=MAX_SCAN):
    """Whether ``source`` defines ``name`` (:func:`definitions`)."""
    return str(name).isidentifier() and name in definitions(source, limit)


#: Longest expression of reported numbers read (characters): four numbers with all their digits take about 100.
MAX_REPORTED = 2000
#: Most numbers a report of numbers may have.
MAX_REPORTED_NUMBERS = 16


def _open_brackets(text):
    return sum(text.count(c) for c in "([{") > sum(text.count(c) for c in ")]}")


def assigned(sources, name, limit=MAX_SCAN):
    """The expression of the last ``name = …`` at the start of a line (not indented) in the cell ``sources`` (in
    order), with the lines that follow while its brackets are open, at most :data:`MAX_REPORTED` characters; None
    when no cell assigns ``name`` so."""
    found = None
    if not str(name).isidentifier():
        return None
    for source in sources:
        lines = str(source)[:limit].split("\n")
        for k, line in enumerate(lines):
            if not line.startswith(name) or _identifier(line) != name:
                continue
            rest = line[len(name):].lstrip(" \t")
            if not rest.startswith("=") or rest.startswith("=="):
                continue
            text, j = rest[1:], k
            while _open_brackets(text) and j + 1 < len(lines) and len(text) <= MAX_REPORTED:
                j += 1
                text += "\n" + lines[j]
            found = text[:MAX_REPORTED + 1]
    return found


def _numbers(value):
    """The plain numbers of a literal (a number, or a tuple or list of numbers), or None."""
    items = list(value) if isinstance(value, (tuple, list)) else [value]
    if not 0 < len(items) <= MAX_REPORTED_NUMBERS or not all(
            isinstance(x, (int, float)) and not isinstance(x, bool) for x in items):
        return None
    return {"kind": "array", "shape": [len(items)] if isinstance(value, (tuple, list)) else [],
            "data": [float(x) for x in items]}


def reported_outcome(sources, name):
    """The numbers the code cells ``sources`` report as ``name = (…)``, read as written, never run: an outcome as
    :func:`lab.teaching.kernel.protocol.outcome` gives one – ``ok`` with the numbers, ``error`` for an expression that
    is no literal of numbers (code, which the grader does not run for it), ``not implemented`` when no cell assigns
    ``name`` at the start of a line."""
    text = assigned(sources, name)
    if text is None:
        return {"status": "not implemented", "message": _("{name} is not written yet: write the numbers as "
                                                          "{name} = (…) in its cell").format(name=name)}
    value = None
    if len(text) <= MAX_REPORTED:
        try:
            value = _numbers(ast.literal_eval(ast.parse(text.strip(), mode="eval")))
        except (SyntaxError, ValueError, TypeError, RecursionError, MemoryError):
            value = None
    if value is None:
        return {"status": "error", "message": _("{name} = {code} is not numbers as written; write the numbers "
                                                "themselves").format(name=name, code=clean(text.strip(), 120,
                                                                                          keep_newlines=False))}
    return {"status": "ok", "value": value}


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


#: Most cells a notebook may have to be read (the course's notebooks have at most about 120).
MAX_CELLS = 2000
#: Most texts (JSON strings: mostly lines of cells) a notebook may hold to be read: each costs about 50 bytes of the
#: grader's memory while it is parsed, so this bounds a notebook's cost at about 60 MiB whatever its 20 MiB hold (a
#: cell of a million lines is read; the course's notebooks have fewer than 5 000).
MAX_TEXTS = 1_200_000


def read_notebook(raw):
    """The notebook (nbformat 4) in the bytes ``raw`` of a student's file, parsed and validated once.

    The JSON is read with a bounded nesting (:func:`loads`); a notebook of more than :data:`MAX_TEXTS` texts is refused
    before it is parsed, one of more than :data:`MAX_CELLS` cells before it is validated (nbformat's validator takes about 0.25 ms per cell, much more on an invalid one,
    and ``nbformat.reads`` validates a second time).  Raises ``ValueError`` saying what is wrong.
    """
    head = raw[:4096].lstrip()
    if head and not head.startswith(b"{"):  # nbformat would fail on .get of a list: say what the file is
        kind = {b"[": "a JSON list", b'"': "a JSON string"}.get(head[:1], "no JSON object")
        raise ValueError(f"not a notebook: a notebook is a JSON object with 'cells' (nbformat 4); the file holds {kind}")
    texts = (raw.count(b'"') - raw.count(b'\\"')) // 2  # counted before anything is parsed
    if texts > MAX_TEXTS:
        raise ValueError(f"a notebook of about {texts} texts (lines of its cells and outputs); at most {MAX_TEXTS} "
                         "are read")
    try:
        data = loads(raw, max_depth=64)
    except UntrustedError as exc:
        raise ValueError(f"not a notebook: {exc}") from None
    if not isinstance(data, dict):
        raise ValueError("not a notebook: a notebook is a JSON object with 'cells' (nbformat 4)")  # noqa: TRY004 - a bad file
    cells = data.get("cells")
    if isinstance(cells, list) and len(cells) > MAX_CELLS:
        raise ValueError(f"a notebook of {len(cells)} cells; at most {MAX_CELLS} are read")
    import nbformat

    try:
        if data.get("nbformat") == 4:  # as nbformat reads it (sources as one string), without its own validation
            from nbformat.v4.nbjson import JSONReader

            nb = JSONReader().to_notebook(data)
        else:  # an old format: converted (nbformat validates it on the way)
            nb = nbformat.reads(raw.decode("utf-8", "replace"), as_version=4)
        nbformat.validate(nb)
    except Exception as exc:  # noqa: BLE001 - any parse or schema failure: a note, not a crash
        raise ValueError(f"{type(exc).__name__}: {clean(exc, 300)}") from None
    return nb


_VISIBLE = {"\t": "\\t", "\r": "\\r", "\n": "\\n"}
#: Unicode categories shown as escapes: controls (C0, DEL, C1), format characters (bidi controls, zero-width
#: characters, BOMs, soft hyphens, tags), line and paragraph separators, lone surrogates.
_HIDDEN = frozenset(("Cc", "Cf", "Zl", "Zp", "Cs"))


def _escape(ch):
    code = ord(ch)
    return f"\\x{code:02x}" if code < 0x100 else f"\\u{code:04x}" if code < 0x10000 else f"\\U{code:08x}"


def clean(text, limit=MAX_TEXT, *, keep_newlines=True):
    """``text`` safe to print, write to a report, a CSV cell or JSON: every control, format or separator character
    (Unicode categories Cc, Cf, Zl, Zp: C0, DEL, C1, bidi controls and marks, zero-width characters, BOMs, U+2028
    and U+2029; and lone surrogates) is shown as an escape (``\\x1b``, ``\\u202e``), a newline too unless
    ``keep_newlines``, and the text is cut at ``limit`` characters (with " … (N more characters)")."""
    text = "" if text is None else str(text)
    if len(text) > limit:
        text = text[:limit] + f" … ({len(text) - limit} more characters)"
    out = []
    for ch in text:
        if ch == "\n" and keep_newlines:
            out.append(ch)
        elif ch in _VISIBLE:
            out.append(_VISIBLE[ch])
        elif unicodedata.category(ch) in _HIDDEN:
            out.append(_escape(ch))
        else:
            out.append(ch)
    return "".join(out)


def csv_cell(value):
    """A value for a CSV cell: text cleaned (one line) and never read as a formula by a spreadsheet.

    Text beginning with ``= + - @`` (or a tab or CR) gets a leading ``'``, and so does text that begins with
    ``'`` itself: :func:`csv_value` removes exactly one, so every text reads back as itself.
    """
    if isinstance(value, (int, float, bool)) or value is None:
        return "" if value is None else value
    text = clean(str(value).replace("\r\n", " ").replace("\n", " "))
    return "'" + text if text[:1] in ("=", "+", "-", "@", "\t", "\r", "'") else text


def csv_value(cell):
    """The text of a cell :func:`csv_cell` wrote: the cell without the one leading ``'`` that quotes it."""
    return ("" if cell is None else str(cell)).removeprefix("'")


def csv_rows(lines, **options):
    """The rows of a CSV file (an open file or lines) written with :func:`csv_cell`, as dicts of text, every cell
    read back through :func:`csv_value` (cells beyond the header stay a list under the key ``None``, as
    :class:`csv.DictReader` gives them).  ``options``: those of :class:`csv.DictReader`."""
    return [{k: (v if k is None else csv_value(v)) for k, v in row.items()} for row in csv.DictReader(lines, **options)]


def student_id(text):
    """``text`` if it is a user name, the id of a student everywhere (a folder ``SUBS/<student>``, a file
    ``SUBS/<student>.ipynb``, a home ``HOMES/<student>``, a key of results and gradebooks); else
    :class:`UntrustedError` saying what is wrong.

    Refused: an empty name, ``.`` and ``..``, a leading dot, a path separator (``/``, ``\\``), a control
    character, a line break (also U+2028, U+2029), an invisible character (zero-width, bidi control, BOM: Unicode
    categories Cc, Cf, Zl, Zp), more than :data:`MAX_ID` characters.
    """
    if not isinstance(text, str):
        raise UntrustedError(f"a user name must be text; got {type(text).__name__}")
    if not text:
        raise UntrustedError("an empty user name")
    shown = clean(text, MAX_ID + 20, keep_newlines=False)
    if len(text) > MAX_ID:
        raise UntrustedError(f"the user name '{shown}' has {len(text)} characters; at most {MAX_ID}")
    if text in (".", ".."):
        raise UntrustedError(f"'{shown}' is a path, not a user name")
    if text.startswith("."):
        raise UntrustedError(f"the user name '{shown}' begins with a dot")
    for ch in text:
        what = None
        if ch in "/\\":
            raise UntrustedError(f"the user name '{shown}' has a path separator ({ch})")
        if ch in "\n\r\v\f\x1c\x1d\x1e\x85\u2028\u2029":
            what = "a line break"
        elif unicodedata.category(ch) == "Cc":
            what = "a control character"
        elif unicodedata.category(ch) in _HIDDEN:
            what = "an invisible character"
        if what:
            raise UntrustedError(f"the user name '{shown}' has {what} (U+{ord(ch):04X})")
    return text


def file_name(name):
    """``name`` if it is one path component that :func:`write_at` may create in a folder, else
    :class:`UntrustedError`: not empty, not ``.`` or ``..``, no ``/`` or NUL, at most :data:`MAX_FILE_NAME`
    bytes."""
    if not isinstance(name, str) or name in ("", ".", "..") or "/" in name or "\0" in name:
        raise UntrustedError(f"{clean(name, 80, keep_newlines=False)!r} is not a single file name")
    if len(os.fsencode(name)) > MAX_FILE_NAME:
        raise UntrustedError(f"the file name {clean(name, 80, keep_newlines=False)!r} is longer than "
                             f"{MAX_FILE_NAME} bytes")
    return name


def open_folder(path, *, dir_fd=None):
    """A descriptor of the folder ``path`` (relative to ``dir_fd`` if given), opened without following a symbolic
    link at its last component; :class:`UntrustedError` if it cannot be opened as a folder.  Close it with
    ``os.close``."""
    flags = os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0)
    try:
        return os.open(path, flags, dir_fd=dir_fd)
    except OSError as exc:
        raise UntrustedError(f"{clean(path, 300, keep_newlines=False)} cannot be opened as a folder "
                             f"({exc.strerror})") from None


def write_at(dir_fd, name, data, *, owner=None, mode=0o666):
    """Write ``data`` (text or bytes) to the file ``name`` in the open folder ``dir_fd``, atomically.

    ``name`` must be one path component (:func:`file_name`).  The bytes go to a new temporary file in the
    folder (created exclusively, never through a link) that is then renamed to ``name``: a symbolic link
    called ``name`` is replaced, never followed.  ``owner``: ``(uid, gid)`` to give the file (when running as root);
    ``mode``: its permissions (less the umask).  Returns ``name``.
    """
    file_name(name)
    data = data.encode() if isinstance(data, str) else bytes(data)
    tmp = f".{name}.{secrets.token_hex(8)}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | getattr(os, "O_CLOEXEC", 0), mode,
                 dir_fd=dir_fd)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            if owner is not None:
                os.fchown(fh.fileno(), *owner)
        os.replace(tmp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
    except BaseException:
        try:
            os.unlink(tmp, dir_fd=dir_fd)
        except OSError:
            pass
        raise
    return name
