"""What runs beside the student's code: the check's calling protocol, the graded calls, the graded run of a notebook,
exercise mode, the student's own surface.  The only teaching code the grading sandbox keeps (the trust boundary is this folder); it holds no case,
answer or hint and imports nothing of ``lab.teaching`` outside it."""
