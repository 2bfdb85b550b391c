"""What the fuzzer calls (issue 35): the public API's entry points, each with a valid baseline call and, per
argument, the kind of bad input to try there; the command line and the course's verbs.

A target is ``Target(name, func, params)``: ``func(**kwargs)`` makes the call, ``params`` lists each argument with
its kind (:data:`KINDS`: the strategies of bad and borderline values) and a good value.  An example keeps most
arguments good and replaces one or two by values of their kind, so that each bad value meets an otherwise valid
call (the way a student's one mistake does).  To fuzz a new entry point, add a ``Target`` to :func:`targets` (a
new kind of argument: a strategy in :data:`KINDS`); ``python -m tests.fuzz`` runs them all with a larger budget
and prints the distinct failures by category.
"""

import atexit
import os
import shutil
import tempfile
from dataclasses import dataclass, field

import numpy as np
from hypothesis import strategies as st

import lab
from lab import surfaces
from lab.geometry.derivatives import Derivatives

from .fuzz_support import UserBug

# -- values ---------------------------------------------------------------------------------------------------------

HUGE_INTS = [10**9, 10**12, 2**63, 10**30, 10**400, -(10**30)]
EXTREME_FLOATS = [np.nan, np.inf, -np.inf, 1e308, -1e308, np.finfo(float).max, 5e-324, 1e-300, 1e300, -0.0]
TEXT = ["half", "1.5", "", "nan", "1e999", "0,5", "-1", "x" * 40]
OTHER = [None, True, 1 + 2j, [], {}, {"a": 1}, {1, 2}, b"1", (), [None], Ellipsis]

finite = st.floats(-1e6, 1e6, allow_nan=False)
any_float = st.floats(allow_nan=True, allow_infinity=True)
number = st.one_of(finite, any_float, st.sampled_from(EXTREME_FLOATS), st.integers(-10**6, 10**6),
                   st.sampled_from(HUGE_INTS), st.sampled_from(TEXT), st.sampled_from(OTHER),
                   st.builds(np.float32, finite), st.builds(np.array, finite), st.lists(finite, min_size=1, max_size=3))
count = st.one_of(st.integers(-3, 40), st.sampled_from(HUGE_INTS), st.sampled_from([2.5, 3.0, np.nan, np.inf, -1e9]),
                  st.sampled_from(TEXT + ["3"]), st.sampled_from(OTHER), st.builds(np.int64, st.integers(0, 20)))


def _views():
    """Parameters that look small and are not: views broadcast to billions of points, and open grids."""
    big = np.linspace(0.0, 1.0, 10**5)
    return [np.broadcast_to(np.float64(0.5), (10**5, 10**5)), np.broadcast_to(0.25, (10**10,)),
            big[:, None], big[None, :], np.broadcast_to(big, (10**5, 10**5))]


VIEWS = _views()
unit = st.floats(0.0, 1.0)
param = st.one_of(
    unit, number,
    st.lists(unit, min_size=0, max_size=6).map(np.array),
    st.sampled_from(VIEWS),
    st.sampled_from([np.array([0.1, np.nan]), np.array([[0.1, 0.2], [0.3]], dtype=object), ["a", "b"], [[0.1, 0.2], [0.3]],
                     np.zeros((2, 3, 0)), np.array([0.5 + 1j]), np.array(["0.5"]), np.array([True, False]),
                     np.zeros((4, 1, 1, 1)) + 0.5, np.array(np.datetime64("2026-12-07")), np.float16(0.5)]),
)
uv = st.one_of(
    st.tuples(unit, unit), st.tuples(number, unit), st.tuples(unit, number),
    st.sampled_from([(0.1,), (0.1, 0.2, 0.3), "0.5,0.5", None, np.array([[0.1, 0.2]]), [np.nan, 0.1], (1e308, 0.0),
                     ("a", 0.5), {0.1, 0.2}, np.zeros((0, 2))]),
)
vector3 = st.one_of(
    st.tuples(finite, finite, finite),
    st.sampled_from([(0, 0, 0), (np.nan, 0, 1), (1e308, 1e308, 0), (1e-320, 0, 0), "z", [1, 2], None, [[0, 0, 1]],
                     ("0", "0", "1"), (0, 0, 10**400)]),
)
values = st.one_of(  # what a colour map or a measure receives
    st.lists(finite, min_size=1, max_size=8).map(np.array),
    st.lists(st.sampled_from([1.7e308, -1.7e308, 1e308, 5e-324, 0.0, 1e-300]), min_size=1, max_size=6).map(np.array),
    st.lists(any_float, min_size=0, max_size=6).map(np.array),
    st.sampled_from([np.array([]), [], "x", None, ["1", "2"], [[1.0, 2.0], [3.0]], np.array([1 + 1j]), 1.0,
                     np.broadcast_to(1.0, (10**6, 10**4)), np.zeros((3, 0)), np.array([True, False]), [10**400, 1]]),
)
name = st.one_of(st.text(max_size=8), st.sampled_from(OTHER), st.sampled_from([["linear"], 3, 1.5]))
flag = st.one_of(st.booleans(), st.sampled_from(["yes", "", None, 2, np.nan, [True]]))
small = st.one_of(st.integers(-2, 12), count)  # counts where small values are the valid ones (depth, resolution)


