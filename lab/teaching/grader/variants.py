"""The grader's side of per-student surfaces (:mod:`lab.teaching.kernel.variants`): whether a notebook comes from a
per-student hand-out, and the notes on a student's variant – a student not in the table (for the student too), numbers
that answer classmates' variants (for the instructor only, with their names)."""

import numpy as np

from ...i18n import _
from ..kernel.protocol import decode
from ..tasks import TASKS
from ..untrusted import clean

__all__ = ["classmates_numbers", "per_student_hand_out", "variant_notes"]


def per_student_hand_out(nb):
    """The variants table id a notebook of a per-student hand-out carries (metadata ``lab.variants``), or ""."""
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    return str(meta.get("variants", "") or "")


def variant_notes(prepared, student):
    """A note for each per-student task of a student who is not in the variants table (graded on the common
    surface)."""
    if prepared.variants is None:
        return []
    return [_("{student} is not in the variants table: {task} is graded on the common surface").format(
                student=clean(str(student), 100, keep_newlines=False), task=name)
            for name, _obj, _points in prepared.tasks
            if TASKS[name].variant and prepared.params.get(TASKS[name].variant) is None]


def classmates_numbers(prepared, k, outcomes, student):
    """A note when the numbers of task ``k`` (wrong for ``student``) are right for classmates' variants."""
    values = [out.get("value") for out in outcomes.values() if isinstance(out, dict) and out.get("status") == "ok"]
    if not values:
        return []
    try:
        value = values[0] if isinstance(values[0], np.ndarray) else decode(values[0])
    except (ValueError, TypeError):
        return []
    owners = prepared.owners(k, value)
    if not owners:
        return []
    shown = ", ".join(clean(o, 100, keep_newlines=False) for o in owners[:10]) + (" …" if len(owners) > 10 else "")
    return [_("{task}: these numbers answer the variant of another student ({owners}), not {student}'s own").format(
        task=prepared.tasks[k][0], owners=shown, student=clean(str(student), 100, keep_newlines=False))]
