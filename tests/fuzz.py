"""Run the lab's fuzzer over every target and print the distinct failures by category (issue 35).

``python -m tests.fuzz`` (the suite's budget), ``python -m tests.fuzz --scale 4`` (four times as many examples),
``python -m tests.fuzz --only geodesic`` (targets whose name contains the text), ``--seed N`` (other examples than
the suite's derandomized ones).  The test ``tests/test_fuzz.py`` runs the same targets and fails on any finding.
"""

import argparse
import time

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from .fuzz_support import fuzzing, report, run
from .fuzz_targets import draw_kwargs, targets


def fuzz(target, examples, seed=None):
    """Run ``examples`` examples of ``target``; returns the findings and the time per call."""
    findings, times = [], []

    @settings(max_examples=examples, deadline=None, database=None, derandomize=seed is None,
              suppress_health_check=list(HealthCheck))
    @given(data=st.data())
    def one(data):
        kwargs = draw_kwargs(data, target)
        out = run(target.name, target.func, kwargs, expect=target.expect, numbers=target.numbers, cli=target.cli)
        findings.extend(out.findings)
        times.append(out.seconds)

    if seed is not None:
        from hypothesis import seed as with_seed

        one = with_seed(seed)(one)
    with fuzzing():
        one()
    return findings, times


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python -m tests.fuzz")
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--only", default="")
    parser.add_argument("--seed", type=int)
    args = parser.parse_args(argv)
    everything, slow = [], []
    start = time.monotonic()
    for target in targets():
        if args.only not in target.name:
            continue
        t0 = time.monotonic()
        found, times = fuzz(target, max(1, round(target.examples * args.scale)), args.seed)
        everything += found
        slow.append((time.monotonic() - t0, target.name, len(times), max(times, default=0)))
        print(f"{target.name:40s} {len(times):4d} calls {slow[-1][0]:7.1f} s (slowest {slow[-1][3]:.1f} s) "
              f"{len(found)} failing", flush=True)
    print(f"\n{time.monotonic() - start:.0f} s in all; slowest targets:")
    for total, name, n, worst in sorted(slow, reverse=True)[:10]:
        print(f"  {name:40s} {total:7.1f} s for {n} calls, slowest call {worst:.1f} s")
    print()
    report(everything)


if __name__ == "__main__":
    main()