# -- a user's own surfaces and functions ----------------------------------------------------------------------------

def _raise(*_args, **_kwargs):
    raise UserBug("the user's function failed")


def _fields(u, v, last=3, value=0.0):
    shape = np.shape(u)
    return Derivatives(*(np.full(shape + (last,), value) for _ in range(6)))


def _plane_derivs(u, v):
    u, v = np.asarray(u, float), np.asarray(v, float)
    z, o = np.zeros_like(u), np.ones_like(u)
    return Derivatives(np.stack([u, v, z], -1), np.stack([o, z, z], -1), np.stack([z, o, z], -1),
                       *(np.zeros(u.shape + (3,)) for _ in range(3)))


USER_DERIVATIVES = {
    "returns None": lambda u, v: None,
    "returns a tuple": lambda u, v: tuple(_plane_derivs(u, v)),
    "wrong shape": lambda u, v: _fields(u, v, last=2),
    "one point": lambda u, v: Derivatives(*(np.zeros(3) for _ in range(6))),
    "NaN": lambda u, v: _fields(u, v, value=np.nan),
    "huge": lambda u, v: _fields(u, v, value=1e300),
    "strings": lambda u, v: Derivatives(*(np.full(np.shape(u) + (3,), "x") for _ in range(6))),
    "raises": _raise,
    "fields None": lambda u, v: Derivatives(None, None, None, None, None, None),
}


def _user_surfaces():
    import sympy as sp

    found = {f"user surface ({k})": lab.ParametricSurface(f, ((0, 1), (0, 1)), name=k) for k, f in USER_DERIVATIVES.items()}
    u, v, a = sp.symbols("u v a")
    try:
        found["sympy surface with a free symbol"] = lab.ParametricSurface.from_sympy((u, v, a * u * v), (u, v),
                                                                                     ((0, 1), (0, 1)))
    except (TypeError, ValueError):
        pass  # refused when built: what the fix does
    return found


class _Lazy:
    """Objects built once, when the fuzzer first needs them (building the OpenCASCADE parts is not free)."""

    def __init__(self):
        self._cache = {}

    def get(self, key, build):
        if key not in self._cache:
            self._cache[key] = build()
        return self._cache[key]


LAZY = _Lazy()


def good_surfaces():
    return LAZY.get("good", lambda: {
        "torus": surfaces.torus(), "plane": surfaces.plane(), "sphere": surfaces.sphere(), "practical": surfaces.practical(),
        "bezier": lab.BezierSurface(np.random.default_rng(35).random((4, 3, 3))),
        "user plane": lab.ParametricSurface(_plane_derivs, ((0, 1), (0, 1)), name="user plane"),
    })


def bad_surfaces():
    def build():
        found = _user_surfaces()
        found["zero-size surface"] = lab.BezierSurface(np.zeros((4, 4, 3)))
        found["patches instead"] = surfaces.torus().to_bezier_patches()
        return found

    return LAZY.get("bad", build)


a_surface = st.one_of(  # a surface whose methods are called: the library's and a user's own
    st.sampled_from(["torus", "plane", "sphere", "practical", "bezier", "user plane"]).map(lambda k: good_surfaces()[k]),
    st.sampled_from(sorted(USER_DERIVATIVES) + ["sympy surface with a free symbol", "zero-size surface"])
    .map(lambda k: bad_surfaces().get(f"user surface ({k})", bad_surfaces().get(k))).filter(lambda s: s is not None),
)
surface = st.one_of(a_surface, st.sampled_from([None, "torus", 3, lab.BezierSurface]),
                    st.just("patches instead").map(lambda k: bad_surfaces()[k]))

FUNCTIONS = [lambda *a, **k: None, lambda *a, **k: "x", lambda *a, **k: np.nan, _raise, lambda *a, **k: np.zeros((7, 5)),
             lambda *a, **k: 1e308, 42, None, "f2"]
function = st.sampled_from(FUNCTIONS)


