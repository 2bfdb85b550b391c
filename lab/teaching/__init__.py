"""Teaching: the in-notebook checks, the tasks, the sandboxed grader and the course's commands.  May import every
layer below; nothing imports it.  Student code runs only in the student's own process (the checks) or in the grading
sandbox (``kernel/`` is all of this package that the sandbox keeps).

Its rooms, by role: what each holds; what it may import of ``lab.teaching`` (``tests/test_layout.py`` keeps it so);
its side of the trust boundaries.

- ``kernel/``: runs beside the student's code (the calling protocol, the graded calls, the graded run of a notebook,
  exercise mode, the student's own surface ``lab.my_surface``); imports nothing of teaching; **inside the sandbox**,
  the only teaching code it keeps.
- ``tasks/``: the graded tasks' cases, exact answers, hints and mutants, the registry ``TASKS`` and ``ANALYTIC_BLOCK``;
  imports ``task``, ``report``, ``kernel``; **withheld whole from the hand-out**.
- ``task``: the task model (``Task``, ``CaseSpec``, ``Hint``, the judges, ``judge_outcome``, ``build_report``);
  imports ``report``, ``kernel``.
- ``report``: ``Case`` and ``Report``, what a check shows; imports nothing of teaching.
- ``check``: ``lab.check``, a task's public cases on the student's code; imports ``self_check``, ``task``, ``report``,
  ``tasks``.
- ``self_check``: runs those cases in the student's own process (withheld functions blocked, a time limit); imports
  ``kernel``, ``task``, ``report``, ``untrusted``.
- ``untrusted``: everything a student wrote, read as hostile input; imports nothing of teaching.
- ``sandbox/``: bubblewrap, seccomp, cgroups, the launcher, and ``withhold`` (the withheld set, the sandbox's and the
  hand-out's copy of the library); imports ``kernel``, ``tasks``; never the self-check.
- ``grader/``: grading one notebook (the assignment, the run in the sandbox, its output read as hostile input);
  imports ``kernel``, ``task``, ``report``, ``tasks``, ``sandbox``, ``untrusted``.
- ``course/``: one module per ``curvature-lab`` verb (``start``, ``exercises``, ``release``, ``collect``, ``grade``,
  ``feedback``, ``gradebook``, ``gradescope``, ``written``) and what verbs share (``files``, ``late``, ``pages``);
  imports everything above.
"""
