"""lab.continuity: G0/G1/G2 across knot lines and patch borders.

References: closed forms (two circular arcs of radii r1, r2 joined tangentially and extruded: g1 = 0,
g2 = |1/r1 - 1/r2|), one-sided limits of the public evaluator approached from both sides, and OpenCASCADE's
LocalAnalysis_SurfaceContinuity on the two Bézier pieces and on the shared edges of OpenCASCADE's sample parts
(one read per file; skipped without cadquery-ocp-novtk or Debian's occt-misc)."""

import os
from pathlib import Path

import numpy as np
import pytest

import lab
from lab.interrogation.continuity import TOLERANCES

C15 = np.cos(np.radians(15))  # the middle weight of a 30° arc: cos(half its angle)


def two_arcs(r1=1.0, r2=2.5, length=2.0):
    """Arcs of radius r1 (120°..90°) and r2 (90°..60°) meeting tangentially at the top, extruded along y.

    An exact degree-(2, 1) NURBS with the join at the double knot u = 1."""
    def arc(c, r, a0, a1):
        a0, a1 = np.radians(a0), np.radians(a1)
        p0 = c + r * np.array([np.cos(a0), np.sin(a0)])
        p2 = c + r * np.array([np.cos(a1), np.sin(a1)])
        mid = (a0 + a1) / 2
        p1 = c + r / np.cos((a1 - a0) / 2) * np.array([np.cos(mid), np.sin(mid)])
        return p0, p1, p2

    a = arc(np.array([0.0, 0.0]), r1, 120, 90)
    b = arc(np.array([0.0, r1 - r2]), r2, 90, 60)
    xz = np.array([a[0], a[1], a[2], b[1], b[2]])
    P = np.zeros((5, 2, 3))
    P[:, :, 0], P[:, :, 2] = xz[:, None, 0], xz[:, None, 1]
    P[:, 1, 1] = length
    w = np.repeat(np.array([1, C15, 1, C15, 1])[:, None], 2, axis=1)
    return lab.BSplineSurface(P, [0, 0, 0, 1, 1, 2, 2, 2], [0, 0, 1, 1], 2, 1, weights=w)


def crease(height=0.05):
    """A bicubic B-spline with a triple knot at u = 0.5 (C0) and the control point row there lifted: a kink."""
    x = np.linspace(0, 1, 7)
    X, Y = np.meshgrid(x, np.linspace(0, 1, 5), indexing="ij")
    Z = 0.2 * np.sin(2 * X) * np.cos(Y)
    Z[3] += height
    P = np.stack([X, Y, Z], axis=-1)
    return lab.BSplineSurface(P, [0, 0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1, 1], [0, 0, 0, 0, 0.5, 1, 1, 1, 1], 3, 3)


def test_smooth_spline_surfaces_are_g2_everywhere():
    rep = lab.continuity(lab.surfaces.practical())
    assert len(rep.edges) == 12 and rep.achieved == "G2"
    assert {(e.direction, e.value) for e in rep.edges} == {(d, float(k)) for d in "uv" for k in range(1, 7)}
    assert all(e.kind == "knot line" and e.multiplicity == 1 and e.g0 == 0 for e in rep.edges)
    assert max(e.g1 for e in rep.edges) <= 1e-11 and max(e.g2 for e in rep.edges) <= 1e-12
    torus = lab.continuity(lab.surfaces.torus())
    assert torus.achieved == "G3" and sum(e.kind == "seam" for e in torus.edges) == 2


def test_tangent_arcs_are_g1_with_the_curvature_jump_of_their_radii():
    r1, r2 = 1.0, 2.5
    rep = lab.continuity(two_arcs(r1, r2))
    (edge,) = rep.edges
    assert (edge.kind, edge.direction, edge.value, edge.multiplicity) == ("knot line", "u", 1.0, 2)
    assert edge.g0 <= 1e-15 and edge.g1 <= 1e-12
    assert edge.g2 == pytest.approx(abs(1 / r1 - 1 / r2), rel=1e-13)
    assert np.allclose(edge.jump, abs(1 / r1 - 1 / r2), rtol=1e-13)
    assert edge.achieved == "G1" and rep.achieved == "G1"
    np.testing.assert_allclose(edge.worst[[0, 2]], [0.0, r1], atol=1e-14)  # on the join line x = 0, z = r1


