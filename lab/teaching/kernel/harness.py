"""The graded calls, run inside the sandboxed notebook kernel after the notebook's cells.

``run(namespace, spec_path, index, out_path, start, case_timeout)`` reads the cases of one task (inputs only:
no expected values exist in the sandbox), calls the student's object on each, and appends one JSON line
per case to ``out_path``: the plain numbers that came back, or a status and message.  The grader reads
those lines after the sandbox has ended and judges them itself; nothing here decides a score.
"""

import json

from ...i18n import _
from .protocol import decode_args, outcome

__all__ = ["run"]


def run(namespace, spec_path, index, out_path, start=0, case_timeout=10.0):
    with open(spec_path) as fh:
        task = json.load(fh)["tasks"][index]
    obj = namespace.get(task["object"])
    with open(out_path, "a") as out:
        for i, args in enumerate(task["cases"]):
            if i < start:
                continue
            if obj is None:
                result = {"status": "not implemented", "undefined": True,
                          "message": _("{name} is not defined: run the cell that defines it (and keep its name).").format(
                              name=task["object"])}
            else:
                result = outcome(task["protocol"], obj, decode_args(args), case_timeout)
            out.write(json.dumps({"index": i, **result}) + "\n")
            out.flush()  # a case that ran out of time costs that case only: the next one runs
