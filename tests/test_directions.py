"""Principal directions (curvature(..., directions=True)), umbilics and lines of curvature.

References: sympy-exact eigenvectors of the Weingarten map, OpenCASCADE's GeomLProp_SLProps.CurvatureDirections
(skipped without cadquery-ocp-novtk), the ellipsoid's umbilics in closed form, the Monge forms of a lemon, a star and
a monstar, and lines of curvature of the torus (its meridians and parallels) and of the ellipsoid (on confocal
quadrics)."""

import warnings

import numpy as np
import pytest
import sympy as sp

import lab
from lab.geometry import directions


def _exact_directions(xyz, uv, point):
    """d1, d2, k1, k2 at a rational point from sympy: eigenvectors of S = G^-1 H, 40 digits."""
    u, v = uv
    X = sp.Matrix(xyz)
    Xu, Xv = X.diff(u), X.diff(v)
    Q = Xu.cross(Xv)
    W = sp.sqrt(Q.dot(Q))
    Gm = sp.Matrix([[Xu.dot(Xu), Xu.dot(Xv)], [Xu.dot(Xv), Xv.dot(Xv)]])
    Hm = sp.Matrix([[Q.dot(X.diff(u, 2)), Q.dot(Xu.diff(v))], [Q.dot(Xu.diff(v)), Q.dot(X.diff(v, 2))]]) / W
    sub = dict(zip(uv, point))
    S = (Gm.inv() * Hm).subs(sub)
    S = S.applyfunc(lambda x: sp.nsimplify(sp.N(x, 60), rational=True))
    out = []
    for k, mult, vecs in sorted(S.eigenvects(), key=lambda e: -float(sp.N(e[0]))):
        w = vecs[0]
        d = (w[0] * Xu + w[1] * Xv).subs(sub)
        d = np.array([float(sp.N(c, 40)) for c in d / sp.sqrt(d.dot(d))])
        out.append((float(sp.N(k, 40)), d))
    return out


def test_directions_match_sympy_exact_eigenvectors(rng):
    u, v = sp.symbols("u v", real=True)
    xyz = (u + v**2 / 3, v - u * v / 4, u**2 / 2 - u * v + v**3 / 5)
    s = lab.ParametricSurface.from_sympy(xyz, (u, v), ((-1, 1), (-1, 1)))
    for point in [(sp.Rational(1, 3), sp.Rational(-1, 2)), (sp.Rational(-3, 4), sp.Rational(2, 5)), (0, 0)]:
        (k1, e1), (k2, e2) = _exact_directions(xyz, (u, v), point)
        c = s.curvature(float(point[0]), float(point[1]), directions=True)
        assert abs(float(c.k1) - k1) <= 1e-13 and abs(float(c.k2) - k2) <= 1e-13
        assert abs(abs(c.d1 @ e1) - 1) <= 1e-13 and abs(abs(c.d2 @ e2) - 1) <= 1e-13  # up to the sign


def test_directions_frame_and_orientation(rng):
    s = lab.surfaces.practical()
    u, v = rng.uniform(0, 7, 2000), rng.uniform(0, 7, 2000)
    c = s.curvature(u, v, directions=True)
    d = s.derivatives(u, v)
    N = s.normal(u, v)

    def dot(a, b):
        return np.einsum("...i,...i->...", a, b)

    assert not c.umbilic.any() and not c.degenerate.any()
    for x in (c.d1, c.d2):
        np.testing.assert_allclose(np.linalg.norm(x, axis=-1), 1, atol=1e-14)
        assert np.max(np.abs(dot(x, N))) <= 1e-13
    assert np.max(np.abs(dot(c.d1, c.d2))) <= 1e-12
    assert np.all(dot(c.d1, d.bu) >= 0)  # the documented orientation: d1 . b_u >= 0, (d1, d2, N) right-handed
    np.testing.assert_allclose(np.cross(c.d1, c.d2), N, atol=1e-12)
    # the same K, H, k1, k2 as without directions, and the normal curvature II(d, d) is k
    plain = s.curvature(u, v)
    for f in ("K", "H", "k1", "k2"):
        np.testing.assert_array_equal(getattr(c, f), getattr(plain, f))
    ff = s.fundamental_forms(u, v)
    for x, k in ((c.d1, c.k1), (c.d2, c.k2)):
        # coordinates of x in (b_u, b_v): solve the 2x2 system of the first fundamental form
        rhs = np.stack([dot(x, d.bu), dot(x, d.bv)], -1)
        Gm = np.stack([np.stack([ff.E, ff.F], -1), np.stack([ff.F, ff.G], -1)], -2)
        w = np.linalg.solve(Gm, rhs[..., None])[..., 0]
        II = ff.e * w[:, 0] ** 2 + 2 * ff.f * w[:, 0] * w[:, 1] + ff.g * w[:, 1] ** 2
        np.testing.assert_allclose(II, k, atol=1e-12 * np.max(np.abs(k)))