# -- files ----------------------------------------------------------------------------------------------------------

def scratch():
    """A folder for the fuzzer's files (made once per process): an empty folder, junk files, a missing path."""

    def build():
        root = tempfile.mkdtemp(prefix="lab-fuzz-")
        atexit.register(shutil.rmtree, root, True)  # the process's own scratch folder, gone when it ends
        os.makedirs(os.path.join(root, "empty"))
        for name, content in (("junk.step", b"\x00\xffnot a step file"), ("empty.igs", b""), ("list.ipynb", b"[1, 2]"),
                              ("junk.ipynb", b"{\"cells\": 3}"), ("roster.csv", b"username\n\xff\xfe"),
                              ("junk.bez", b"CBEZ333\n1 2 3\n"), ("text.3dm", b"hello"), ("deadline.txt", b"x")):
            with open(os.path.join(root, name), "wb") as f:
                f.write(content)
        return root

    return LAZY.get("scratch", build)


path = st.sampled_from(["empty", "junk.step", "empty.igs", "list.ipynb", "junk.ipynb", "roster.csv", "junk.bez",
                        "text.3dm", "missing/x.step", "out.png", "out.vtp", "new", ""]).map(
    lambda p: os.path.join(scratch(), p) if p else p)


# -- targets --------------------------------------------------------------------------------------------------------

KINDS = {"a_surface": a_surface, "number": number, "count": count, "small": small, "param": param, "uv": uv, "vector3": vector3,
         "values": values, "name": name, "flag": flag, "surface": surface, "function": function, "path": path}


@dataclass
class Param:
    name: str
    kind: str
    good: object  # a value, or a Fresh(factory) built anew for every call
    bad: object = None  # a strategy that replaces KINDS[kind]


@dataclass
class Fresh:
    build: object


@dataclass
class Target:
    name: str
    func: object
    params: list
    numbers: tuple = ()  # arguments where text must not be accepted
    examples: int = 25  # relative budget: the test scales it
    expect: object = None
    cli: bool = False
    strategy: object = None  # a whole strategy of kwargs instead of params (the command line)
    extra: dict = field(default_factory=dict)


def P(name, kind, good, bad=None):
    return Param(name, kind, good, bad)


def draw_kwargs(data, target):
    """The arguments of one example: most of them good, one or two (sometimes none) replaced by their kind's values."""
    if target.strategy is not None:
        return data.draw(target.strategy)
    n_bad = data.draw(st.sampled_from([1, 1, 1, 2, 0]), label="how many bad")
    names = [p.name for p in target.params if p.kind != "fixed"]
    chosen = set(data.draw(st.lists(st.sampled_from(names), min_size=min(n_bad, len(names)),
                                    max_size=min(n_bad, len(names)), unique=True), label="bad")) if names else set()
    kwargs = {}
    for p in target.params:
        if p.name in chosen:
            kwargs[p.name] = data.draw(p.bad if p.bad is not None else KINDS[p.kind], label=p.name)
        else:
            kwargs[p.name] = p.good.build() if isinstance(p.good, Fresh) else p.good
    return kwargs


def _finite_colors(attr):
    def expect(result, kwargs):
        obj = kwargs.get("patches") if result is None else result
        colors = getattr(obj, attr, None)
        if colors is not None and not np.all(np.isfinite(colors)):
            return f"non-finite {attr} stored"
        return None

    return expect


def _patches():
    return surfaces.practical().to_bezier_patches()


def _mode_map(p):
    """What visualize_curvature, colors_for and the pictures take as measure and map."""
    return p