def test_a_kink_is_g0_and_its_angle_is_the_one_sided_limit():
    s = crease()
    rep = lab.continuity(s, samples=9)
    kink = next(e for e in rep.edges if e.direction == "u")
    smooth = next(e for e in rep.edges if e.direction == "v")
    assert kink.multiplicity == 3 and kink.achieved == "G0" and smooth.achieved == "G2"
    # one-sided limits through the public evaluator, approached from both sides (error O(h))
    v = np.concatenate([np.linspace(0, 0.5, 9), np.linspace(0.5, 1, 9)])  # the samples of the two v-spans
    angles = []
    for h in (1e-6, 1e-7):
        nl, nr = s.normal(np.full_like(v, 0.5 - h), v), s.normal(np.full_like(v, 0.5 + h), v)
        angles.append(np.degrees(np.arccos(np.clip(np.einsum("ij,ij->i", nl, nr), -1, 1))))
    assert 5 < kink.g1 < 90
    np.testing.assert_allclose(kink.angle, angles[1], atol=1e-4)
    assert abs(angles[1] - kink.angle).max() < abs(angles[0] - kink.angle).max()  # converging to ours
    assert rep.worst is kink and rep.achieved == "G0"


def test_a_gap_achieves_none():
    patches = lab.surfaces.practical().to_bezier_patches()
    patches.control_points[10] += [0.0, 0.0, 0.01]  # move one patch up: four borders open
    rep = lab.continuity(patches)
    bad = [e for e in rep.edges if e.achieved == "none"]
    assert len(bad) == 4 and all(10 in e.faces for e in bad)
    assert all(e.g0 == pytest.approx(0.01, rel=1e-12) for e in bad)
    assert rep.achieved == "none" and rep.worst in bad


def test_patches_without_a_grid_are_matched_by_their_borders(rng):
    grid = lab.surfaces.practical().to_bezier_patches()
    order = rng.permutation(len(grid))
    P = grid.control_points[order].copy()
    P[3] = P[3].transpose(1, 0, 2)[::-1]  # one patch with swapped and reversed parameters
    loose = lab.BezierPatches(P)
    rep_grid, rep_loose = lab.continuity(grid), lab.continuity(loose)
    assert len(rep_grid.edges) == len(rep_loose.edges) == 2 * 6 * 7
    assert rep_loose.achieved == "G2"
    assert max(e.g2 for e in rep_loose.edges) <= 1e-12


def test_table_and_tolerances():
    rep = lab.continuity(lab.surfaces.hood())
    text = rep.table()
    first = text.splitlines()[2]
    assert first.startswith("knot line v = 3") and first.rstrip().endswith("G1")  # the crease first
    assert "tolerances: G0 gap <=" in text and f"G1 angle <= {TOLERANCES['g1']:g} deg" in text
    loose = lab.continuity(lab.surfaces.hood(), tol_g2=1e3)
    assert loose.achieved == "G2"
    with pytest.raises(ValueError, match="tol_g1 must be a finite number >= 0; got -1.0"):
        lab.continuity(lab.surfaces.hood(), tol_g1=-1)
    with pytest.raises(TypeError, match="continuity needs a lab.BSplineSurface, a lab.BezierPatches or a lab.Model"):
        lab.continuity(lab.surfaces.catenoid())
    with pytest.raises(ValueError, match="samples"):
        lab.continuity(lab.surfaces.hood(), samples=1)


def _occ_patch(net, weights):
    from tests.occ_support import occt_surface

    m, n = net.shape[0] - 1, net.shape[1] - 1
    return occt_surface(lab.BSplineSurface(net, [0] * (m + 1) + [1] * (m + 1), [0] * (n + 1) + [1] * (n + 1), m, n,
                                           weights=weights))


