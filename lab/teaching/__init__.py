"""Teaching: in-notebook checks (``check``: cases, exact references, hints), the autograder (``grading``) and
exercise generation (``notebooks``).  May import every layer below; nothing imports it.
Student code runs here only in the student's own process (checks) or in the grader's sandbox.
"""