def targets():
    """Every target, in a stable order (the test's ids)."""
    from lab.geometry import colormaps as C
    from lab.geometry import curvature as K

    torus, plane = surfaces.torus(), surfaces.plane()
    found = []
    add = found.append

    # surfaces from the library's catalogue and from control nets
    for fname, args in (("torus", ("R", "r")), ("sphere", ("radius",)), ("cylinder", ("r", "h")),
                        ("cone", ("radius", "height")), ("catenoid", ("c", "height")), ("ellipsoid", ("a", "b", "c")),
                        ("plane", ("size",)), ("sine_wave", ("amplitude", "frequency", "radius"))):
        factory = getattr(surfaces, fname)

        def make(_f=factory, **kw):
            s = _f(**kw)
            return s, s.curvature(0.3, 0.6)

        defaults = {"torus": (2.0, 1.0), "cylinder": (1.0, 2.0), "cone": (1.0, 1.0), "catenoid": (1.0, 2.0),
                    "ellipsoid": (3.0, 2.0, 1.0), "sine_wave": (0.5, 1.0, 6.0)}.get(fname, (1.0,))
        add(Target(f"surfaces.{fname}", make, [P(a, "number", d) for a, d in zip(args, defaults)], numbers=args))
    add(Target("surfaces.practical_height", surfaces.practical_height, [P("x", "param", 0.5), P("y", "param", 0.5)],
               numbers=("x", "y")))
    net = np.random.default_rng(35).random((4, 4, 3))
    add(Target("BezierSurface", lambda P_, weights: lab.BezierSurface(P_, weights).curvature(0.5, 0.5),
               [P("P_", "values", net, st.one_of(values, st.sampled_from([net * 1e200, net[..., :2], net[None], net * np.nan,
                                                                          net.tolist(), np.zeros((1, 1, 3))]))),
                P("weights", "values", None, st.one_of(values, st.sampled_from([np.ones((4, 4)) * -1, np.ones((3, 3))])))]))
    knots = np.array([0, 0, 0, 0, 1, 1, 1, 1.0])
    add(Target("BSplineSurface", lambda P_, ku, kv, du, dv: lab.BSplineSurface(P_, ku, kv, du, dv).curvature(0.5, 0.5),
               [P("P_", "values", net), P("ku", "values", knots), P("kv", "values", knots, st.sampled_from(
                   [knots[::-1], np.array([0, 0, 0, 0, np.nan, 1, 1, 1.0]), knots[:5], np.zeros(8)])),
                P("du", "count", 3), P("dv", "count", 3)], numbers=("du", "dv")))
    add(Target("BezierPatches", lambda cp, weights, grid_shape, seams: lab.BezierPatches(cp, weights, grid_shape, seams),
               [P("cp", "values", np.zeros((2, 4, 4, 3)) + net), P("weights", "values", None),
                P("grid_shape", "uv", (1, 2), st.one_of(uv, st.sampled_from([(2, 1), (1.5, 2), (10**30, 1), "ab"]))),
                P("seams", "name", None, st.sampled_from([(1, 2), "x", ((True, False),), 3, ((1, 2), (3, 4))]))]))
    add(Target("ParametricSurface", lambda derivatives, domain: lab.ParametricSurface(derivatives, domain).curvature(0.5, 0.5),
               [P("derivatives", "function", _plane_derivs, st.sampled_from(list(USER_DERIVATIVES.values()) + FUNCTIONS)),
                P("domain", "uv", ((0, 1), (0, 1)), st.one_of(uv, st.sampled_from(
                    [((0, 1),), ((1, 0), (0, 1)), ((0, np.inf), (0, 1)), ((0, 10**400), (0, 1)), (("a", 1), (0, 1)),
                     ((0, 1e308), (-1e308, 0)), ((0, 5e-324), (0, 1))])))]))
    add(Target("ParametricSurface.from_sympy", _from_sympy, [P("xyz", "name", "plane", st.sampled_from(
        ["free symbol", "two", "strings", "sqrt", "huge", "none", "division", "constant", "function"])),
        P("domain", "uv", ((0, 1), (0, 1)), st.sampled_from([((0, 1),), ((0, "pi"), (0, 1)), ((0, np.nan), (0, 1)),
                                                              "x", ((0, 10**400), (0, 1)), ((-1, 1), (-1, 1))]))]))
    add(Target("ReparametrizedSurface", _reparametrized, [P("map_u", "function", "good", st.sampled_from(
        ["none", "short", "nan", "raises", "decreasing", "scalar"])), P("domain", "uv", ((0, 1), (0, 1)))]))
    add(Target("TrimmedSurface", lambda surface, outer, tol: lab.TrimmedSurface(surface, outer, (), tol).curvature(0.5, 0.5),
               [P("surface", "surface", plane), P("outer", "values", None, st.one_of(values, st.sampled_from(
                   [np.array([[0.1, 0.1], [0.9, 0.1], [0.9, 0.9]]), np.array([[0.1, 0.1], [0.9, 0.9]]),
                    np.array([[0.1, 0.1], [0.9, 0.1], [0.9, np.nan]]), np.zeros((3, 3)), np.array([[0.5, 0.5]] * 4)]))),
                P("tol", "number", None)], numbers=("tol",)))

    # a surface's evaluators
    def method(mname, **extra):
        def call(surface, u, v, **kw):
            return getattr(surface, mname)(u, v, **kw)

        return call

    for mname in ("curvature", "curvature_grid", "evaluate", "derivatives", "normal", "fundamental_forms", "sample_points"):
        p = [P("surface", "a_surface", torus), P("u", "param", np.array([0.1, 0.4])), P("v", "param", np.array([0.2, 0.7]))]
        add(Target(f"Surface.{mname}", method(mname), p, numbers=("u", "v"), examples=40))
    add(Target("Surface.curvature(directions)", lambda surface, u, v, directions: surface.curvature(u, v, directions=directions),
               [P("surface", "a_surface", torus), P("u", "param", 0.3), P("v", "param", 0.6), P("directions", "flag", True)],
               numbers=("u", "v")))
    add(Target("Surface.grid", lambda surface, nu, nv: surface.grid(nu, nv),
               [P("surface", "a_surface", torus), P("nu", "count", 5), P("nv", "count", 7)], numbers=("nu", "nv")))
    add(Target("BSplineSurface.insert_knot", lambda t, direction, times: surfaces.practical().insert_knot(t, direction, times),
               [P("t", "number", 2.5), P("direction", "name", "u"), P("times", "count", 1)], numbers=("t", "times")))

    # the practical's patches
    add(Target("BezierPatches.refine", lambda patches, num, memory_limit: patches.refine(num, memory_limit=memory_limit),
               [P("patches", "fixed", Fresh(_patches)), P("num", "small", 1), P("memory_limit", "number", None)],
               numbers=("num",)))
    add(Target("BezierPatches.visualize_curvature", _visualize,
               [P("patches", "fixed", Fresh(_patches)), P("mode", "name", "gaussian", st.one_of(name, st.sampled_from(
                   list(K.CurvatureMode) + ["mean", "k1"]))), P("color_map", "name", "linear", st.one_of(
                       name, st.sampled_from(list(C.COLOR_MAPS)))), P("options", "name", {}, st.sampled_from(
                           [{"vmin": "a"}, {"vmin": np.nan}, {"vmin": 1.0, "vmax": 0.0}, {"vmax": 1e308}, {"nope": 1},
                            {"vmin": -1e308, "vmax": 1e308}, {"tol": -1}, {"vmax": -2.0}]))],
               expect=_finite_colors("colors")))
    add(Target("BezierPatches.curvature_at", lambda patches, u, v: patches.curvature_at(u, v),
               [P("patches", "fixed", Fresh(_patches)), P("u", "param", 0.5), P("v", "param", 0.5)], numbers=("u", "v")))
    add(Target("BezierPatches.evaluate", lambda patches, u, v: patches.evaluate(u, v),
               [P("patches", "fixed", Fresh(_patches)), P("u", "param", 0.5), P("v", "param", 0.5)], numbers=("u", "v")))
    add(Target("BezierPatches.to_mesh", lambda patches, resolution: patches.to_mesh(resolution),
               [P("patches", "fixed", Fresh(_patches)), P("resolution", "small", 2)], numbers=("resolution",)))
    add(Target("BezierPatches[index]", lambda patches, index: patches[index],
               [P("patches", "fixed", Fresh(_patches)), P("index", "count", 3, st.one_of(count, st.sampled_from(
                   ["2", 1.0, -1, np.int32(2), slice(0, 2)])))]))
    add(Target("BezierPatch.set_curvature", _set_curvature,
               [P("c00", "number", 0.5), P("c01", "number", 0.5), P("c10", "number", 0.5), P("c11", "number", 0.5)],
               numbers=("c00", "c01", "c10", "c11"), expect=_finite_colors("colors")))
    add(Target("BezierPatch.set_colors", _set_colors, [P("c00", "values", (0.1, 0.2, 0.3)), P("c11", "values", (1, 1, 1))]))
    add(Target("BezierPatches.write_cbez", lambda patches, path: patches.write_cbez(path),
               [P("patches", "fixed", Fresh(_patches)), P("path", "path", os.path.join(scratch(), "out.bez"))], examples=10))

    # colour maps
    for fname, extra in (("f1", []), ("h", []), ("f3", [P("tol", "number", 1e-9)]),
                         ("f2", [P("vmin", "number", None), P("vmax", "number", None)]),
                         ("dill", [P("vmin", "number", -0.07), P("vmax", "number", 0.03)]),
                         ("dill_names", [P("vmin", "number", -0.07), P("vmax", "number", 0.03)]),
                         ("symmetric", [P("vmax", "number", None)]), ("signed_log", [P("scale", "number", None),
                                                                                     P("vmax", "number", None)]),
                         ("percentile", [P("lower", "number", 2.0), P("upper", "number", 98.0)])):
        add(Target(f"colormaps.{fname}", getattr(C, fname), [P("x", "values", np.array([-1.0, 0.0, 2.0])), *extra],
                   numbers=tuple(p.name for p in extra), examples=30))
    add(Target("colormaps.colors_for", lambda values, color_map, options: C.colors_for(values, color_map, **options),
               [P("values", "values", np.array([-1.0, 0.0, 2.0])), P("color_map", "name", "linear", st.one_of(
                   name, st.sampled_from(list(C.COLOR_MAPS) + list(C.ColorMap)))),
                P("options", "name", {}, st.sampled_from([{"vmin": "a"}, {"vmax": np.inf}, {"tol": "x"}, {"x": 1},
                                                          {"vmin": 3.0, "vmax": 1.0}, {"chunk": 0}, {"chunk": 10**30}]))],
               examples=30))
    add(Target("colormaps.apply", lambda name_, values: C.apply(name_, values),
               [P("name_", "name", "linear"), P("values", "values", np.array([0.0, 1.0]))]))

    # measures and curvature helpers
    add(Target("curvature.as_mode", K.as_mode, [P("mode", "name", "gaussian")]))
    add(Target("curvature.classify", K.classify, [P("k1", "values", np.array([1.0, 0.0])),
                                                  P("k2", "values", np.array([1.0, -1.0])), P("tol", "number", 1e-8)]))
    add(Target("min_radius", _min_radius, [P("k1", "values", np.array([1.0, 0.0])),
                                              P("k2", "values", np.array([1.0, -1.0]))]))
    add(Target("draft_angle", lab.draft_angle, [P("normals", "values", np.array([[0.0, 0.0, 1.0]])),
                                                P("pull", "vector3", (0.0, 0.0, 1.0))]))

    # interrogation
    add(Target("geodesic", lambda surface, uv, angle, length, n_samples: lab.geodesic(surface, uv, angle, length,
                                                                                      n_samples=n_samples),
               [P("surface", "surface", torus), P("uv", "uv", (0.1, 0.1)), P("angle", "number", 0.3),
                P("length", "number", 1.0), P("n_samples", "count", 21)], numbers=("angle", "length")))
    add(Target("normal_section", lambda surface, uv, angle, length: lab.normal_section(surface, uv, angle, length),
               [P("surface", "surface", torus), P("uv", "uv", (0.1, 0.1)), P("angle", "number", 0.3),
                P("length", "number", 1.0)], numbers=("angle", "length"), examples=15))
    add(Target("geodesic_fan", lambda surface, uv, n_angles, length: lab.geodesic_fan(surface, uv, n_angles, length),
               [P("surface", "surface", torus), P("uv", "uv", (0.1, 0.1)), P("n_angles", "count", 6),
                P("length", "number", 0.5)], numbers=("n_angles", "length"), examples=15))
    add(Target("geodesic_between", lambda surface, uv_a, uv_b: lab.geodesic_between(surface, uv_a, uv_b),
               [P("surface", "surface", plane), P("uv_a", "uv", (0.1, 0.1)), P("uv_b", "uv", (0.8, 0.7))], examples=10))
    add(Target("polar_isodistance", lambda distances, samples_per_angle: lab.polar_isodistance(
        _fan(), distances, samples_per_angle=samples_per_angle),
        [P("distances", "values", [0.2]), P("samples_per_angle", "count", 4)], numbers=("distances", "samples_per_angle"),
        examples=15))
    add(Target("line_of_curvature", _line_of_curvature,
               [P("surface", "surface", surfaces.ellipsoid()), P("start", "uv", (0.3, 0.4)), P("which", "name", "k1"),
                P("length", "number", 0.5)], numbers=("length",), examples=15))
    add(Target("umbilics", lambda surface, n: lab.umbilics(surface, n=n),
               [P("surface", "surface", surfaces.ellipsoid()), P("n", "count", 8)], numbers=("n",), examples=10))
    add(Target("continuity", lambda obj, samples: lab.continuity(obj, samples=samples),
               [P("obj", "surface", surfaces.practical()), P("samples", "count", 5)], numbers=("samples",), examples=15))
    add(Target("probe", lambda surface, u, v, size: lab.probe(surface, u, v, size=size),
               [P("surface", "surface", torus), P("u", "param", 0.3), P("v", "param", 0.4), P("size", "number", None)],
               numbers=("u", "v", "size")))
    add(Target("comb", lambda surface, uv_, scale: lab.comb(surface, uv_, scale=scale),
               [P("surface", "surface", torus), P("uv_", "values", np.array([[0.1, 0.1], [0.5, 0.2], [0.9, 0.3]])),
                P("scale", "number", 0.1)], numbers=("scale",)))
    add(Target("iso_comb", lambda surface, direction, value, density: lab.iso_comb(surface, direction, value, density=density),
               [P("surface", "surface", torus), P("direction", "name", "u"), P("value", "number", 0.5),
                P("density", "count", 16)], numbers=("value", "density")))
    add(Target("border_combs", lambda surface, density, count_: lab.border_combs(surface, density=density, count=count_),
               [P("surface", "surface", torus), P("density", "count", 8), P("count_", "count", 1)],
               numbers=("density", "count_"), examples=15))
    for fname, extra in (("isophotes", [P("count", "count", 3)]), ("parabolic_lines", []),
                         ("focal_surface", [P("scale", "number", 1.0), P("function", "name", "mean", st.one_of(
                             name, function))]),
                         ("reflection_lines", [P("count", "count", 3), P("direction", "vector3", (1.0, 0.0, 0.0))]),
                         ("stripe_mapping", [P("n_stripes", "count", 4)]),
                         ("draft_map", [P("pull", "vector3", (0.0, 0.0, 1.0))]),
                         ("radius_map", [P("r", "number", 0.5)]), ("focal_sheets", [])):
        func = getattr(lab, fname)
        add(Target(fname, lambda surface, resolution, _f=func, **kw: _f(surface, resolution=resolution, **kw),
                   [P("surface", "surface", torus), P("resolution", "small", 8), *extra],
                   numbers=("resolution",) + tuple(p.name for p in extra if p.kind in ("number", "count")), examples=12))
    add(Target("band_lines", lambda surface, values_, levels: lab.band_lines(surface, values_, levels, resolution=8),
               [P("surface", "surface", torus), P("values_", "name", "gaussian"), P("levels", "values", [0.0])],
               numbers=("levels",), examples=12))
    add(Target("trimmed", lambda outer, holes: lab.trimmed(plane, outer, holes),
               [P("outer", "values", None), P("holes", "values", ())], examples=15))
    add(Target("BSplineLoop", lambda cp, knots_, degree: lab.BSplineLoop(cp, knots_, degree),
               [P("cp", "values", np.array([[0.2, 0.2], [0.8, 0.2], [0.8, 0.8], [0.2, 0.2]])),
                P("knots_", "values", np.array([0, 0, 1, 2, 3, 3.0])), P("degree", "count", 1)], numbers=("degree",)))

    # pictures, explorers, files
    add(Target("render.picture", _picture, [P("obj", "surface", plane), P("curvature", "name", "gaussian"),
                                            P("color_map", "name", "linear"), P("window_size", "uv", (64, 48)),
                                            P("resolution", "small", 1)], examples=6, expect=_not_blank))
    add(Target("CurvatureExplorer", lambda surface, depth, max_depth: lab.CurvatureExplorer(
        surface, depth=depth, max_depth=max_depth, window_size=(64, 48), live=False),
        [P("surface", "surface", plane), P("depth", "small", 0), P("max_depth", "small", 2)], examples=5))
    add(Target("read", lambda path_: lab.read(path_), [P("path_", "path", os.path.join(scratch(), "junk.step"))],
               examples=10))
    add(Target("write", lambda obj, path_: lab.write(obj, path_),
               [P("obj", "surface", plane), P("path_", "path", os.path.join(scratch(), "out.step"))], examples=8))

    # the language, the memory limit, the notebooks' helpers
    add(Target("set_language", _restoring_language, [P("lang", "name", "de")]))
    add(Target("set_memory_limit", _restoring_limit, [P("limit", "number", "1G", st.one_of(number, st.sampled_from(
        ["2G", "1.5 GiB", "lots", "-1G", "1e999G", "0", "nanG", "9" * 5000])))]))
    add(Target("exercise_mode", _exercise_mode, [P("on", "flag", True)]))
    add(Target("my_surface", lambda assignment: lab.my_surface(assignment), [P("assignment", "name", "05_visualize_curvature")]))
    add(Target("mark", lambda folder, assignment: lab.mark(folder, assignment),
               [P("folder", "path", os.path.join(scratch(), "empty")), P("assignment", "name", None)], examples=8))
    for task in ("f2", "h", "curvatures", "visualize_curvature"):
        add(Target(f"check.{task}", lambda obj, seed, timeout, _t=task: getattr(lab.check, _t)(obj, seed=seed, timeout=timeout),
                   [P("obj", "function", FUNCTIONS[0]), P("seed", "count", 1), P("timeout", "number", 20.0)],
                   examples=6, expect=_a_report))

    from .fuzz_cli import cli_targets

    found.extend(cli_targets())
    return found