def test_against_opencascade_local_analysis():
    pytest.importorskip("OCP")
    from OCP.GeomAbs import GeomAbs_Shape
    from OCP.LocalAnalysis import LocalAnalysis_SurfaceContinuity

    for s, check_g2 in ((two_arcs(), True), (crease(), False)):
        nets, w, _, _ = s.bezier_nets()
        A = _occ_patch(nets[0, 0], None if w is None else w[0, 0])
        B = _occ_patch(nets[1, 0], None if w is None else w[1, 0])
        rep = lab.continuity(s, samples=7)
        edge = next(e for e in rep.edges if e.direction == "u")
        t = np.linspace(0, 1, 7)
        for k, tk in enumerate(t):
            la = LocalAnalysis_SurfaceContinuity(A, 1.0, float(tk), B, 0.0, float(tk), GeomAbs_Shape.GeomAbs_G2)
            assert la.IsDone()
            assert la.C0Value() == pytest.approx(edge.gap[k], abs=1e-14)
            assert np.radians(edge.angle[k]) == pytest.approx(la.G1Angle(), abs=1e-10)
            if check_g2:
                # OpenCASCADE's gap is half the largest normal-curvature difference (|dη| + amplitude)/2; with
                # the principal directions the same on both sides it is |1/r1 - 1/r2| / 2
                assert 2 * la.G2CurvatureGap() == pytest.approx(edge.jump[k], rel=1e-12)


# -- a model's face edges, against OpenCASCADE at every sample of every shared edge ---------------------------

DATA = Path(os.environ.get("LAB_OCC_DATA", "/usr/share/opencascade/data"))
MODEL_FILES = ("occ/wing.brep", "occ/shell1.brep", "step/linkrods.step")


@pytest.fixture(scope="module")
def model_reports():
    """Each sample file read once (lab.read) and its continuity report."""
    pytest.importorskip("OCP")
    if not (DATA / "occ" / "wing.brep").exists():
        pytest.skip(f"OpenCASCADE's sample parts (Debian occt-misc) are not in {DATA}")
    out = {}
    for name in MODEL_FILES:
        model = lab.read(DATA / name)
        out[name] = (model, lab.continuity(model))
    return out


def _file_surfaces(path):
    """The file's own surfaces (BRep_Tool.Surface of each face, in the reader's face order): the edges' (u, v)
    are the file's parameters, so OpenCASCADE evaluates the file's geometry there, not the lab's NURBS."""
    from OCP.BRep import BRep_Tool

    from tests.occ_support import occ_faces

    return [BRep_Tool.Surface_s(f) for f in occ_faces(path)]


def _occ_reference(model, edge, surfaces):
    """At the edge's samples: OpenCASCADE's C0Value and G1Angle (LocalAnalysis_SurfaceContinuity on the two faces'
    surfaces at the edge's (u, v)), the angle between the faces' oriented normals and the jump of the normal
    curvature across the edge by Euler's formula from GeomLProp_SLProps's principal curvatures and directions."""
    from OCP.GeomAbs import GeomAbs_Shape
    from OCP.GeomLProp import GeomLProp_SLProps
    from OCP.gp import gp_Dir
    from OCP.LocalAnalysis import LocalAnalysis_SurfaceContinuity

    faces = [model.face(i) for i in edge.faces]
    geoms = [surfaces[i] for i in edge.faces]
    signs = [-1.0 if f.reversed else 1.0 for f in faces]
    rows = []
    for k in range(len(edge.t)):
        (ua, va), (ub, vb) = edge.uv[0][k], edge.uv[1][k]
        la = LocalAnalysis_SurfaceContinuity(geoms[0], float(ua), float(va), geoms[1], float(ub), float(vb),
                                             GeomAbs_Shape.GeomAbs_G2)
        if not la.IsDone():  # a sample where a side has no normal or curvature (a collapsed border)
            rows.append((np.nan,) * 6)
            continue
        t = edge.tangents[k] / np.linalg.norm(edge.tangents[k])
        normals, kn = [], []
        for g, s, (u, v) in zip(geoms, signs, ((ua, va), (ub, vb))):
            p = GeomLProp_SLProps(g, float(u), float(v), 2, 1e-9)
            assert p.IsCurvatureDefined()  # it computes the curvatures: asked first, later answers agree
            n = p.Normal()
            N = s * np.array([n.X(), n.Y(), n.Z()])
            c = np.cross(N, t)
            if p.IsUmbilic():
                kn.append(s * p.MaxCurvature())
            else:
                dmax, dmin = gp_Dir(), gp_Dir()
                p.CurvatureDirections(dmax, dmin)
                dmax, dmin = (np.array([d.X(), d.Y(), d.Z()]) for d in (dmax, dmin))
                kn.append(s * (p.MaxCurvature() * (c @ dmax) ** 2 + p.MinCurvature() * (c @ dmin) ** 2))
            normals.append(N)
        angle = np.degrees(np.arctan2(np.linalg.norm(np.cross(*normals)), normals[0] @ normals[1]))
        pa, pb = (g.Value(float(u), float(v)) for g, (u, v) in zip(geoms, ((ua, va), (ub, vb))))
        d = np.array([pa.X() - pb.X(), pa.Y() - pb.Y(), pa.Z() - pb.Z()])
        across = np.linalg.norm(d - (d @ t) * t)  # the distance across the edge: a shift along it is no gap
        rows.append((la.C0Value(), np.degrees(la.G1Angle()), angle, abs(kn[0] - kn[1]), max(map(abs, kn)), across))
    return np.array(rows).T


