"""The course, one module per ``curvature-lab`` verb (``exercises``, ``release``, ``collect``, ``grade``, ``feedback``,
``gradebook``, ``gradescope``, ``written``) and what verbs share: the files passed between them (:mod:`.files`), the
late policy (:mod:`.late`), HTML pages (:mod:`.pages`).  Sits on top: imports the grader and everything below it."""
