"""Draft angle, parting line, minimum-radius map and curvature combs against analytic references."""

import numpy as np
import pytest
import sympy as sp

import lab
from lab import surfaces
from lab.interrogation import combs, maps


def test_draft_angle_on_the_sphere_is_the_latitude():
    s = surfaces.sphere(2.0)
    u, v = np.meshgrid(np.linspace(0, 1, 13), np.linspace(0.05, 0.95, 11))
    X = s.evaluate(u, v)
    d = s.derivatives(u, v)
    normal = np.cross(d.bu, d.bv)
    normal /= np.linalg.norm(normal, axis=-1, keepdims=True)
    latitude = np.degrees(np.arcsin(np.clip(X[..., 2] / 2.0, -1, 1)))
    assert np.max(np.abs(maps.draft_angle(normal, (0, 0, 5)) - latitude)) < 1e-9
    # a pull along -z flips the sign; the angle is that to the pull's plane
    assert np.max(np.abs(maps.draft_angle(normal, (0, 0, -1)) + latitude)) < 1e-9


@pytest.mark.filterwarnings("ignore:.*degenerate point")
def test_parting_line_of_the_sphere_is_the_equator():
    s = surfaces.sphere(1.0)
    mesh = maps.draft_map(s, (0, 0, 1), resolution=32)
    assert np.max(np.abs(np.asarray(mesh.point_data["draft"]))) <= 90
    lines = maps.parting_line(mesh)
    P = np.asarray(lines.points)
    assert len(P) > 20
    assert np.max(np.abs(P[:, 2])) < 2e-2  # the interpolated 0° level on a mesh at this resolution
    assert np.max(np.abs(np.linalg.norm(P[:, :2], axis=1) - 1)) < 2e-2


def test_draft_errors_name_the_parameter():
    with pytest.raises(ValueError, match="pull must be a non-zero vector"):
        maps.draft_angle(np.array([[0, 0, 1.0]]), (0, 0, 0))
    with pytest.raises(TypeError, match=r"pull must be an array of numbers; got str 'up'"):
        maps.draft_angle(np.array([[0, 0, 1.0]]), "up")
    with pytest.raises(ValueError, match=r"pull must be a direction \(x, y, z\) of three finite numbers"):
        maps.draft_angle(np.array([[0, 0, 1.0]]), (0, 1))
    with pytest.raises(ValueError, match=r"normals must have shape \(\.\.\., 3\)"):
        maps.draft_angle(np.ones((4, 2)), (0, 0, 1))


@pytest.mark.parametrize("R", [0.5, 0.99, 1.01, 2.0])
def test_min_radius_on_a_cylinder(R):
    s = surfaces.cylinder(R, 1.0)
    mesh = maps.radius_map(s, 1.0, resolution=8)
    rho = np.asarray(mesh.point_data["min_radius"])
    assert np.max(np.abs(rho - R)) < 1e-9 * R
    below = np.asarray(mesh.point_data["below"])
    assert below.all() if R < 1.0 else not below.any()


def test_min_radius_flat_point_and_errors():
    assert maps.min_radius(0.0, 0.0) == np.inf
    mesh = maps.radius_map(surfaces.plane(), 0.5, resolution=8)  # a plane: every radius infinite, flagged flat
    assert np.all(np.isinf(mesh.point_data["min_radius"])) and np.all(mesh.point_data["flat"])
    assert not np.any(maps.radius_map(surfaces.cylinder(1.0, 1.0), 0.5, resolution=8).point_data["flat"])
    assert not maps.below_radius(0.0, 0.0, 1.0)
    with pytest.raises(ValueError, match="r"):
        maps.below_radius(1.0, 1.0, 0.0)


@pytest.mark.parametrize("R", [0.5, 3.0])
def test_comb_on_a_cylinder_circle_has_teeth_of_length_scale_over_R(R):
    s = surfaces.cylinder(R, 2.0)
    c = combs.iso_comb(s, "v", 0.3, density=41, scale=0.2)
    length = np.linalg.norm(c.tips - c.points, axis=1)
    assert np.max(np.abs(length - 0.2 / R)) < 1e-9 / R
    assert np.max(np.abs(c.kn + 1 / R)) < 1e-9 / R  # outward normal: kn = -1/R
    assert len(c.inflections) == 0
    # along the rulings (u fixed) the normal curvature is 0
    line = combs.iso_comb(s, "u", 0.1, density=9, scale=0.2)
    assert np.max(np.abs(line.kn)) < 1e-9


