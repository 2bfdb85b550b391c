r"""Umbilics: the points where κ1 = κ2 and the principal directions are undefined, with their index and type.

In an orthonormal frame :math:`\mathbf e_1 = \mathbf b_u/|\mathbf b_u|`,
:math:`\mathbf e_2 = \mathbf N\times\mathbf e_1` of the tangent plane the
second fundamental form has the matrix :math:`s_{ij} = \mathrm{II}(\mathbf e_i, \mathbf e_j)`;
its traceless part

.. math:: z = \tfrac12(s_{11} - s_{22}) + i\,s_{12} = \tfrac12(\kappa_1 - \kappa_2)\,e^{2i\theta}

(θ the angle of ``d1`` from :math:`\mathbf e_1`) vanishes exactly at umbilics.
They are found as the zeros of this complex function: local minima of
:math:`|z|` on a sample grid, refined by Powell's hybrid method
(:func:`scipy.optimize.root`), kept where :math:`|z|` is zero to the
tolerance of :func:`lab.geometry.directions.from_derivatives`.

Index and type (Darboux; Berry and Hannay 1977): on a small circle around
the umbilic, ``d1`` turns by half the winding of :math:`z`: index +1/2
(lemon or monstar) or −1/2 (star).  Lemon and monstar differ in how many
lines of curvature run straight into the umbilic: the directions φ on the
circle at which a principal direction is radial are the zeros of
:math:`\sin 2(\theta(\varphi) - \varphi)`: 2 for a lemon (one line of each
family), 6 for a star and a monstar (three of each).
"""

from dataclasses import dataclass
from itertools import pairwise

import numpy as np

from ..geometry import validation as _v
from ..geometry.curvature import unit_normal
from ..geometry.directions import UMBILIC_RTOL
from ..model.surface import Surface
from . import export

__all__ = ["Umbilic", "Umbilics", "traceless", "umbilics"]

#: Points on the circle around an umbilic at which the index and the radial directions are read.
CIRCLE_POINTS = 720


@dataclass(frozen=True)
class Umbilic:
    """An umbilic point.

    Attributes
    ----------
    uv : (float, float)
    point : (3,) ndarray
    k : float
        The curvature there (κ1 = κ2).
    index : float
        +0.5 or -0.5: how often ``d1`` turns (in half turns / 2) on a small circle around the point.
    kind : str
        ``"lemon"``, ``"monstar"`` or ``"star"``.
    radial : int
        Directions on the circle in which a principal direction points at the umbilic (2 or 6).
    """

    uv: tuple
    point: np.ndarray
    k: float
    index: float
    kind: str
    radial: int

    def __repr__(self):
        return (f"Umbilic({self.kind}, index {self.index:+g}, uv=({self.uv[0]:.6g}, {self.uv[1]:.6g}), "
                f"point={np.array2string(self.point, precision=6)}, k={self.k:.6g})")

    def __str__(self):
        """One line for a person, in the lab's language (decimal commas in German, no ``-0`` or ``e-16``)."""
        from ..i18n import N_, _, decimal, language

        kinds = {"lemon": N_("lemon"), "monstar": N_("monstar"), "star": N_("star")}
        sep = "; " if language() == "de" else ", "

        def num(x):
            return f"{float(np.round(x, 6)) + 0.0:.6g}"  # + 0.0: -0 (rounding noise of a zero) prints as 0

        return decimal(_("umbilic ({kind}, index {index}) at ({point}), (u, v) = ({uv}), κ = {k}").format(
            kind=_(kinds.get(self.kind, self.kind)), index=f"{self.index:+g}", point=sep.join(map(num, self.point)),
            uv=sep.join(map(num, self.uv)), k=num(self.k)))


class Umbilics(list):
    """The umbilics :func:`umbilics` found: a list of :class:`Umbilic`, which also exports
    (``to_csv(path)``, ``to_pandas()``: one row per umbilic) and keeps the search's ``rtol``."""

    rtol = UMBILIC_RTOL

    def _table(self):
        from ..i18n import _

        columns = {"u": [float(p.uv[0]) for p in self], "v": [float(p.uv[1]) for p in self]}
        columns.update({c: [float(p.point[k]) for p in self] for k, c in enumerate("xyz")})
        columns.update({"k": [float(p.k) for p in self], "index": [float(p.index) for p in self],
                        "kind": [p.kind for p in self], "radial": [int(p.radial) for p in self]})
        length = _("length")
        units = {"u": _("parameter"), "v": _("parameter"), "x": length, "y": length, "z": length, "k": f"1/{length}",
                 "index": _("turns of d1 around the point")}
        return export.Table(_("umbilics"), columns, units, {
            "tolerance": _("|κ1 − κ2| <= {rtol} x the curvature scale").format(rtol=repr(float(self.rtol)))})

    to_csv = export.to_csv
    to_pandas = export.to_pandas