# -- helpers of the targets -----------------------------------------------------------------------------------------

def _line_of_curvature(surface, start, which, length):
    """lab.line_of_curvature; its path's ``angle`` is NaN by design (a line of curvature has no start angle)."""
    import dataclasses

    path = lab.line_of_curvature(surface, start, which, length)
    assert np.isnan(path.angle)
    return dataclasses.replace(path, angle=0.0)


def _min_radius(k1, k2):
    """lab.min_radius, whose ``inf`` at flat points (κ1 = κ2 = 0) is the documented answer, not garbage; NaN is
    garbage unless a given curvature was NaN there (a degenerate point, flagged by whoever computed it)."""
    r = lab.min_radius(k1, k2)
    given_nan = np.isnan(np.asarray(k1, float)) | np.isnan(np.asarray(k2, float))
    return np.where(np.isposinf(r) | given_nan, 0.0, r)


def _from_sympy(xyz, domain):
    import sympy as sp

    u, v, a = sp.symbols("u v a")
    exprs = {"plane": (u, v, 0), "free symbol": (u, v, a * u), "two": (u, v), "strings": ("u", "v", "w"),
             "sqrt": (u, v, sp.sqrt(u - 2)), "huge": (u, v, sp.exp(1000 * u)), "none": (u, v, None),
             "division": (u, v, 1 / u), "constant": (0, 0, 0), "function": (u, v, sp.Function("f")(u))}[xyz]
    s = lab.ParametricSurface.from_sympy(exprs, (u, v), domain)
    return s.curvature(np.array([0.0, 0.5, 1.0]), 0.5)