def test_model_edges_against_opencascade(model_reports):
    """Folded angle equal to LocalAnalysis_SurfaceContinuity's, the gap to its points' distance across the edge
    (C0Value without the part along the edge's tangent, where a pcurve slips), the oriented angle and the curvature jump
    GeomLProp_SLProps's, at every sample of every shared edge of shell1.brep (sewn: its faces share no edges
    in the file) and linkrods.step, OpenCASCADE evaluating the file's own surfaces at the edges' (u, v)."""
    checked, skipped = 0, 0
    worst = {"occ/shell1.brep": 0.0, "step/linkrods.step": 0.0, "analytic": 0.0}
    for name in ("occ/shell1.brep", "step/linkrods.step"):
        model, rep = model_reports[name]
        assert len(rep.edges) == len(model.edges)
        L = rep.size
        surfaces = _file_surfaces(DATA / name)
        for edge, ours in zip(model.edges, rep.edges):
            assert ours.kind == "face edge" and ours.faces == edge.faces
            c0, g1, angle, jump, kn, across = _occ_reference(model, edge, surfaces)
            done = np.isfinite(c0)
            skipped += np.count_nonzero(~done)
            ours_gap, ours_angle, ours_jump = ours.gap[done], ours.angle[done], ours.jump[done]
            c0, g1, angle, jump, kn, across = (x[done] for x in (c0, g1, angle, jump, kn, across))
            # C0Value is the distance at the two (u, v); the lab's gap leaves out the part along the edge
            np.testing.assert_allclose(ours_gap, across, atol=1e-12 * L, err_msg=f"{name} {edge.faces}: gap")
            assert np.all(ours_gap <= c0 + 1e-12 * L)
            folded = np.minimum(ours_angle, 180 - ours_angle)
            np.testing.assert_allclose(folded, g1, atol=1e-6, err_msg=f"{name} {edge.faces}: G1 angle")
            np.testing.assert_allclose(ours_angle, angle, atol=1e-6, err_msg=f"{name} {edge.faces}: oriented angle")
            ok = np.isfinite(ours_jump)
            # relative to the curvature scale of the point (GeomLProp differentiates the same NURBS)
            relative = (np.abs(ours_jump - jump) / (kn + 1 / L))[ok]
            worst[name] = max(worst[name], relative.max(initial=0))
            if any(model.face(i).kind != "BSplineSurface" for i in edge.faces):
                worst["analytic"] = max(worst["analytic"], relative.max(initial=0))
            checked += np.count_nonzero(done)
    print(f"{checked} edge samples ({skipped} where OpenCASCADE is not done); largest relative G2 differences "
          f"{worst}")
    assert checked > 5000 and skipped < 0.01 * checked
    # measured: 1.3e-9 on shell1's B-spline faces; 2.3e-6 on linkrods.step's 67 edges with an analytic face
    # (their (u, v) are the file's pcurves, no projection); 6.3e-5 at linkrods.step's B-spline|B-spline edges
    # where the faces meet at 0.85 degrees, unchanged by the file's parameters (B-spline faces keep theirs):
    # not explained yet (suspected: the reference takes the normal curvature across the 3-D edge tangent,
    # which lies in neither tangent plane exactly), hence the loose bound there
    assert worst["occ/shell1.brep"] <= 1e-8 and worst["analytic"] <= 1e-5 and worst["step/linkrods.step"] <= 2e-4