def test_comb_finds_a_known_inflection():
    u, v = sp.symbols("u v")
    s = lab.ParametricSurface.from_sympy((u, v, (u - sp.Rational(37, 100)) ** 3 + v**2), (u, v), ((0, 1), (0, 1)))
    c = combs.iso_comb(s, "v", 0.5, density=20, scale=1.0)
    assert c.inflections.shape == (1, 2)
    assert abs(c.inflections[0, 0] - 0.37) < 1e-9 and c.inflections[0, 1] == 0.5
    # kn = 6(u - 0.37) / (1 + 9 (u - 0.37)^4) along v = 0.5, with the normal (−z_u, −z_v, 1)/|.|
    t = c.uv[:, 0]
    zu, zv = 3 * (t - 0.37) ** 2, 1.0
    ref = 6 * (t - 0.37) / np.sqrt(1 + zu**2 + zv**2) / (1 + zu**2)
    assert np.max(np.abs(c.kn - ref)) < 1e-12
    lines = combs.comb_lines(c)
    assert lines.field_data["inflections"].shape == (1, 3)
    assert np.count_nonzero(np.asarray(lines.cell_data["part"]) == 0) == 20
    assert np.count_nonzero(np.asarray(lines.cell_data["part"]) == 2) == 1


def test_border_combs_and_errors():
    s = surfaces.practical()
    cs = combs.border_combs(s, density=16, count=1)
    assert len(cs) == 6
    with pytest.raises(ValueError, match="direction must be 'u'"):
        combs.iso_comb(s, "w", 0.5)
    with pytest.raises(ValueError, match="value must lie in the domain"):
        combs.iso_comb(s, "u", 1e6)
    with pytest.raises(ValueError, match=r"uv must have shape \(k, 2\)"):
        combs.comb(s, np.zeros((3, 3)))


def test_render_draft_min_radius_and_combs(tmp_path, capsys):
    import pyvista as pv
    from PIL import Image

    from lab import cli

    out = tmp_path / "draft.vtp"
    assert cli.main(["render", "--surface", "sphere", "--depth", "0", "--draft", "0,0,2", "--quiet", "-o", str(out)]) == 0
    mesh = pv.read(out)
    X, delta = np.asarray(mesh.points), np.asarray(mesh.point_data["draft"])
    latitude = np.degrees(np.arcsin(np.clip(X[:, 2] / np.linalg.norm(X, axis=1), -1, 1)))
    good = np.abs(np.abs(latitude) - 90) > 1  # the poles' normals are limits
    assert np.max(np.abs(delta - latitude)[good]) < 1e-6
    out = tmp_path / "radius.vtp"
    assert cli.main(["render", "--surface", "cylinder", "--depth", "0", "--min-radius", "1.5", "--quiet",
                     "-o", str(out)]) == 0
    assert np.asarray(pv.read(out).point_data["below"]).all()  # the cylinder's radius 1 < 1.5
    png = tmp_path / "combs.png"
    assert cli.main(["render", "--surface", "practical", "--depth", "1", "--draft", "1,0,0", "--combs", "1",
                     "--window-size", "400x300", "--quiet", "-o", str(png)]) == 0
    image = np.asarray(Image.open(png).convert("RGB")).astype(int)
    assert (np.abs(image[..., 0] - image[..., 2]) > 60).sum() > 1000  # red and blue sides of the parting line
    assert (image.sum(-1) < 60).sum() > 200  # black parting line and combs
    for bad, message in ((["--draft", "0,0,0"], "pull direction must look like X,Y,Z"),
                         (["--draft", "0,0,1", "--min-radius", "1"], "different colourings"),
                         (["--min-radius", "-1"], "r must be")):
        with pytest.raises(SystemExit):
            cli.main(["render", "--surface", "sphere", "--quiet", *bad, "-o", str(tmp_path / "x.vtp")])
        assert message in capsys.readouterr().err


def test_a_pull_direction_of_any_length_is_its_direction():
    """(1e308, 1e308, 0) overflowed in its length and (1e-320, 0, 0) underflowed (the fuzzer): each is a direction."""
    import warnings

    normals = np.array([[1.0, 1.0, 0.0], [1.0, 0.0, 0.0]]) / np.array([[np.sqrt(2)], [1.0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        big = maps.draft_angle(normals, (1e308, 1e308, 0))
        tiny = maps.draft_angle(normals, (1e-320, 0, 0))
    np.testing.assert_allclose(big, maps.draft_angle(normals, (1.0, 1.0, 0.0)), atol=1e-12)
    np.testing.assert_allclose(tiny, maps.draft_angle(normals, (1.0, 0.0, 0.0)), atol=1e-12)
    np.testing.assert_allclose(big, [90.0, 45.0], atol=1e-12)