def _reparametrized(map_u, domain):
    from lab.geometry.parameter_maps import ParameterMap  # noqa: F401 - the maps a CAD face uses have this shape

    def good(t):
        t = np.asarray(t, float)
        return t, np.ones_like(t), np.zeros_like(t)

    maps = {"good": good, "none": lambda t: None, "short": lambda t: (t,), "nan": lambda t: (t * np.nan, t, t),
            "raises": _raise, "decreasing": lambda t: (1 - np.asarray(t), -np.ones_like(t), np.zeros_like(t)),
            "scalar": lambda t: (0.5, 1.0, 0.0)}
    if map_u not in maps:
        return lab.ReparametrizedSurface(surfaces.plane(), map_u, good, domain).curvature(0.5, 0.5)
    return lab.ReparametrizedSurface(surfaces.plane(), maps[map_u], good, domain).curvature(np.array([0.2, 0.5]), 0.5)


def _visualize(patches, mode, color_map, options):
    if not isinstance(options, dict):
        options = {}
    patches.visualize_curvature(mode, color_map, **options)
    return patches


def _set_curvature(c00, c01, c10, c11):
    p = lab.BezierPatches(np.random.default_rng(35).random((2, 4, 4, 3)))
    for patch in p:
        patch.set_curvature(c00, c01, c10, c11)
    from lab.geometry.colormaps import colors_for

    colors_for(p.curvature, "linear", out=p.colors)
    return p