def test_model_edges_known_sharp_and_tangent(model_reports):
    model, rep = model_reports["occ/wing.brep"]
    # its four faces share no edges in the file: sewn (at 1e-6 of its size) they share six, two of them
    # tangent (the leading edge), four creases (the trailing edges, whose faces' normals are 165 degrees apart)
    assert model.sewn == pytest.approx(1e-6 * rep.size, rel=1e-6) and len(rep.edges) == 6
    assert sorted(e.achieved for e in rep.edges) == ["G0"] * 4 + ["G1"] * 2
    assert all(e.g1 < 1e-3 for e in rep.edges if e.achieved == "G1")
    model, rep = model_reports["step/linkrods.step"]
    sharp = [e for e in rep.edges if e.g1 > 45]
    assert len(sharp) == 6 and all(e.g1 == pytest.approx(90, abs=1e-6) for e in sharp)  # plane against cylinder
    assert all(e.achieved in ("G0", "none") for e in sharp)
    tangent = [e for e in rep.edges if e.achieved == "G1"]
    assert len(tangent) >= 60 and max(e.g1 for e in tangent) <= TOLERANCES["g1"]
    text = rep.table(max_rows=3)
    assert "face edge" in text and f"{len(rep.edges)} edges" in text


def test_a_pcurve_that_slips_along_the_edge_is_no_gap(model_reports):
    """linkrods.step's pcurves on its cylinders slip along the edges by up to 5.5e-5 (more than some edges'
    tolerances): the faces' points at the same edge parameter are that far apart, but the faces meet (their
    distance across the edge is rounding). With the slip left out and the file's own edge tolerances, no edge of
    the part is open; its six 90-degree edges are its sharp ones (G0)."""
    model, rep = model_reports["step/linkrods.step"]
    assert rep.counts()["none"] == 0 and rep.achieved == "G0"
    slipped = [e for e, m in zip(rep.edges, model.edges)
               if np.max(np.linalg.norm(model.face(m.faces[0]).evaluate(*m.uv[0].T)
                                        - model.face(m.faces[1]).evaluate(*m.uv[1].T), axis=1)) > 4e-5]
    assert min(e.g0 for e in slipped) < 1e-8  # faces 5.5e-5 apart at the same t, 1.2e-9 across (its 24 samples)
    assert all(e.g0 <= (e.g0_tol or 0) for e in slipped if e.g0 > 1e-6 * rep.size)  # the rest: within the file's
    sharp = [e for e in rep.edges if e.g1 > 10]
    assert len(sharp) == 6 and all(abs(e.g1 - 90) < 1e-6 for e in sharp)


# --- G3: the jump of the cross-boundary derivative of the normal curvature --------------------------------------

def spline_with_simple_knot(degree, multiplicity=1, seed=3):
    """A degree-(p, 3) B-spline with the knot u = 0.5 of the given multiplicity (one span in v), its control
    points' heights drawn at random (rounded): C^(p - multiplicity) across u = 0.5."""
    rows = degree + 1 + multiplicity
    knots_u = [0.0] * (degree + 1) + [0.5] * multiplicity + [1.0] * (degree + 1)
    greville_u = [np.mean(knots_u[i + 1:i + degree + 1]) for i in range(rows)]
    X, Y = np.meshgrid(greville_u, np.linspace(0, 1, 4), indexing="ij")
    Z = np.round(np.random.default_rng(seed).normal(0, 0.3, X.shape), 2)
    return lab.BSplineSurface(np.stack([X, Y, Z], axis=-1), knots_u, [0, 0, 0, 0, 1, 1, 1, 1], degree, 3)


