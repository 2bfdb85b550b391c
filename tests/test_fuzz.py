"""The lab's own fuzzer in the suite (issue 35): every target of :mod:`tests.fuzz_targets` (the public API, the
command line and the course's verbs) with a derandomized Hypothesis run of a bounded number of examples and no
deadline.  Each call must end in a correct result, a clear ``ValueError``/``TypeError`` from the lab, or a flagged
degenerate result (:func:`tests.fuzz_support.run` judges it); a test fails with the distinct findings.

``python -m tests.fuzz`` runs the same targets with a larger budget (``--scale``), other examples (``--seed``) or
only some targets (``--only``); see docs/developers/testing.md.
"""

import io

import pytest

from .fuzz import fuzz
from .fuzz_support import report
from .fuzz_targets import targets

#: Share of each target's examples that the suite runs (``python -m tests.fuzz`` runs them all): the whole fuzzer
#: then takes about a minute on two loaded cores.
SUITE_SCALE = 0.5

TARGETS = targets()


@pytest.mark.parametrize("target", TARGETS, ids=[t.name for t in TARGETS])
def test_fuzz(target):
    findings, times = fuzz(target, max(2, round(target.examples * SUITE_SCALE)))
    assert times, "the fuzzer made no call"
    if findings:
        text = io.StringIO()
        report(findings, file=text)
        pytest.fail(text.getvalue())