def traceless(d):
    """The traceless part ``z`` (complex) of the second fundamental form in the frame ``e1, e2``, the mean
    curvature ``H`` and the scale of curvature (|H| + second derivatives / (E + G)) used by the umbilic tolerance.

    ``d`` is a :class:`~lab.derivatives.Derivatives` record; results have its batch shape.
    """
    bu, bv, buu, buv, bvv = d[1:]
    E, F, G = (np.einsum("...i,...i->...", x, y) for x, y in ((bu, bu), (bu, bv), (bv, bv)))
    Q = np.cross(bu, bv)
    W = np.linalg.norm(Q, axis=-1)
    e, f, g = (np.einsum("...i,...i->...", Q, x) / W for x in (buu, buv, bvv))
    # parameter coordinates of e1 = b_u/|b_u| and e2 = (b_v - F/E b_u)/|.| (= N x e1)
    a1 = 1 / np.sqrt(E)
    n2 = 1 / np.sqrt(G - F * F / E)
    c2u, c2v = -F / E * n2, n2
    s11 = e * a1 * a1
    s12 = a1 * (e * c2u + f * c2v)
    s22 = e * c2u * c2u + 2 * f * c2u * c2v + g * c2v * c2v
    scale = np.abs(0.5 * (s11 + s22)) + (_norm(buu) + 2 * _norm(buv) + _norm(bvv)) / (E + G)
    return 0.5 * (s11 - s22) + 1j * s12, 0.5 * (s11 + s22), scale


def _norm(x):
    return np.linalg.norm(x, axis=-1)


def _z_at(surface, u, v):
    with np.errstate(invalid="ignore", divide="ignore"):  # degenerate points (poles) give NaN: no umbilic there
        return traceless(surface.derivatives(u, v))


def _into_domain(surface, x):
    """Parameters wrapped in periodic directions and clipped to the domain otherwise."""
    out = []
    for xi, (a, b), periodic in zip(x, surface.domain, surface.periodic):
        out.append(a + np.mod(xi - a, b - a) if periodic else np.clip(xi, a, b))
    return np.array(out, dtype=float)


def umbilics(surface, *, n=64, rtol=UMBILIC_RTOL):
    """The umbilics of ``surface``: where κ1 = κ2, each with its index and type (see the module docstring).

    Parameters
    ----------
    surface : lab.Surface
    n : int
        Samples per knot span (or per domain side for analytic surfaces) of the search grid.
    rtol : float
        An umbilic has |κ1 − κ2| <= rtol × the curvature scale (as ``curvature(..., directions=True)``).

    Returns
    -------
    Umbilics
        A list of :class:`Umbilic` sorted by (u, v), with ``to_csv(path)`` and ``to_pandas()``.

    Raises
    ------
    ValueError
        If the surface is umbilic on a whole region (a sphere, a plane): there are no isolated umbilics.

    Examples
    --------
    >>> import lab
    >>> [u.kind for u in lab.umbilics(lab.surfaces.ellipsoid(3, 2, 1))]
    ['lemon', 'lemon', 'lemon', 'lemon']
    """
    from scipy.optimize import root

    if not isinstance(surface, Surface):
        raise TypeError(f"surface must be a lab.Surface; got {type(surface).__name__}")
    n = _v.as_positive_int(n, "n", minimum=4, maximum=100_000)
    (u0, u1), (v0, v1) = surface.domain
    su, sv = _spans(surface)
    uu = np.unique(np.concatenate([np.linspace(a, b, n + 1) for a, b in su]))
    vv = np.unique(np.concatenate([np.linspace(a, b, n + 1) for a, b in sv]))
    z, _, scale = _z_at(surface, uu[:, None], vv[None, :])
    with np.errstate(invalid="ignore", divide="ignore"):  # degenerate points: NaN, left out below
        m = np.abs(z) / scale
    finite = np.isfinite(m)
    if np.mean(finite & (m <= rtol)) > 0.5:
        raise ValueError("the surface is umbilic on a whole region (κ1 = κ2 at most sample points, as on a sphere "
                         "or a plane): it has no isolated umbilics")
    mm = np.where(finite, m, np.inf)
    pad = np.pad(mm, 1, mode="edge")
    neighbours = np.stack([pad[1 + di : pad.shape[0] - 1 + di, 1 + dj : pad.shape[1] - 1 + dj]
                           for di in (-1, 0, 1) for dj in (-1, 0, 1) if (di, dj) != (0, 0)])
    candidates = np.argwhere(finite & (mm <= neighbours.min(axis=0)) & (mm < 0.2))
    found = []
    width = np.array([u1 - u0, v1 - v0])
    for i, j in candidates:
        x0 = np.array([uu[i], vv[j]])

        def F(x):
            x = _into_domain(surface, x)
            zz, _, sc = _z_at(surface, x[0], x[1])
            with np.errstate(invalid="ignore", divide="ignore"):
                r = zz / sc
            return [float(r.real), float(r.imag)] if np.isfinite(r) else [1e3, 1e3]

        sol = root(F, x0, method="hybr", options={"xtol": 1e-14})
        x = _into_domain(surface, sol.x)
        zz, Hx, sc = _z_at(surface, x[0], x[1])
        if not (np.isfinite(zz) and abs(zz) <= rtol * sc):
            continue
        if any(np.all(np.abs(_unwrap(surface, x - y)) <= 1e-7 * width) for y, _ in found):
            continue
        found.append((x, float(Hx)))
    out = [_classify(surface, x, k) for x, k in found]
    found = Umbilics(sorted(out, key=lambda p: p.uv))
    found.rtol = rtol
    return found