def one_sided_kn_derivative(surface, v, side, h):
    """dκn/ds on one side (-1: u < 0.5, +1: u > 0.5) of the knot line at (0.5, v), along the geodesic leaving in
    the cross direction c = N x b_v, by Richardson-extrapolated one-sided differences of κn from the public
    evaluator (second derivatives only) along the geodesic to second order in (u, v).  Error O(h²)."""
    def at(u, vv):
        d = surface.derivatives(np.array([u]), np.array([vv]))
        return d.map(lambda x: x[0])

    def kn(d, tau):
        N = np.cross(d.bu, d.bv)
        N /= np.linalg.norm(N)
        t = d.bu * tau[0] + d.bv * tau[1]
        second = d.buu * tau[0] ** 2 + 2 * d.buv * tau[0] * tau[1] + d.bvv * tau[1] ** 2
        return float(N @ second / (t @ t))

    d0 = at(0.5 + side * 1e-13, v)
    N = np.cross(d0.bu, d0.bv)
    N /= np.linalg.norm(N)
    c = np.cross(N, d0.bv)
    c /= np.linalg.norm(c)
    I = np.array([[d0.bu @ d0.bu, d0.bu @ d0.bv], [d0.bu @ d0.bv, d0.bv @ d0.bv]])
    w = np.linalg.solve(I, [c @ d0.bu, c @ d0.bv])  # unit speed: c is a unit vector
    Q = d0.buu * w[0] ** 2 + 2 * d0.buv * w[0] * w[1] + d0.bvv * w[1] ** 2
    w2 = np.linalg.solve(I, [-(d0.bu @ Q), -(d0.bv @ Q)])
    sigma = side * np.sign(w[0])  # s of this sign goes into the side
    f0 = kn(d0, w)

    def D(step):
        s = sigma * step
        uv = np.array([0.5, v]) + w * s + 0.5 * w2 * s * s
        return (kn(at(*uv), w + w2 * s) - f0) / s

    return 2 * D(h / 2) - D(h)


@pytest.fixture(scope="module")
def g3_reports():
    """The reports of quartic, quintic and cubic splines with a simple knot and a quartic with a double one."""
    cases = {(4, 1): None, (5, 1): None, (3, 1): None, (4, 2): None}
    for degree, mult in cases:
        s = spline_with_simple_knot(degree, mult)
        cases[degree, mult] = (s, lab.continuity(s, samples=9))
    return cases


def knot_edge(report):
    return next(e for e in report.edges if e.direction == "u" and e.value == 0.5)


def test_a_simple_knot_of_a_quartic_or_quintic_is_g3_of_a_cubic_g2(g3_reports):
    for (degree, mult), (_s, rep) in g3_reports.items():
        e = knot_edge(rep)
        assert e.multiplicity == mult and e.g2 <= 1e-12
        if degree - mult >= 3:
            assert e.achieved == "G3" and e.g3 <= 1e-11, (degree, mult, e)
        else:
            assert e.achieved == "G2" and e.g3 > 0.1, (degree, mult, e)  # far above the tolerance
    assert rep.tolerances["g3"] == TOLERANCES["g3"] == 0.01
    tight = lab.continuity(spline_with_simple_knot(4), tol_g3=0.0)
    assert knot_edge(tight).achieved in ("G2", "G3")  # rounding may or may not be exactly 0
    with pytest.raises(ValueError, match="tol_g3"):
        lab.continuity(spline_with_simple_knot(4), tol_g3=-1)


def test_g3_jump_equals_the_one_sided_differences(g3_reports):
    """jump3 at each sample = |dκn/ds from below - from above| by Richardson differences.  Their error is O(h²)
    (measured: a factor 4 per halving of h, from 2e-3 at h = 4e-3 to 8e-6 of the largest |κn'| at h = 2.5e-4);
    stated tolerance at h = 2.5e-4: 2e-5 of the largest |κn'| (1/length²)."""
    for (degree, mult), (s, rep) in g3_reports.items():
        e = knot_edge(rep)
        v = np.linspace(0, 1, len(e.jump3))[1:-1]  # inside: the geodesic may leave the domain at v = 0, 1
        below = np.array([one_sided_kn_derivative(s, x, -1, 2.5e-4) for x in v])
        above = np.array([one_sided_kn_derivative(s, x, +1, 2.5e-4) for x in v])
        scale = np.max(np.abs(np.concatenate([below, above])))
        assert scale > 0.1
        np.testing.assert_allclose(e.jump3[1:-1], np.abs(below - above), atol=2e-5 * scale, rtol=0,
                                   err_msg=f"degree {degree}, multiplicity {mult}")


def test_a_torus_is_g3_across_its_double_knots():
    """A rational biquadratic torus: its parametrization is only C1 at the double knots, its geometry is G∞."""
    rep = lab.continuity(lab.surfaces.torus())
    assert rep.achieved == "G3" and max(e.g3 for e in rep.edges) <= 1e-12


