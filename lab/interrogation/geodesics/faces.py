"""Paths on a face of a model (:class:`lab.Face`): on the face's surface, stopped where they leave its trimmed region.

A face of a part read by :func:`lab.read` is a surface restricted by trimming loops.  The geodesic and
normal-section ODEs are integrated on the surface as everywhere else (patch by patch, to the surface's own
boundary); afterwards each path is cut where it first leaves the face: the path's dense output is sampled
finely (:data:`TRIM_SAMPLES` per path, at least 8 per returned sample), and the first sample outside the
trimmed region is bisected against the last one inside, down to a relative arc length of 1e-13.  The
path then ends on the face's trimming loop as the lab stores it (a polyline in (u, v), see
:class:`lab.trimming.TrimmedSurface`), with ``end == "trim"`` and ``hit_boundary`` set.  A loop crossed and
re-crossed between two samples (a sliver narrower than the sampling step) is missed.

Everything goes through :func:`lab.interrogation.faces.face_surface`, the one place that says which surface a
face is evaluated on.
"""

import numpy as np

from ..faces import as_surface, check_inside, face_surface, is_face

__all__ = ["TRIM_SAMPLES", "as_surface", "check_inside", "face_surface", "is_face", "trim_ends"]

#: Samples per path (at least) at which a path is tested against the face's trimmed region before bisection.
TRIM_SAMPLES = 1024
#: Bisection stops when the bracket is this small relative to the path's length.
_BISECT_RTOL = 1e-13


def trim_ends(states, ends, stops, trim, wrap, *, n_check=TRIM_SAMPLES, stop_code):
    """Cut paths where they first leave the trimmed region ``trim``.

    Parameters
    ----------
    states : list of callables
        Each path's dense output ``s -> (k, m)`` states; the first two columns are (u, v), unwrapped.
    ends : list of float
        Arc length each path reached.
    stops : list of int
        Why each path ended.
    trim : lab.trimming.TrimmedSurface
    wrap : callable
        Unwrapped (u, v) into the domain (periodic directions).
    n_check : int
        Samples per path tested against the region.
    stop_code : int
        The stop code for a path cut at the trim.

    Returns
    -------
    ends, stops : lists, changed for the paths that leave the region.
    """
    ends, stops = list(ends), list(stops)

    def inside(uv):
        uv = wrap(np.asarray(uv, dtype=float).reshape(-1, 2))
        return np.asarray(trim.contains(uv[:, 0], uv[:, 1])).ravel()

    brackets = {}
    for k, (state, end) in enumerate(zip(states, ends)):
        if not end > 0:
            continue
        s = np.linspace(0.0, end, n_check)
        ok = inside(state(s)[:, :2])
        if ok.all():
            continue
        first = int(np.argmin(ok))  # the first sample outside (the start, s = 0, is inside)
        brackets[k] = [s[max(first - 1, 0)], s[first]]
    while brackets:
        keys = list(brackets)
        lo = np.array([brackets[k][0] for k in keys])
        hi = np.array([brackets[k][1] for k in keys])
        mid = 0.5 * (lo + hi)
        uv = np.concatenate([states[k](np.array([m]))[:, :2] for k, m in zip(keys, mid)])
        ok = inside(uv)
        for k, m, good in zip(keys, mid, ok):
            brackets[k][0 if good else 1] = m
            if brackets[k][1] - brackets[k][0] <= _BISECT_RTOL * max(ends[k], 1e-300):
                ends[k], stops[k] = brackets[k][0], stop_code
                del brackets[k]
    return ends, stops
