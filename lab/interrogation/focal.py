r"""Generalized focal surfaces and parabolic lines (Choi & Lee, §4).

Hagen and Hahmann's generalized focal surface (Choi & Lee, eq. 8, reference [14])
offsets every point of the surface along its unit normal by a scaled function
of the principal curvatures,

.. math:: \mathbf F = \mathbf X + a\, f(\kappa_1, \kappa_2)\, \mathbf N ,

evaluated at the vertices of a tessellation (eq. 9).  The classical focal
sheets are the surfaces of the centres of principal curvature,
:math:`\mathbf F_i = \mathbf X + \mathbf N / \kappa_i`; with this library's
sign convention (:math:`\kappa` positive where the surface bends towards
:math:`\mathbf N`) they are the same points for either orientation.

Where the focal surface of the Gaussian curvature meets the surface, K changes
sign: those are the parabolic lines (Choi & Lee, §4, area B of colour
plate 2), traced as the zero set of K by :func:`parabolic_lines`.

Functions here take plain arrays; :mod:`lab.interrogation` applies them to
surfaces and PyVista meshes.
"""

import numpy as np

from ..geometry import validation as _v
from ..mesh.levels import level_lines

__all__ = ["FOCAL_FUNCTIONS", "focal_function", "focal_points", "focal_sheet", "parabolic_lines"]

#: The curvature functions of Choi & Lee, §4 (and the principal curvatures), by name.
#: The names match :class:`lab.CurvatureMode` values.
FOCAL_FUNCTIONS = {
    "gaussian": lambda k1, k2: k1 * k2,  # K
    "mean": lambda k1, k2: 0.5 * (k1 + k2),  # H
    "strain-energy": lambda k1, k2: k1**2 + k2**2,  # strain energy of curvature
    "k1": lambda k1, k2: k1,
    "k2": lambda k1, k2: k2,
}


def focal_function(function):
    """The callable ``f(k1, k2)`` for a name in :data:`FOCAL_FUNCTIONS` (or a :class:`lab.CurvatureMode`).

    A callable ``function`` is returned as it is.

    Raises
    ------
    ValueError
        Unknown name.
    TypeError
        Neither a string nor a callable.
    """
    if callable(function):
        return function
    if isinstance(function, str):
        name = getattr(function, "value", function)
        if name == "strain_energy":
            name = "strain-energy"
        if name in FOCAL_FUNCTIONS:
            return FOCAL_FUNCTIONS[name]
        listed = ", ".join(repr(n) for n in FOCAL_FUNCTIONS)
        raise ValueError(f"unknown focal function {function!r}; expected one of {listed} or a callable f(k1, k2)")
    raise TypeError(f"function must be a name or a callable f(k1, k2); got {type(function).__name__}")


def focal_points(X, N, k1, k2, scale=1.0, function="mean"):
    r"""Points of the generalized focal surface (Choi & Lee, eq. 9).

    .. math:: \mathbf F = \mathbf X + a\, f(\kappa_1, \kappa_2)\, \mathbf N

    Parameters
    ----------
    X : (k, 3) array_like
        Surface points.
    N : (k, 3) array_like
        Unit normals.
    k1, k2 : (k,) array_like
        Principal curvatures, signed with respect to ``N``.
    scale : float
        The scale factor ``a`` (curvatures are small: ``a`` makes the offset visible).
    function : str or callable
        ``"gaussian"`` (K), ``"mean"`` (H), ``"strain-energy"`` (κ1² + κ2²),
        ``"k1"``, ``"k2"``, or any ``f(k1, k2)`` returning an array of shape (k,).

    Returns
    -------
    F : (k, 3) ndarray
    f : (k,) ndarray
        The function values; the displacement along N is ``scale * f``.
    """
    f = _v.as_array(focal_function(function)(np.asarray(k1, float), np.asarray(k2, float)),
                    "the focal function's values", finite=False)
    X = np.asarray(X, dtype=float)
    if f.shape != X.shape[:1]:
        f = np.broadcast_to(f, X.shape[:1])
    return X + scale * f[:, None] * np.asarray(N, dtype=float), f


def focal_sheet(X, N, kappa, tol):
    r"""The classical focal sheet :math:`\mathbf X + \mathbf N / \kappa` (centres of curvature).

    Points where :math:`|\kappa| < \text{tol}` have their centre of curvature
    at (or near) infinity and are dropped.

    Parameters
    ----------
    X : (k, 3) array_like
    N : (k, 3) array_like
        Unit normals.
    kappa : (k,) array_like
        A principal curvature, signed with respect to ``N``.
    tol : float
        Smallest ``|kappa|`` kept (largest radius of curvature ``1/tol``).

    Returns
    -------
    F : (k, 3) ndarray
        NaN at dropped points.
    keep : (k,) bool ndarray
    """
    kappa = np.asarray(kappa, dtype=float)
    keep = np.isfinite(kappa) & (np.abs(kappa) >= tol)
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = np.where(keep, 1.0 / np.where(keep, kappa, 1.0), np.nan)
    return np.asarray(X, dtype=float) + rho[:, None] * np.asarray(N, dtype=float), keep


def parabolic_lines(points, triangles, K, tol):
    """The parabolic lines: where K changes sign, as polylines (zero set of the piecewise-linear K).

    Vertices with ``|K| <= tol`` count as ``K = 0`` (rounding noise); a line
    runs through them only where it separates elliptic (K > 0) from
    hyperbolic (K < 0) points, so flat or cylindrical regions give no lines
    (see :func:`lab.mesh.levels.level_lines`).  These are the curves along which
    the focal surface of K meets the surface (Choi & Lee, §4).

    Parameters
    ----------
    points : (k, 3) array_like
    triangles : (t, 3) int array_like
    K : (k,) array_like
    tol : float

    Returns
    -------
    list of (n, 3) ndarray
        Closed polylines repeat their first point at the end.
    """
    return level_lines(points, triangles, K, 0.0, tol=tol)