def test_the_edge_overlay_draws_g3_black_readable_in_every_vision(g3_reports):
    """G3 edges black in the overlay and counted in its legend; black stays >= 40 CAM02-UCS ΔE from each other
    level's colour under normal vision and the three simulated dichromacies (lab.geometry.vision)."""
    from lab.geometry import vision
    from lab.view.explorers.edges import EDGE_COLORS, edge_legend_html, edge_lines

    rep = g3_reports[4, 1][1]
    lines = edge_lines(rep)
    level = np.asarray(lines.cell_data["level"])
    assert set(level) == {4} and np.all(np.asarray(lines.cell_data["RGB"]) == 0)  # every edge G3, black
    assert "G3: 1" in edge_legend_html(rep) and "G3: 0" in edge_legend_html(g3_reports[3, 1][1])
    rgb = np.array([[int(c[k:k + 2], 16) / 255 for k in (1, 3, 5)] for c in EDGE_COLORS.values()])
    for deficiency in vision.VISIONS:
        seen = rgb if deficiency is None else vision.simulate(rgb, deficiency)
        assert np.min(vision.delta_e(seen[-1], seen[:-1])) >= 40, deficiency


def test_the_report_exports_to_csv_and_reads_back_equal(g3_reports, tmp_path):
    """Every edge's numbers as written (repr: the same floats), units and tolerances in the header; pandas too."""
    from lab.interrogation.export import read_csv

    for rep in (g3_reports[3, 1][1], crease_report(), lab.continuity(lab.surfaces.hood())):
        path = rep.to_csv(tmp_path / "continuity.csv")
        back = read_csv(path)
        assert len(back.columns["g3"]) == len(rep.edges)
        for name in ("g0", "g1", "g2", "g3"):
            np.testing.assert_array_equal(back.columns[name], [getattr(e, name) for e in rep.edges])
        assert list(back.columns["achieved"]) == [e.achieved for e in rep.edges]
        np.testing.assert_array_equal(back.columns["worst_x"], [e.worst[0] for e in rep.edges])
        np.testing.assert_array_equal(back.columns["value"], [e.value for e in rep.edges])
        assert back.units["g3"] == "1/length²" and back.units["g1"] == "deg"
        assert "g3 <= 0.01" in back.meta["tolerance"] and back.meta["achieved"] == rep.achieved
    try:
        import pandas as pd
    except ImportError:  # pandas is optional: to_pandas says how to get it
        with pytest.raises(ImportError, match="pip install pandas"):
            rep.to_pandas()
        return
    frame = rep.to_pandas()
    assert isinstance(frame, pd.DataFrame) and list(frame["g2"]) == [e.g2 for e in rep.edges]
    assert frame.attrs["units"]["g0"] == "length"


def crease_report():
    return lab.continuity(crease())


# --- G3 on a model's face edges: the faces' third derivatives -----------------------------------------------------

def test_model_faces_third_derivatives_against_opencascade(model_reports):
    """At every sample of every shared edge of wing.brep, shell1.brep (NURBS faces) and linkrods.step (planes,
    cylinders, tori: NURBS in the file's angles, the chain rule with the parameter maps' s'''), each face's
    third derivatives equal OpenCASCADE's Geom_Surface::D3 of the file's own surface at the edge's (u, v):
    measured 1.6e-9 of the sample's largest component (linkrods, where it is 1.8e7), stated 3e-9."""
    from OCP.gp import gp_Pnt, gp_Vec

    checked = 0
    for name, (model, rep) in model_reports.items():
        surfaces = _file_surfaces(DATA / name)
        for edge in model.edges:
            if len(edge.faces) != 2:
                continue
            for index, uv in zip(edge.faces, edge.uv):
                face = model.face(index)
                uv = np.asarray(uv, dtype=float)
                got = np.stack(face.file_surface.third_derivatives(uv[:, 0], uv[:, 1]), axis=1)
                for k, (u, v) in enumerate(uv):
                    vectors = [gp_Vec() for _ in range(9)]
                    surfaces[index].D3(float(u), float(v), gp_Pnt(), *vectors)
                    ref = np.array([[x.X(), x.Y(), x.Z()] for x in (vectors[5], vectors[7], vectors[8], vectors[6])])
                    np.testing.assert_allclose(got[k], ref, atol=3e-9 * np.abs(ref).max(), rtol=0,
                                               err_msg=f"{name} face {index} at ({u}, {v})")
                    checked += 1
        assert rep.measured_g3 and all(np.isfinite(e.g3) for e in rep.edges), name  # every edge has its g3
    assert checked > 5000