def _unwrap(surface, duv):
    (u0, u1), (v0, v1) = surface.domain
    period = np.array([u1 - u0, v1 - v0])
    periodic = np.array(surface.periodic, dtype=bool)
    return np.where(periodic, duv - period * np.round(duv / period), duv)


def _spans(surface):
    """The knot spans of a spline surface per direction, else the domain."""
    (u0, u1), (v0, v1) = surface.domain
    knots = getattr(surface, "knots_u", None)
    if knots is None:
        return [(u0, u1)], [(v0, v1)]
    out = []
    for k, (a, b) in zip((surface.knots_u, surface.knots_v), surface.domain):
        t = np.unique(k[(k >= a) & (k <= b)])
        out.append(list(pairwise(t)))
    return out


def _classify(surface, x, k):
    """Index and type of the umbilic at parameters ``x`` (see the module docstring)."""
    d = surface.derivatives(x[0], x[1])
    bu, bv = d.bu, d.bv
    e1 = bu / np.linalg.norm(bu)
    N = unit_normal(bu, bv)[0]  # the library's one (a copy of its line here made release refuse the hand-out)
    e2 = np.cross(N, e1)
    J = np.array([[bu @ e1, bv @ e1], [bu @ e2, bv @ e2]])  # tangent-plane coordinates of (du, dv)
    size = np.linalg.norm(np.ptp(surface.evaluate(*surface.grid(9, 9)).reshape(-1, 3), axis=0))
    rho = 1e-3 / (abs(k) + 1 / size)
    # half a step off the axes, so that no sample falls on a zero of sin 2(θ - φ) of a symmetric umbilic
    phi = (np.arange(CIRCLE_POINTS) + 0.5) * (2 * np.pi / CIRCLE_POINTS)
    duv = np.linalg.solve(J, rho * np.stack([np.cos(phi), np.sin(phi)]))
    u, v = _into_domain(surface, (x[0] + duv[0], x[1] + duv[1]))
    z, _, _ = _z_at(surface, u, v)
    winding = np.sum(np.angle(np.roll(z, -1) / z)) / (2 * np.pi)  # the turns of z = (κ1 - κ2)/2 e^{2iθ}
    index = 0.5 * round(float(winding))
    s = np.sin(np.angle(z) - 2 * phi)
    radial = int(np.count_nonzero(np.sign(s) != np.sign(np.roll(s, 1))))
    kind = "star" if index < 0 else ("lemon" if radial <= 2 else "monstar")
    point = surface.evaluate(x[0], x[1])
    return Umbilic((float(x[0]), float(x[1])), point, float(k), index, kind, radial)
