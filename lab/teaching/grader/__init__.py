"""Grading one notebook: the instructor's assignment, the cases and exact answers outside, the run in the sandbox, and
what the sandbox leaves behind read as hostile input.  Imports the task model, the tasks, the kernel's protocol and
the sandbox."""
