"""The Bézier patches of a surface as polynomials in local parameters, and eq. 11 evaluated from them.

:class:`_PatchEvaluator` holds every patch in the monomial basis, so that its
derivatives anywhere (also a little outside its span) are small products;
:func:`_geodesic_rhs_fast` is the right-hand side of the geodesic equation in
few array operations.  Both are on the hot path of the integrators (a shooting
step of :func:`lab.geodesic_between` evaluates them for two paths at a time,
thousands of times), so they are written for a small per-call overhead.
"""

import numpy as np

from ...geometry import bezier
from ...geometry.derivatives import Derivatives, from_homogeneous


class _PatchEvaluator:
    """Derivatives of the Bézier patches of a (rational) B-spline surface at local parameters, extended beyond [0, 1].

    Built from :meth:`lab.BSplineSurface.bezier_nets` (or the one net of a
    :class:`lab.BezierSurface`).  Each patch is converted once from the
    Bernstein to the monomial basis in its local parameters ``(s, t)``, so that
    all six fields ``b, bu, bv, buu, buv, bvv`` come from one tensor
    contraction; being a polynomial (in homogeneous coordinates), a patch
    continues smoothly a little outside its span.  Chain rule: ``d/du = (1/h_u) d/ds``.

    For the geodesic equation the derivatives it needs are also kept as one
    coefficient block per patch, :attr:`vector_coeffs` ``(S_u, S_v, (p+1)(q+1), f d)``:
    the monomials :math:`s^i t^j` of a point times the block of its patch give
    ``x_u, x_v, x_uu, x_uv, x_uv, x_vv`` (polynomial patches, f = 6, d = 3) or
    the homogeneous ``X, X_u, X_v, X_uu, X_uv, X_uv, X_vv`` (rational, f = 7,
    d = 4) in one matrix product, the widths of the spans already applied.
    """

    def __init__(self, nets, weights, widths_u, widths_v):
        Pw = bezier.homogeneous(nets, weights)
        self.rational = weights is not None
        p, q = Pw.shape[-3] - 1, Pw.shape[-2] - 1
        self.coeffs = np.einsum("ik,jl,...ijd->...kld", _bernstein_to_monomial(p), _bernstein_to_monomial(q), Pw)
        self.powers = (np.arange(p + 1), np.arange(q + 1))
        self.inv_widths = (1.0 / widths_u, 1.0 / widths_v)
        # derivatives of the monomial coefficients: d/ds sum_i c_i s^i = sum_i (i+1) c_{i+1} s^i, times 1/h
        c = self.coeffs  # (Su, Sv, p+1, q+1, d)
        Ds, Dt = np.diag(np.arange(1.0, p + 1), 1), np.diag(np.arange(1.0, q + 1), 1)
        hu = self.inv_widths[0][:, None, None, None, None]
        hv = self.inv_widths[1][None, :, None, None, None]
        cu = np.einsum("ik,abkld->abild", Ds, c) * hu
        cv = np.einsum("jl,abkld->abkjd", Dt, c) * hv
        cuu = np.einsum("ik,abkld->abild", Ds, cu) * hu
        cuv = np.einsum("jl,abkld->abkjd", Dt, cu) * hv
        cvv = np.einsum("jl,abkld->abkjd", Dt, cv) * hv
        fields = ([c] if self.rational else []) + [cu, cv, cuu, cuv, cuv, cvv]
        if not self.rational:
            fields = [x[..., :3] for x in fields]
        block = np.stack(fields, axis=-2)  # (Su, Sv, p+1, q+1, f, d)
        Su, Sv = c.shape[:2]
        self.vector_coeffs = np.ascontiguousarray(block.reshape(Su, Sv, (p + 1) * (q + 1), -1))
        self._n_fields, self._dim = block.shape[-2:]
        self._exponents = max(p, q) + 1

    @staticmethod
    def _basis(x, k, inv_width):
        """Rows (x^k, d/du x^k, d²/du² x^k) for local parameters x: shape (n, 3, len(k))."""
        n, m = len(x), len(k)
        out = np.zeros((n, 3, m))
        powers = out[:, 0]
        powers[:, 0] = 1.0
        if m > 1:
            powers[:, 1:] = x[:, None]
            np.cumprod(powers, axis=1, out=powers)  # x^0, x^1, ..., x^p without pow()
        out[:, 1, 1:] = k[1:] * powers[:, :-1] * inv_width[:, None]
        out[:, 2, 2:] = k[2:] * (k[2:] - 1) * powers[:, :-2] * (inv_width * inv_width)[:, None]
        return out

    def table(self, iu, iv, su, sv):
        """All mixed derivatives up to order 2 in each direction: ``(k, 3, 3, d)``, ``[:, du, dv]`` (homogeneous)."""
        if len(self.powers[0]) == len(self.powers[1]):  # equal degrees: both directions in one go
            both = self._basis(np.concatenate([su, sv]), self.powers[0],
                               np.concatenate([self.inv_widths[0][iu], self.inv_widths[1][iv]]))
            Su, Sv = both[: len(su)], both[len(su):]
        else:
            Su = self._basis(su, self.powers[0], self.inv_widths[0][iu])
            Sv = self._basis(sv, self.powers[1], self.inv_widths[1][iv])
        C = self.coeffs[iu, iv]  # (k, p+1, q+1, d)
        k, p1, q1, d = C.shape
        T = np.matmul(Su, C.reshape(k, p1, q1 * d)).reshape(k, 3, q1, d)  # over i: (k, du, j, c)
        return np.matmul(Sv[:, None], T)  # over j: (k, du, dv, c), two batched small products

    def __call__(self, iu, iv, su, sv):
        X = self.table(iu, iv, su, sv)
        d = Derivatives(X[:, 0, 0], X[:, 1, 0], X[:, 0, 1], X[:, 2, 0], X[:, 1, 1], X[:, 0, 2])
        return from_homogeneous(d) if self.rational else d

    def vectors(self, C, local):
        """``x_u, x_v, x_uu, x_uv, x_uv, x_vv`` stacked, ``(k, 6, 3)``: what the geodesic equation needs.

        ``C`` (k, (p+1)(q+1), f d) are the blocks of :attr:`vector_coeffs` of
        each point's patch, ``local`` (k, 2) its local parameters.
        """
        k = len(local)
        p1, q1 = len(self.powers[0]), len(self.powers[1])
        x = np.empty((k, 2, self._exponents))
        x[:, :, 0] = 1.0
        x[:, :, 1:] = local[:, :, None]
        np.cumprod(x, axis=2, out=x)  # s^i and t^j
        monomials = (x[:, 0, :p1, None] * x[:, 1, None, :q1]).reshape(k, 1, p1 * q1)
        H = np.matmul(monomials, C).reshape(k, self._n_fields, self._dim)
        if not self.rational:
            return H
        # quotient rule (The NURBS Book eq. 4.20, as lab.derivatives.from_homogeneous), the mixed terms
        # w_i S_j + w_j S_i of the second derivatives from one outer product
        A, w = H[:, :, :3], H[:, :, 3:]
        w0 = w[:, 0:1]
        S = A[:, 0:1] / w0
        first = (A[:, 1:3] - w[:, 1:3] * S) / w0  # (k, 2, 3): S_u, S_v
        Q = w[:, 1:3, None] * first[:, None]  # (k, 2, 2, 3): w_i S_j
        mixed = (Q + Q.swapaxes(1, 2)).reshape(k, 4, 3)
        second = (A[:, 3:] - w[:, 3:] * S - mixed) / w0  # (k, 4, 3): S_uu, S_uv, S_vu, S_vv
        return np.concatenate([first, second], axis=1)


