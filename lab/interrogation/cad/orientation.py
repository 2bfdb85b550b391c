"""A face's orientation: the curvature seen from the opposite normal (a ``TopAbs_REVERSED`` face)."""

from ...geometry import curvature as _curv
from ...geometry import directions as _dirs

__all__ = ["flip"]


def flip(c):
    """The curvature of the opposite normal: K stays, H changes sign, k1 and k2 change sign and order.

    With principal directions (:class:`lab.directions.CurvatureDirections`) ``d1`` and ``d2`` change
    places with their curvatures.
    """
    if isinstance(c, _dirs.CurvatureDirections):
        return _dirs.CurvatureDirections(c.K, -c.H, -c.k2, -c.k1, c.degenerate, c.d2, c.d1, c.umbilic)
    return _curv.Curvature(c.K, -c.H, -c.k2, -c.k1, c.degenerate)
