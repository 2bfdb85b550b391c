"""A face's orientation: the curvature seen from the opposite normal (a ``TopAbs_REVERSED`` face)."""

from ...geometry import curvature as _curv

__all__ = ["flip"]


def flip(c):
    """The curvature of the opposite normal: K stays, H changes sign, k1 and k2 change sign and order."""
    return _curv.Curvature(c.K, -c.H, -c.k2, -c.k1, c.degenerate)
