"""Peak memory of a call, for tests/test_memory.py, tests/test_tensor.py and benchmarks/curvature.py (one copy)."""

import gc
import tracemalloc


def traced_peak(call):
    """Peak memory traced by :mod:`tracemalloc` during ``call()`` above what was allocated before, and the result."""
    gc.collect()
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    result = call()
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    return peak, result