def _geodesic_rhs_fast(V, y, regular=False):
    r"""Eq. 11 from the vectors ``V = (x_u, x_v, x_uu, x_uv, x_uv, x_vv)`` (k, 6, 3), in few array operations.

    :math:`(u'', v'') = -g^{-1} h` with :math:`h_l = \mathbf a\cdot\mathbf x_l` and
    :math:`\mathbf a = \sum_{ij} \mathbf x_{ij}\, u'^i u'^j` (the symbols of the first
    kind contracted with the velocity before the metric is inverted): the same
    as :func:`lab.interrogation.geodesics.problem._geodesic_rhs`, with fewer
    operations per evaluation.  With ``regular=True`` also
    :math:`|\mathbf x_u\times\mathbf x_v| / (E + G)` (the regularity).
    """
    k = len(y)
    d = y[:, 2:4]
    T = V[:, :2]
    a = np.matmul((d[:, :, None] * d[:, None, :]).reshape(k, 1, 4), V[:, 2:])  # (k, 1, 3)
    M = np.matmul(T, np.concatenate([T, a], axis=1).swapaxes(1, 2))  # (k, 2, 3): [[E, F, x_u.a], [F, G, x_v.a]]
    E, F, G = M[:, 0, 0], M[:, 0, 1], M[:, 1, 1]
    hu, hv = M[:, 0, 2], M[:, 1, 2]
    det = E * G - F * F
    out = np.empty_like(y)
    out[:, :2] = d
    out[:, 2] = (F * hv - G * hu) / det
    out[:, 3] = (F * hu - E * hv) / det
    return (out, _regularity_fast(V)) if regular else out


def _regularity_fast(V):
    """|x_u x x_v| / (E + G) from the vectors of :func:`_geodesic_rhs_fast` (k, >= 2, 3)."""
    xu, xv = V[:, 0], V[:, 1]
    n = xu[:, _NEXT] * xv[:, _PREV] - xu[:, _PREV] * xv[:, _NEXT]  # x_u x x_v
    return np.sqrt(np.sum(n * n, axis=1)) / np.sum(xu * xu + xv * xv, axis=1)


_NEXT, _PREV = np.array([1, 2, 0]), np.array([2, 0, 1])


def _bernstein_to_monomial(n):
    """Matrix M with B_i^n(t) = sum_k M[i, k] t^k."""
    from math import comb

    M = np.zeros((n + 1, n + 1))
    for i in range(n + 1):
        for k in range(i, n + 1):
            M[i, k] = comb(n, i) * comb(n - i, k - i) * (-1) ** (k - i)
    return M
