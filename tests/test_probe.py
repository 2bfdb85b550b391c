"""The point probe: values against lab's curvature at the point, the indicatrix against Euler's formula."""

import numpy as np
import pytest

from lab import surfaces
from lab.interrogation.probe import probe, probe_lines


def test_probe_values_equal_curvature_at_the_point():
    s = surfaces.practical()
    p = probe(s, 2.5, 3.5)
    c = s.curvature(np.array([2.5]), np.array([3.5]), directions=True)
    for name in ("K", "H", "k1", "k2"):
        assert getattr(p, name) == float(getattr(c, name)[0])
    assert np.array_equal(p.d1, c.d1[0]) and np.array_equal(p.d2, c.d2[0])
    assert np.allclose(p.point, s.evaluate(2.5, 3.5), atol=1e-14)


def test_indicatrix_radii_follow_euler():
    s = surfaces.torus(2.0, 0.5)
    (u0, u1), (v0, v1) = s.domain
    kinds = set()
    for t in (0.05, 0.2, 0.45, 0.6):  # around the tube: outer (elliptic) and inner (hyperbolic) side
        p = probe(s, u0 + t * (u1 - u0), 0.5 * (v0 + v1), size=0.1)
        assert p.indicatrix
        big = max(abs(p.k1), abs(p.k2))
        for line in p.indicatrix:
            x = line - p.point
            a, b = x @ p.d1, x @ p.d2
            assert np.max(np.abs(x @ p.normal)) < 1e-12  # in the tangent plane
            # k1 a^2 + k2 b^2 = ±1 in units where the shortest radius is size
            lhs = (p.k1 * a**2 + p.k2 * b**2) / (0.1**2 * big)
            assert np.max(np.abs(np.abs(lhs) - 1)) < 1e-9
        assert (p.K > 0) == (len(p.indicatrix) == 1)  # an ellipse; else branches of hyperbolas
        kinds.add(p.K > 0)
    assert kinds == {True, False}


def test_probe_errors_and_lines():
    s = surfaces.practical()
    with pytest.raises(ValueError, match=r"\(u, v\) must lie in the domain"):
        probe(s, -1.0, 2.0)
    lines = probe_lines(probe(s, 2.5, 3.5))
    assert set(np.asarray(lines.cell_data["part"]).tolist()) >= {0, 1, 2}


def test_explorer_tools_offscreen():
    from lab.view.explorers import CurvatureExplorer

    e = CurvatureExplorer(surfaces.practical(), live=False, depth=1)
    try:
        t = e.tools
        t.probe.value = True
        t.u.value, t.v.value = 2.5, 3.5
        p = t.last_probe
        c = surfaces.practical().curvature(np.array([2.5]), np.array([3.5]))
        assert p.uv == (2.5, 3.5) and p.K == float(c.K[0]) and p.k1 == float(c.k1[0])
        assert "κ1 = " in t.readout.value
        t.map.value = "draft"
        t.pull.value = 2  # +x
        rgb = np.asarray(e.mesh.point_data["RGB"], dtype=int)
        assert (rgb[:, 0] - rgb[:, 2] > 60).any() and (rgb[:, 2] - rgb[:, 0] > 60).any()  # both sides of the parting line
        assert "δ" in e.legend().title and e.picture_title() == "draft angle, pull +x, depth 1"
        t.map.value = "radius"
        t.radius.value = 2.0
        below = np.all(np.asarray(e.mesh.point_data["RGB"]) == np.round(255 * np.array(t_flagged())), axis=1)
        k = np.maximum(np.abs(e.mesh.point_data["k1"]), np.abs(e.mesh.point_data["k2"]))
        assert np.array_equal(below, k * 2.0 > 1)
        t.combs.value = True
        image = e.picture()
        assert image.shape[2] == 3 and (image.sum(-1) < 60).sum() > 200  # the combs and probe in black
        t.map.value = "curvature"
        assert e.legend().title.startswith("Gaussian")
    finally:
        e.close()


def t_flagged():
    from lab.interrogation.maps import FLAGGED

    return FLAGGED
