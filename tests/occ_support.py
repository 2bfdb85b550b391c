"""OpenCASCADE (cadquery-ocp-novtk) versions of lab surfaces, for the tests and benchmarks/curvature.py (one copy)."""

import numpy as np


def occt_surface(s):
    """A ``Geom_BSplineSurface`` with the control points, weights, knots and degrees of a lab.BSplineSurface."""
    from OCP.Geom import Geom_BSplineSurface
    from OCP.gp import gp_Pnt
    from OCP.OCP.collections import Array1_double, Array1_int, Array2_double, Array2_gp_Pnt

    P = s.control_points
    nu, nv = P.shape[:2]
    poles = Array2_gp_Pnt(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            poles.SetValue(i + 1, j + 1, gp_Pnt(*map(float, P[i, j])))

    def knots(t):
        values, mult = np.unique(t, return_counts=True)
        K, M = Array1_double(1, len(values)), Array1_int(1, len(values))
        for k, (x, m) in enumerate(zip(values, mult)):
            K.SetValue(k + 1, float(x))
            M.SetValue(k + 1, int(m))
        return K, M

    (ku, mu), (kv, mv) = knots(s.knots_u), knots(s.knots_v)
    p, q = s.degree
    if s.weights is None:
        return Geom_BSplineSurface(poles, ku, kv, mu, mv, p, q, False, False)
    W = Array2_double(1, nu, 1, nv)
    for i in range(nu):
        for j in range(nv):
            W.SetValue(i + 1, j + 1, float(s.weights[i, j]))
    return Geom_BSplineSurface(poles, W, ku, kv, mu, mv, p, q, False, False)
