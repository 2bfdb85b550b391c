"""Teaching: the in-notebook checks, the tasks, the sandboxed grader and the course's commands.  May import every
layer below; nothing imports it.  Student code runs only in the student's own process (the checks) or in the grading
sandbox (``kernel/`` is all of this package that the sandbox keeps).

Its rooms, by role; what each may import of ``lab.teaching`` (``tests/test_layout.py`` keeps it so):

==================  ==============================================================  ==================================
``kernel/``         runs beside the student's code: the calling protocol, the      nothing of teaching; **inside the
                    graded calls and run of a notebook, exercise mode               sandbox** (the only teaching code
                                                                                    it keeps)
``tasks/``          the graded tasks: cases, exact answers, hints, mutants; the     ``task``, ``report``, ``kernel``;
                    registry ``TASKS`` and ``ANALYTIC_BLOCK``                       **withheld whole** from the
                                                                                    hand-out
``task``            the task model: ``Task``, ``CaseSpec``, ``Hint``, judges,       ``report``, ``kernel``
                    ``judge_outcome``, ``build_report``
``report``          ``Case`` and ``Report``: what a check shows                     nothing of teaching
``check``           ``lab.check``: a task's public cases on the student's code      ``self_check``, ``task``,
                                                                                    ``report``, ``tasks``
``self_check``      runs those cases in the student's own process (withheld         ``kernel``, ``task``, ``report``,
                    functions blocked, a time limit)                                ``untrusted``
``untrusted``       everything a student wrote, read as hostile input               nothing of teaching
``sandbox/``        bubblewrap, seccomp, cgroups, the launcher, and ``withhold``    ``kernel``, ``tasks``; never the
                    (the withheld set, the sandbox's and the hand-out's copy)       self-check
``grader/``         grading one notebook: the assignment, the run in the sandbox,   ``kernel``, ``task``, ``report``,
                    its output read as hostile input                                ``tasks``, ``sandbox``,
                                                                                    ``untrusted``
``course/``         one module per ``curvature-lab`` verb (``exercises``,           everything above
                    ``release``, ``collect``, ``grade``, ``feedback``,
                    ``gradebook``, ``gradescope``, ``written``), and what verbs
                    share (``files``, ``late``, ``pages``)
==================  ==============================================================  ==================================
"""