def test_model_edges_reach_g3_where_the_faces_agree_to_third_order(model_reports):
    """linkrods.step: its one G3 edge joins the two halves of a torus (jumps 6e-12 /length²); shell1.brep: its five
    planar strips meet at G3 (g1 = g2 = g3 = 0), five curved joins stop at G2 (g3 4e-6 to 1.4e-4, above 1 % of
    their |κn'|)."""
    model, rep = model_reports["step/linkrods.step"]
    g3 = [e for e in rep.edges if e.achieved == "G3"]
    assert len(g3) == 1 and [model.face(i).kind for i in g3[0].faces] == ["Torus", "Torus"] and g3[0].g3 < 1e-10
    model, rep = model_reports["occ/shell1.brep"]
    counts = rep.counts()
    assert (counts["G3"], counts["G2"]) == (5, 5), counts
    assert all(e.g3 == 0 and e.faces == (k, k + 1) for k, e in enumerate(x for x in rep.edges if x.achieved == "G3"))
    assert all(e.g3 > 1e-6 for e in rep.edges if e.achieved == "G2")
    assert "G3 jump" in rep.table()


@pytest.mark.parametrize("suffix", [".step", ".brep"])
def test_a_face_edge_has_the_g3_of_the_knot_it_was_cut_at(g3_reports, tmp_path, suffix):
    """Each spline of the G3 cases written as its two Bézier patches (lab.write: two faces of one sewn shell) and
    read back: the one face edge achieves what the knot line did, with the same g3 (3 %: the samples differ;
    measured 73.2 against 73.0 for the cubic, 213 against 208 for the double knot, both ~1e-14 where G3)."""
    for (degree, mult), (s, rep) in g3_reports.items():
        knot = knot_edge(rep)
        model = lab.read(lab.write(s.to_bezier_patches(), tmp_path / f"s{degree}{mult}{suffix}"))
        (edge,) = lab.continuity(model).edges
        assert edge.achieved == knot.achieved, (degree, mult, edge, knot)
        if knot.achieved == "G3":
            assert edge.g3 < 1e-12
        else:
            assert edge.g3 == pytest.approx(knot.g3, rel=0.03), (degree, mult)


def test_a_face_without_third_derivatives_is_measured_up_to_g2(model_reports, monkeypatch):
    """A face whose surface cannot give third derivatives (a ParametricSurface has none): its edges' g3 is NaN
    and they stop at G2; the table then has no G3 column when no edge has one."""
    from lab.model import reparametrized, surface

    def none(self, u, v):
        raise NotImplementedError("no third derivatives")

    monkeypatch.setattr(surface._SplineSurface, "third_derivatives", none)
    monkeypatch.setattr(reparametrized.ReparametrizedSurface, "third_derivatives", none)
    model, _rep = model_reports["occ/shell1.brep"]
    rep = lab.continuity(model)
    assert not rep.measured_g3 and all(np.isnan(e.g3) for e in rep.edges)
    assert rep.counts()["G2"] == 10 and "G3" not in rep.counts() and "G3 jump" not in rep.table()


def test_samples_at_a_pole_are_flagged_degenerate():
    """The sphere's meridian knot lines run into its poles, where neither side has a normal: those samples (the two
    ends of each) are flagged in ``edge.degenerate`` and count for the gap only; the equator has none."""
    rep = lab.continuity(lab.surfaces.sphere(), samples=5)
    flagged = {(e.direction, e.value): np.flatnonzero(e.degenerate).tolist() for e in rep.edges}
    ends = [0, len(rep.edges[0].degenerate) - 1]
    assert flagged == {("u", 0.25): ends, ("u", 0.5): ends, ("u", 0.75): ends, ("u", 1.0): ends, ("v", 0.5): []}
    assert all(np.isnan(e.angle[e.degenerate]).all() and np.isfinite(e.angle[~e.degenerate]).all() for e in rep.edges)
    assert rep.achieved == "G3"  # a sphere is smooth: the poles are no break
