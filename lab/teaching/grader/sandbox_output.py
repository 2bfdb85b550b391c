"""What a graded run leaves in its output folder, read back as hostile input.

The sandbox's output folder is writable by the student's code, so everything in it is checked before it is
used (:mod:`lab.teaching.untrusted`): the folder itself must not be a symbolic link, every file is a regular
file of bounded size opened without following links, every JSON line has a bounded depth and the fields
and types the harness writes.  Anything else raises :class:`InvalidResults`, which the grader turns into
that submission's "invalid results" (0 points and a note), never into an exception of the run.

Files: ``task-K.jsonl`` (one line per case: ``{"index", "status", "message"?, "value"?, "undefined"?}``;
the last complete line per index counts, a last line cut off when the sandbox was stopped is ignored) and
``cells.json`` (``{"cell_errors": [{"cell", "error", "kind"}], "restarts"}``).

**Bounded work.**  A task file is read one line at a time (:func:`lab.teaching.untrusted.read_lines`), never
whole; a line longer than :data:`MAX_LINE` (far more numbers than any case asks for) makes its case a "bad output"
without being parsed, and each value is kept decoded (8 bytes per number, at most
:data:`lab.teaching.kernel.protocol.MAX_VALUES` numbers), only the last one per case.  So the grader holds, per task, at
most its cases' values and one line: a few MiB per submission whatever the submission wrote.
"""

import os

from ...i18n import _
from ..kernel.protocol import MAX_VALUES, decode
from ..untrusted import TooLong, UntrustedError, clean, loads, read_file, read_lines

__all__ = ["CELL_KINDS", "MAX_CELL_ERRORS", "OUTCOMES", "InvalidResults", "open_folder", "read_cells", "read_outcomes"]

#: Largest result file of one task read back (bytes), and largest cells.json.
MAX_TASK_FILE = 64 << 20
#: Longest line of a task file that is parsed (bytes): one case's result, :data:`MAX_VALUES` numbers as the harness
#: writes them (at most 25 bytes each) and its message.
MAX_LINE = 32 * MAX_VALUES + (64 << 10)
MAX_CELLS_FILE = 1 << 20
#: Cell errors kept in a report.
MAX_CELL_ERRORS = 200
#: Statuses the harness writes for a case.
OUTCOMES = ("ok", "not implemented", "timeout", "delegated", "error", "bad output", "not run")
#: Kinds of cell errors the child records (``lab.teaching.kernel.graded_run``).
CELL_KINDS = ("error", "syntax", "died", "timeout", "withheld", "follows", "not run")


class InvalidResults(UntrustedError):
    """The output folder of a graded run holds something the harness did not write."""


def open_folder(path):
    """A descriptor of the output folder ``path`` (not a symbolic link); close it with ``os.close``."""
    try:
        return os.open(path, os.O_RDONLY | os.O_DIRECTORY | os.O_NOFOLLOW)
    except OSError as exc:
        raise InvalidResults(f"the output folder cannot be opened ({exc.strerror}): replaced by the submission?") from None


def _exists(name, folder_fd):
    try:
        os.stat(name, dir_fd=folder_fd, follow_symlinks=False)
        return True
    except FileNotFoundError:
        return False


def _text(name, folder_fd, limit):
    try:
        return read_file(name, limit, dir_fd=folder_fd).decode("utf-8", "replace")
    except UntrustedError as exc:
        raise InvalidResults(str(exc)) from None


def _outcome(item, n, where):
    if not isinstance(item, dict):
        raise InvalidResults(f"{where}: not an object")
    index, status = item.get("index"), item.get("status")
    if type(index) is not int or not 0 <= index < n:
        raise InvalidResults(f"{where}: case index {clean(repr(index), 40)} is not one of 0 … {n - 1}")
    if not isinstance(status, str) or status not in OUTCOMES:
        raise InvalidResults(f"{where}: unknown status {clean(repr(status), 40)}")
    message = item.get("message", "")
    if not isinstance(message, str):
        raise InvalidResults(f"{where}: the message is not text")
    if (status == "ok") != ("value" in item):
        raise InvalidResults(f"{where}: a value belongs to status 'ok' only")
    if not isinstance(item.get("undefined", False), bool):
        raise InvalidResults(f"{where}: malformed field 'undefined'")
    out = {"index": index, "status": status, "message": clean(message)}
    if "value" in item:
        try:  # what the harness encodes always decodes; anything else was forged.  Kept decoded: 8 bytes a number
            out["value"] = decode(item["value"])
        except (ValueError, TypeError, OverflowError) as exc:
            raise InvalidResults(f"{where}: the value is not what the harness writes ({clean(exc, 100)})") from None
    if item.get("undefined"):
        out["undefined"] = True
    return out


def read_outcomes(folder_fd, name, n):
    """The outcome of each case from ``name`` (``task-K.jsonl``) in the output folder: ``{index: outcome}``, values
    decoded (see the module docstring for the bounds)."""
    if not _exists(name, folder_fd):
        return {}
    found = {}
    try:
        for number, line in read_lines(name, MAX_TASK_FILE, MAX_LINE, dir_fd=folder_fd):
            if isinstance(line, TooLong):
                out = _too_long(line, n, f"{name}, line {number}")
            elif not line.strip():
                continue
            else:
                try:
                    item = loads(line, constants=True)
                except UntrustedError as exc:
                    raise InvalidResults(f"{name}, line {number}: {exc}") from None
                out = _outcome(item, n, f"{name}, line {number}")
            found[out["index"]] = out
    except InvalidResults:
        raise
    except UntrustedError as exc:
        raise InvalidResults(str(exc)) from None
    return found


def _too_long(head, n, where):
    """A line over :data:`MAX_LINE` bytes, from its first bytes: the harness writes ``{"index": i, …`` first, so its
    case is known; that case is a bad output.  Anything else was forged."""
    prefix = b'{"index": '
    digits = head[len(prefix):].split(b",", 1)[0] if head.startswith(prefix) else b""
    if not digits.isdigit() or not 0 <= int(digits) < n:
        raise InvalidResults(f"{where}: a line of more than {MAX_LINE} bytes that is not a case's result")
    return {"index": int(digits), "status": "bad output", "message": _(
        "a result with far more numbers than the task asks for (more than {limit} are not read)").format(
            limit=MAX_VALUES)}


def read_cells(folder_fd, name="cells.json"):
    """``(cell_errors, restarts, complete)`` from ``cells.json``; ``complete`` is False when the file is missing."""
    if not _exists(name, folder_fd):
        return [], 0, False
    try:
        info = loads(_text(name, folder_fd, MAX_CELLS_FILE))
    except UntrustedError as exc:
        raise InvalidResults(f"{name}: {exc}") from None
    if not isinstance(info, dict) or not isinstance(info.get("cell_errors"), list):
        raise InvalidResults(f"{name}: no list of cell errors")
    restarts = info.get("restarts", 0)
    if type(restarts) is not int or restarts < 0:
        raise InvalidResults(f"{name}: malformed restart count")
    errors = []
    for k, e in enumerate(info["cell_errors"][:MAX_CELL_ERRORS]):
        if not isinstance(e, dict) or type(e.get("cell")) is not int or e["cell"] < 0 \
                or not isinstance(e.get("error"), str) or e.get("kind") not in CELL_KINDS:
            raise InvalidResults(f"{name}: cell error {k} is malformed")
        errors.append({"cell": e["cell"], "error": clean(e["error"], 500), "kind": e["kind"]})
    return errors, restarts, True