def _set_colors(c00, c11):
    p = lab.BezierPatches(np.random.default_rng(35).random((1, 4, 4, 3)))
    p[0].set_colors(c00, (0, 0, 0), (0.5, 0.5, 0.5), c11)
    return p


_FAN = {}


def _fan():
    if "fan" not in _FAN:
        _FAN["fan"] = lab.geodesic_fan(surfaces.torus(), (0.1, 0.1), 6, 0.5)
    return _FAN["fan"]


def _picture(obj, curvature, color_map, window_size, resolution):
    return lab.render.picture(obj, curvature, color_map, window_size=window_size, resolution=resolution, legend=False,
                              title=None)


def _not_blank(image, kwargs):
    """A picture asked for with a colour map shows coloured pixels, not only the background."""
    if image is None or kwargs.get("color_map") is None:
        return None
    img = np.asarray(image)
    if img.ndim == 3 and img.size and np.ptp(img.reshape(-1, img.shape[-1]), axis=0).max() == 0:
        return "a picture of nothing: every pixel the same"
    return None


def _restoring_language(lang):
    from lab.i18n import _normalise  # noqa: F401 - the check set_language runs

    before = lab.language()
    try:
        return lab.set_language(lang)
    finally:
        lab.set_language(before)
        os.environ["LAB_LANG"] = before


def _restoring_limit(limit):
    previous = lab.set_memory_limit(limit)
    try:
        return lab.memory_limit()
    finally:
        lab.set_memory_limit(previous)


def _exercise_mode(on):
    try:
        return lab.exercise_mode(on)
    finally:
        lab.exercise_mode(False)


def _a_report(result, kwargs):
    from lab.teaching.report import Report

    if not isinstance(result, Report):
        return f"a check returned {type(result).__name__}, not a Report"
    return None