def test_directions_broadcast_like_curvature():
    s = lab.surfaces.torus()
    c = s.curvature(np.linspace(0, 1, 4)[:, None], np.linspace(0, 1, 5)[None, :], directions=True)
    assert c.K.shape == (4, 5) and c.d1.shape == (4, 5, 3) and c.umbilic.shape == (4, 5)
    one = s.curvature(0.1, 0.2, directions=True)
    assert one.d1.shape == (3,) and one.umbilic.shape == ()


def test_umbilics_are_nan_and_flagged():
    for s in (lab.surfaces.sphere(2.0), lab.surfaces.plane()):
        c = s.curvature(np.array([0.3, 0.7]), np.array([0.4, 0.6]), directions=True)
        assert np.all(c.umbilic) and np.all(np.isnan(c.d1)) and np.all(np.isnan(c.d2))
    with pytest.warns(lab.DegeneratePointWarning):
        c = lab.surfaces.sphere().curvature(0.3, 0.0, directions=True)  # the pole: degenerate, limits for K, H
    assert c.degenerate and np.isnan(c.d1).all() and float(c.K) == pytest.approx(1.0, abs=1e-6)


def test_directions_match_opencascade(rng):
    pytest.importorskip("OCP")
    from OCP.GeomLProp import GeomLProp_SLProps
    from OCP.gp import gp_Dir

    from tests.occ_support import occt_surface

    for s in (lab.surfaces.practical(), lab.surfaces.ellipsoid(3, 2, 1), lab.surfaces.torus()):
        geom = occt_surface(s)
        (u0, u1), (v0, v1) = s.domain
        u = rng.uniform(u0, u1, 300)
        v = rng.uniform(v0 + 0.02 * (v1 - v0), v1 - 0.02 * (v1 - v0), 300)
        c = s.curvature(u, v, directions=True)
        props = GeomLProp_SLProps(geom, 2, 1e-9)
        worst = 0.0
        for k in range(len(u)):
            props.SetParameters(float(u[k]), float(v[k]))
            if not props.IsCurvatureDefined() or props.IsUmbilic():
                continue
            dmax, dmin = gp_Dir(), gp_Dir()
            props.CurvatureDirections(dmax, dmin)
            a = np.array([dmax.X(), dmax.Y(), dmax.Z()])
            b = np.array([dmin.X(), dmin.Y(), dmin.Z()])
            worst = max(worst, 1 - abs(a @ c.d1[k]), 1 - abs(b @ c.d2[k]))
            assert props.MaxCurvature() == pytest.approx(c.k1[k], abs=1e-10)
        assert worst <= 1e-10, (s, worst)  # 1 - |cos| ~ angle^2 / 2: angles below 1.5e-5 rad; in practice ~1e-16


def test_ellipsoid_umbilics_at_their_analytic_positions():
    for a, b, c in [(3, 2, 1), (1, 3, 2), (2.0, 1.2, 2.5)]:
        e = lab.surfaces.ellipsoid(a, b, c)
        found = lab.umbilics(e)
        ref = lab.surfaces.ellipsoid_umbilics(a, b, c)
        assert len(found) == 4 and [x.kind for x in found] == ["lemon"] * 4
        assert all(x.index == 0.5 and x.radial == 2 for x in found)
        for x in found:
            assert np.min(np.linalg.norm(ref - x.point, axis=1)) <= 1e-12
        # κ at an umbilic: with A > B > C, k = -A C / B^3 (outward normal: negative)
        A, B, C = sorted((a, b, c), reverse=True)
        for x in found:
            assert x.k == pytest.approx(-A * C / B**3, rel=1e-12)
            cd = e.curvature(*x.uv, directions=True)
            assert cd.umbilic and np.isnan(cd.d1).all()


@pytest.mark.parametrize(("cubic", "kind", "index", "radial"), [
    ("x**3 + x*y**2", "lemon", 0.5, 2),
    ("x**3 - 3*x*y**2", "star", -0.5, 6),
    ("2*x**3/5 + 4*x*y**2/5", "monstar", 0.5, 6),
])
def test_umbilic_types_from_monge_forms(cubic, kind, index, radial):
    # z = (x^2 + y^2)/2 + C(x, y): an umbilic at the origin whose type the cubic decides (Berry and Hannay 1977):
    # the traceless part of the Hessian is z = A w + B conj(w); |A| > |B| lemon/monstar, star otherwise
    x, y = sp.symbols("x y", real=True)
    s = lab.ParametricSurface.from_sympy((x, y, (x**2 + y**2) / 2 + sp.sympify(cubic, locals={"x": x, "y": y})), (x, y),
                                         ((-0.1, 0.1), (-0.13, 0.11)))
    found = lab.umbilics(s)
    assert len(found) == 1
    (um,) = found
    assert np.allclose(um.uv, 0, atol=1e-12) and um.kind == kind and um.index == index and um.radial == radial


