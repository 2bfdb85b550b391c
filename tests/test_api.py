"""The public API (the library reference of the documentation), which notebooks and tests rely on."""

import numpy as np
import sympy as sp

import lab


def test_design_api_shapes():
    P = np.random.default_rng(1).normal(size=(3, 4, 3))
    s = lab.BezierSurface(P)
    assert s.domain == ((0, 1), (0, 1))
    u = np.linspace(0, 1, 5)[:, None]
    v = np.linspace(0, 1, 3)[None, :]
    assert s.evaluate(u, v).shape == (5, 3, 3)
    d = s.derivatives(u, v)
    assert d._fields == ("b", "bu", "bv", "buu", "buv", "bvv") and all(x.shape == (5, 3, 3) for x in d)
    c = s.curvature(u, v)
    assert all(getattr(c, f).shape == (5, 3) for f in ("K", "H", "k1", "k2", "degenerate"))
    assert np.all(c.k1 >= c.k2)
    rational = lab.BezierSurface(P, weights=np.ones((3, 4)))
    np.testing.assert_allclose(rational.evaluate(u, v), s.evaluate(u, v), atol=1e-14)


def test_bspline_and_parametric_share_the_interface():
    b = lab.surfaces.practical()
    patches = b.to_bezier_patches()
    assert isinstance(patches, lab.BezierPatches) and len(patches) == 49
    x, y = sp.symbols("x y", real=True)
    p = lab.ParametricSurface.from_sympy((x, y, x * y), (x, y), ((-1, 1), (-1, 1)))
    for s in (b, p):
        assert s.evaluate(0.5, 0.5).shape == (3,)
        assert float(s.curvature(0.5, 0.5).K) <= 0 or s is b
    assert float(p.curvature(0.0, 0.0).K) == -1.0


def test_practical_constants_and_views():
    patches = lab.surfaces.practical().to_bezier_patches()
    for name in ("CURVATURE_GAUSSIAN", "CURVATURE_AVERAGE", "CURVATURE_PRINCIPAL_MAX", "CURVATURE_PRINCIPAL_MIN",
                 "COLOR_MAP_LINEAR", "COLOR_MAP_CUT", "COLOR_MAP_CLASSIFICATION"):
        assert hasattr(lab.BezierPatches, name)
    patch = next(iter(patches))
    assert patch.degree == (3, 3) and patch.control_points.shape == (4, 4, 3)
    for method in ("set_curvature", "set_colors"):
        assert callable(getattr(patch, method))
    assert patch.curvature.shape == (2, 2) and patch.colors.shape == (2, 2, 3)


def test_the_labs_warnings_read_as_one_line():
    """A student sees 'DegeneratePointWarning: …', not the library's path and source line; others are unchanged."""
    import warnings

    from lab.geometry.curvature import DegeneratePointWarning

    text = warnings.formatwarning("3 degenerate points", DegeneratePointWarning, "/lab/x.py", 5, "source line")
    assert text == "DegeneratePointWarning: 3 degenerate points\n"
    other = warnings.formatwarning("hi", UserWarning, "/elsewhere/y.py", 5, "source line")
    assert other.startswith("/elsewhere/y.py:5: UserWarning: hi") and "source line" in other


def test_every_example_in_the_docstrings_runs():
    """The library reference shows the docstrings' examples: each one runs and prints what it says (doctest)."""
    import doctest
    import importlib
    import pkgutil

    failed, tried = [], 0
    for info in pkgutil.walk_packages(lab.__path__, "lab."):
        module = importlib.import_module(info.name)
        for test in doctest.DocTestFinder().find(module, info.name):
            if test.examples:
                result = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE).run(
                    test, out=lambda text, failed=failed, name=test.name: failed.append(f"{name}:\n{text}"))
                tried += result.attempted
    assert tried >= 20 and not failed, "\n".join(failed)
