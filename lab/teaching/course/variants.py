"""Per-student surfaces for a release: ``curvature-lab release OUT --per-student ROSTER --secret-file FILE``.

**What is derived from what.**  A student's variant of an assignment's surface is

    HMAC-SHA256(course secret, "curvature-lab variant" ‖ assignment ‖ student ‖ attempt)

mapped onto the grids of the family's parameters (:meth:`lab.teaching.kernel.variants.Family.from_digest`: two bytes
per parameter pick one of its values).  The same secret and user name give the same variant in every release, so a
student added to the roster later changes nobody else's.  ``attempt`` is 0 unless the variant must be drawn again:

* its **character** differs from the common surface's (:attr:`~lab.teaching.kernel.variants.Family.character`; for
  notebook 05 the sign of K at every corner: the family keeps it by construction, the check keeps it so), or
* its **answers** are a classmate's: the reported numbers of one variant would pass as another's (the students are
  taken in sorted order, a later one draws again), or its parameters are the same as a classmate's.

**Where the secret lives.**  Only in the instructor's file (``--secret-file``, at least 16 bytes, e.g.
``python -c "import secrets; print(secrets.token_hex(32))" > course-secret.txt``, kept out of every repository).  The
hand-out carries the table ``variants.json`` (student → assignment → parameters) and its id in the per-student
exercises' metadata (``lab.variants``), never the secret; the grader reads the same table (``grade --variants``).
"""

import hashlib
import hmac
import json
from pathlib import Path

from ..kernel.variants import FAMILIES, FORMAT, table_id
from ..tasks import TASKS
from ..untrusted import UntrustedError, student_id
from .files import write_atomic

__all__ = ["MIN_SECRET", "VariantError", "build", "derive", "read_secret", "write_table"]

#: Fewest bytes of a course secret.
MIN_SECRET = 16
#: Most draws of one student's variant before the release gives up (each draw is a fresh HMAC).
MAX_ATTEMPTS = 100


class VariantError(ValueError):
    """A roster or secret a per-student release cannot use."""


def read_secret(path):
    """The course secret in the file ``path`` (its bytes, surrounding white space removed)."""
    secret = Path(path).read_bytes().strip()
    if len(secret) < MIN_SECRET:
        raise VariantError(f"{path}: a course secret needs at least {MIN_SECRET} bytes; got {len(secret)} (make one: "
                           "python -c \"import secrets; print(secrets.token_hex(32))\" > FILE)")
    return secret


def derive(secret, student, assignment, attempt=0):
    """The parameters of ``student``'s variant of ``assignment`` (before the release's checks, see the module)."""
    message = "\0".join(("curvature-lab variant", assignment, student, str(attempt))).encode()
    return FAMILIES[assignment].from_digest(hmac.new(secret, message, hashlib.sha256).digest())


def _answers(family, student, params):
    """``[(task, case, answer)]`` of the family's tasks on the variant ``params`` (floating point)."""
    out = []
    for name in family.tasks:
        task = TASKS[name]
        for case in task.variant_cases(student, params, exact=False):
            out.append((task, case, task.expected(case)))
    return out


def _confused(mine, theirs):
    """Whether one variant's answers pass as the other's (either way round) for some task."""
    for (task, case_a, a), (_task, case_b, b) in zip(mine, theirs):
        if task.judge(case_a, b, a)[0] or task.judge(case_b, a, b)[0]:
            return True
    return False


def build(roster, secret, assignments=None):
    """``{student: {assignment: parameters}}`` for every student of ``roster`` (user names) and every assignment with a
    per-student surface (or those of ``assignments``); see the module docstring."""
    students = []
    for name in roster:
        try:
            students.append(student_id(name))
        except UntrustedError as exc:
            raise VariantError(f"the roster has {name!r}, which is no user name: {exc}") from None
    students = sorted(set(students))
    if not students:
        raise VariantError("the roster has no students")
    table = {s: {} for s in students}
    for assignment in assignments or FAMILIES:
        family = FAMILIES[assignment]
        common = family.character(family.surface(None)) if family.character else None
        drawn = []  # (params, answers) of the students so far
        for student in students:
            for attempt in range(MAX_ATTEMPTS):
                params = derive(secret, student, assignment, attempt)
                if any(params == other for other, _ in drawn):
                    continue
                if common is not None and family.character(family.surface(params)) != common:
                    continue
                answers = _answers(family, student, params)
                if any(_confused(answers, theirs) for _, theirs in drawn):
                    continue
                break
            else:  # pragma: no cover - 33⁴ variants for a class of a few hundred
                raise VariantError(f"no variant of {assignment} for {student} after {MAX_ATTEMPTS} draws")
            drawn.append((params, answers))
            table[student][assignment] = params
    return table


def write_table(path, students):
    """Write the variants table of ``students`` (:func:`build`) to ``path``; returns its id."""
    ident = table_id(students)
    families = {a: {"parameters": {k: list(v) for k, v in FAMILIES[a].parameters.items()},
                    "tasks": list(FAMILIES[a].tasks)}
                for a in sorted({a for variants in students.values() for a in variants})}
    write_atomic(path, json.dumps({"format": FORMAT, "id": ident, "assignments": families, "students": students},
                                  indent=1, sort_keys=True) + "\n")
    return ident