def test_umbilics_refuse_a_sphere_and_a_non_surface():
    with pytest.raises(ValueError, match="umbilic on a whole region"):
        lab.umbilics(lab.surfaces.sphere())
    with pytest.raises(TypeError, match="surface must be a lab.Surface; got str"):
        lab.umbilics("sphere")


def test_lines_of_curvature_of_the_torus_are_meridians_and_parallels():
    t = lab.surfaces.torus(2, 1)
    c = t.curvature(0.3, 0.2, directions=True)
    d = t.derivatives(0.3, 0.2)
    for which in ("k1", "k2"):
        p = lab.line_of_curvature(t, (0.3, 0.2), which, 3.0)
        assert p.end == "length" and p.length == pytest.approx(3.0)
        # which parameter stays fixed follows from the direction: d parallel to b_u keeps v
        along_u = abs(getattr(c, "d" + which[1]) @ d.bu) > abs(getattr(c, "d" + which[1]) @ d.bv)
        fixed = p.uv[:, 1] if along_u else p.uv[:, 0]
        assert np.ptp(fixed) <= 1e-12
        # and the curve starts along +d
        step = p.points[1] - p.points[0]
        assert step @ getattr(c, "d" + which[1]) > 0


def _confocal(points, a, b, c):
    """The three roots λ of x²/(a²-λ) + y²/(b²-λ) + z²/(c²-λ) = 1 per point, sorted (one is 0 on the ellipsoid)."""
    A = np.array([a, b, c], dtype=float) ** 2
    out = []
    for X in points:
        total = -np.poly1d([-1, A[0]]) * np.poly1d([-1, A[1]]) * np.poly1d([-1, A[2]])
        for i in range(3):
            q = np.poly1d([X[i] ** 2])
            for j in range(3):
                if j != i:
                    q = q * np.poly1d([-1, A[j]])
            total = total + q
        out.append(np.sort(total.r.real))
    return np.array(out)


def test_lines_of_curvature_of_the_ellipsoid_lie_on_confocal_quadrics():
    e = lab.surfaces.ellipsoid(3, 2, 1)
    net = lab.lines_of_curvature(e, [(0.3, 0.3), (0.05, 0.6)], "k2", 3.0)
    for forward, backward in net:
        for p in (forward, backward):
            lam = _confocal(p.points, 3, 2, 1)
            assert np.min(np.ptp(lam, axis=0)) <= 1e-9  # one confocal parameter is constant along the line


def test_line_of_curvature_errors():
    e = lab.surfaces.ellipsoid(3, 2, 1)
    with pytest.raises(ValueError, match="which must be 'k1' or 'k2'.*got 'k3'"):
        lab.line_of_curvature(e, (0.3, 0.3), "k3", 1.0)
    um = lab.umbilics(e)[0]
    with pytest.raises(ValueError, match="is an umbilic"):
        lab.line_of_curvature(e, um.uv, "k1", 1.0)
    with pytest.raises(ValueError, match="length must be a positive"):
        lab.line_of_curvature(e, (0.3, 0.3), "k1", -1.0)


def test_line_of_curvature_stops_before_an_umbilic():
    # on the ellipsoid a line of curvature of the plane y = 0 family runs into the umbilic: start on the
    # principal section through the umbilics (the equator v = 1/2 of this parametrisation) next to one
    e = lab.surfaces.ellipsoid(3, 2, 1)
    um = lab.umbilics(e)[0]
    start = (um.uv[0] + 0.02, um.uv[1])
    c = e.curvature(*start, directions=True)
    d = e.derivatives(*start)
    which = "k1" if abs(c.d1 @ d.bu) > abs(c.d2 @ d.bu) else "k2"
    with pytest.warns(lab.UmbilicWarning, match="umbilic"):
        paths = [lab.line_of_curvature(e, start, which, 1.0, backward=b) for b in (False, True)]
    ends = sorted(p.end for p in paths)
    assert "umbilic" in ends
    p = next(p for p in paths if p.end == "umbilic")
    assert np.linalg.norm(p.points[-1] - um.point) <= 1e-3


def test_curvature_directions_record():
    c = directions.from_derivatives(lab.surfaces.practical().derivatives(1.0, 2.0))
    assert c._fields == ("K", "H", "k1", "k2", "degenerate", "d1", "d2", "umbilic")
    assert "d1=[" in repr(c) and c.classify().shape == ()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        lab.surfaces.practical().curvature(np.array([0.0, 7.0]), np.array([7.0, 0.0]), directions=True)
