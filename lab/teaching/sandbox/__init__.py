"""The grading sandbox: bubblewrap, the seccomp filter, cgroups, the launcher, and what is withheld from the student's
code (:mod:`.withhold`: the library copy the sandbox shows and the bodies the hand-out leaves out).  Imports the kernel
and the tasks' withheld names; never the self-check."""
