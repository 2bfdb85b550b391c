r"""The task of notebook 11: which faces of a part are developable (K ≡ 0)?

``developable_faces(model)`` gets a :class:`lab.Model` – faces with their NURBS surfaces, as
:func:`lab.read` gives them – and returns the file indices (``face.index``) of the faces whose surface is
developable: Gaussian curvature zero everywhere, judged with the tolerance the notebook states,

.. math:: \max |K| \cdot s^2 \le 10^{-6},

where s is the diagonal of the box around the face's control points (K has the unit 1/length², so K s² is
the same for a part in millimetres and in metres).

The truth of every case is known by construction, not by sampling: planes, exact rational cylinders and
cones, extrusions of a B-spline curve (generalised cylinders) and pieces of the tangent surface of a cubic
(c(u) + v c'(u) with v > 0, developable although its rulings are neither parallel nor concurrent) have
K ≡ 0 (``tests/test_check_models.py`` proves it with sympy); a band of a sphere, a twisted bilinear patch
(a hyperbolic paraboloid: ruled but not developable) and a plane with one control point lifted (a bump
that leaves K = 0 at the corners and along the border) do not.  Faces come rotated, at any scale and with
gaps in their file indices, as in a real file whose unreadable faces are listed in ``model.problems``.

A wrong answer is compared with the answers of the usual mistakes (deciding by the face's kind, by H, by
degree 1 in a direction, at the corners only, with an absolute tolerance, positions instead of file indices)
so that the hint names the mistake.
"""

import itertools

import numpy as np

from ...i18n import N_, _, decimal
from ..task import CaseSpec, Hint, Task, fmt

__all__ = ["DEVELOPABLE_FACES", "TOLERANCE", "relative_gaussian"]

#: max |K| s² at or below this: developable (the notebook states it).
TOLERANCE = 1e-6

_SUMMARY = N_("the file indices (face.index) of the developable faces, e.g. [0, 3, 7]")

#: kinds as a file names them (lab.read's face.kind): extrusions and tangent surfaces come as B-splines
_KIND = {"plane": "Plane", "cylinder": "Cylinder", "cone": "Cone", "extrusion": "BSplineSurface",
         "tangent": "BSplineSurface", "sphere": "Sphere", "twisted": "BSplineSurface", "bump": "BSplineSurface"}
DEVELOPABLE = ("plane", "cylinder", "cone", "extrusion", "tangent")
CURVED = ("sphere", "twisted", "bump")


# -- faces, exact by construction ------------------------------------------------------------------------------

def _arc(angle):
    """Control points (3, 2) and weights (3,) of the unit circle's arc from 0 to ``angle`` (< π), rational
    quadratic (The NURBS Book, section 7.3: the middle weight is cos(angle/2))."""
    h = angle / 2
    P = np.array([[1.0, 0.0], [1.0, np.tan(h)], [np.cos(angle), np.sin(angle)]])
    return P, np.array([1.0, np.cos(h), 1.0])


def _bezier_knots(degree):
    return np.r_[np.zeros(degree + 1), np.ones(degree + 1)]


def _face(name, P, knots_u, knots_v, degree_u, degree_v, W=None):
    return {"name": name, "P": np.asarray(P, dtype=float), "knots_u": np.asarray(knots_u, dtype=float),
            "knots_v": np.asarray(knots_v, dtype=float), "degree": (int(degree_u), int(degree_v)),
            "W": None if W is None else np.asarray(W, dtype=float)}


def _plane(rng):
    a, b = rng.uniform(0.5, 2.0, 2)
    skew = rng.uniform(-0.3, 0.3)
    P = np.array([[[0, 0, 0], [skew, b, 0]], [[a, 0, 0], [a + skew, b, 0]]], dtype=float)
    return _face("plane", P, _bezier_knots(1), _bezier_knots(1), 1, 1)


def _cylinder(rng):
    r, h = rng.uniform(0.5, 2.0), rng.uniform(0.5, 3.0)
    C, w = _arc(rng.uniform(0.5, 2.5))
    P = np.stack([np.column_stack([r * C, np.full(3, z)]) for z in (0.0, h)], axis=1)
    return _face("cylinder", P, _bezier_knots(2), _bezier_knots(1), 2, 1, np.column_stack([w, w]))


def _cone(rng):
    r, h = rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0)
    v0, v1 = rng.uniform(0.2, 0.5), rng.uniform(0.8, 1.0)  # the apex (v = 0) stays outside
    C, w = _arc(rng.uniform(0.5, 2.5))
    apex = np.array([0.0, 0.0, h])
    base = np.column_stack([r * C, np.zeros(3)])
    P = np.stack([apex + t * (base - apex) for t in (v0, v1)], axis=1)
    return _face("cone", P, _bezier_knots(2), _bezier_knots(1), 2, 1, np.column_stack([w, w]))


def _extrusion(rng):
    """A cubic B-spline curve with two interior knots, extruded along a direction across its plane-ish shape."""
    c = np.column_stack([np.arange(6.0) / 2, rng.uniform(-0.8, 0.8, 6), rng.uniform(-0.3, 0.3, 6)])
    d = np.array([0.0, 0.0, 1.0]) * rng.uniform(1.0, 2.5) + np.r_[rng.uniform(-0.3, 0.3, 2), 0]
    P = np.stack([c, c + d], axis=1)
    return _face("extrusion", P, [0, 0, 0, 0, 1, 2, 3, 3, 3, 3], _bezier_knots(1), 3, 1)


def _tangent(rng):
    """The tangent surface c(u) + v c'(u) of a cubic Bézier curve with curvature and torsion, for v in [a, b]
    with a > 0 (v = 0 is its edge of regression, where it is singular)."""
    while True:
        c = np.array([[0, 0, 0], [1, 0, 0], [1.6, 1.0, 0.3], [1.8, 2.0, 1.2]], dtype=float)
        c += rng.uniform(-0.15, 0.15, c.shape)
        d = 3 * np.diff(c, axis=0)  # c'(u): quadratic, control points d_0..d_2
        e = np.array([d[0], (d[0] + 2 * d[1]) / 3, (2 * d[1] + d[2]) / 3, d[2]])  # elevated to degree 3
        u = np.linspace(0, 1, 41)[:, None]
        dc = 3 * ((1 - u) ** 2 * (c[1] - c[0]) + 2 * u * (1 - u) * (c[2] - c[1]) + u**2 * (c[3] - c[2]))
        ddc = 6 * ((1 - u) * (c[2] - 2 * c[1] + c[0]) + u * (c[3] - 2 * c[2] + c[1]))
        if np.min(np.linalg.norm(np.cross(dc, ddc), axis=1)) > 0.5:  # curved all along: the surface is regular
            break
    a, b = rng.uniform(0.15, 0.3), rng.uniform(0.5, 0.8)
    P = np.stack([c + a * e, c + b * e], axis=1)
    return _face("tangent", P, _bezier_knots(3), _bezier_knots(1), 3, 1)


def _sphere(rng):
    """A band of a sphere: a meridian arc (rational quadratic) revolved by a circle arc, away from the poles."""
    R = rng.uniform(0.5, 2.0)
    lat0 = rng.uniform(0.1, 0.5)
    M, wm = _arc(rng.uniform(0.4, 0.9))  # meridian from latitude 0 in its own plane
    rot = np.array([[np.cos(lat0), -np.sin(lat0)], [np.sin(lat0), np.cos(lat0)]])
    M = M @ rot.T  # (radius in the xy-plane, z)
    C, wc = _arc(rng.uniform(0.5, 2.0))
    P = np.array([[[M[j, 0] * C[i, 0], M[j, 0] * C[i, 1], M[j, 1]] for j in range(3)] for i in range(3)]) * R
    return _face("sphere", P, _bezier_knots(2), _bezier_knots(2), 2, 2, np.outer(wc, wm))


def _twisted(rng):
    """A bilinear patch with one corner lifted: a hyperbolic paraboloid, straight lines both ways, K < 0."""
    a, b = rng.uniform(0.8, 2.0, 2)
    t = rng.uniform(0.1, 0.3) * min(a, b)
    P = np.array([[[0, 0, 0], [0, b, 0]], [[a, 0, 0], [a, b, t]]], dtype=float)
    return _face("twisted", P, _bezier_knots(1), _bezier_knots(1), 1, 1)


def _bump(rng):
    """A bicubic B-spline plane, 7 × 7 control points, one interior point lifted: K = 0 at the corners and
    along the border rows' spans far from it, K ≠ 0 around it."""
    x = np.arange(7.0) / 2
    X, Y = np.meshgrid(x, x, indexing="ij")
    P = np.stack([X, Y, np.zeros_like(X)], axis=-1)
    i, j = rng.integers(2, 5, 2)
    P[i, j, 2] = rng.uniform(0.08, 0.15) * (1 if rng.uniform() < 0.5 else -1)
    knots = [0, 0, 0, 0, 1, 2, 3, 4, 4, 4, 4]
    return _face("bump", P, knots, knots, 3, 3)


_MAKERS = {"plane": _plane, "cylinder": _cylinder, "cone": _cone, "extrusion": _extrusion, "tangent": _tangent,
           "sphere": _sphere, "twisted": _twisted, "bump": _bump}


def _rotation(rng):
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    return Q if np.linalg.det(Q) > 0 else -Q


def _model(rng, names, scale=1.0, start=0):
    """Faces in a random order, rotated, moved and scaled, with file indices that skip some numbers."""
    faces = [_MAKERS[n](rng) for n in names]
    order = rng.permutation(len(faces))
    indices = start + np.cumsum(rng.integers(1, 3, len(faces))) - 1
    out = []
    for index, k in zip(indices, order):
        f = dict(faces[k])
        Q, shift = _rotation(rng), rng.uniform(-2, 2, 3)
        f["P"] = scale * (f["P"] @ Q.T + shift)
        f["index"], f["kind"] = int(index), _KIND[f["name"]]
        out.append(f)
    return out


def _args(faces):
    args = [float(len(faces))]
    for f in faces:
        W = f["W"] if f["W"] is not None else np.zeros(0)
        args += [float(f["index"]), f["kind"], f["P"], f["knots_u"], f["knots_v"], float(f["degree"][0]),
                 float(f["degree"][1]), W]
    return tuple(args)


def _case(name, faces, weight=1.0):
    return CaseSpec(name, _args(faces), weight, info={"faces": faces})


def _cases(rng, graded):
    """Every kind in one model; the same at the scale of a car body (s ≈ 1000) and of a watch part
    (s ≈ 0.001); curved faces only (the answer is empty); developable faces only; random mixtures."""
    every = DEVELOPABLE + CURVED
    cases = [
        _case(_("a part with every kind of face: plane, cylinder, cone, extrusion, tangent surface, sphere band, "
                "twisted bilinear patch, plane with a bump"), _model(rng, every)),
        _case(_("the same kinds at the size of a car body (s ≈ 1000 length units)"),
              _model(rng, ("cylinder", "extrusion", "twisted", "bump", "sphere"), scale=400.0)),
        _case(_("the same kinds at the size of a watch part (s ≈ 0.001)"),
              _model(rng, ("cone", "tangent", "plane", "bump", "sphere"), scale=4e-4)),
        _case(_("curved faces only: no face is developable (the answer is empty)"),
              _model(rng, ("sphere", "twisted", "bump"), start=3)),
        _case(_("developable faces only"), _model(rng, DEVELOPABLE, start=1)),
    ]
    for k in range(4 if graded else 2):
        names = list(rng.choice(every, size=int(rng.integers(4, 8)), replace=True))
        names += [rng.choice(DEVELOPABLE), rng.choice(CURVED)]  # at least one of each
        scale = float(10.0 ** rng.uniform(-2, 2))
        cases.append(_case(_("random part no. {k}: {n} faces, size about {s}").format(
            k=k + 1, n=len(names), s=decimal(f"{2 * scale:.2g}")), _model(rng, names, scale=scale)))
    return cases


def _expected(case):
    return np.array(sorted(f["index"] for f in case.info["faces"] if f["name"] in DEVELOPABLE), dtype=float)


# -- what the usual mistakes answer -----------------------------------------------------------------------------

def _surface(f):
    from ...model.surface import BSplineSurface

    return BSplineSurface(f["P"], f["knots_u"], f["knots_v"], *f["degree"], weights=f["W"])


def _size(f):
    P = f["P"].reshape(-1, 3)
    return float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))


def relative_gaussian(surface, n=41):
    """max |K| s² and max |H| s on an ``n × n`` grid over each knot span's closure (the decision's numbers)."""
    (u0, u1), (v0, v1) = surface.domain
    ku, kv = (np.unique(np.clip(k, a, b)) for k, (a, b) in zip((surface.knots_u, surface.knots_v), surface.domain))
    u = np.unique(np.concatenate([np.linspace(a, b, 9) for a, b in itertools.pairwise(ku)] + [np.linspace(u0, u1, n)]))
    v = np.unique(np.concatenate([np.linspace(a, b, 9) for a, b in itertools.pairwise(kv)] + [np.linspace(v0, v1, n)]))
    c = surface.curvature_grid(u, v)
    P = surface.control_points.reshape(-1, 3)
    s = float(np.linalg.norm(P.max(axis=0) - P.min(axis=0)))
    return float(np.max(np.abs(c.K))) * s**2, float(np.max(np.abs(c.H))) * s


def _corners(surface):
    (u0, u1), (v0, v1) = surface.domain
    c = surface.curvature(np.array([u0, u0, u1, u1]), np.array([v0, v1, v0, v1]))
    return float(np.max(np.abs(c.K)))


def _mistakes(faces):
    """``{key: sorted indices}``: what each usual mistake answers on these faces."""
    out = {"kind": [], "H": [], "ruled": [], "corners": [], "absolute": [], "not": []}
    for f in faces:
        surface, s, i = _surface(f), _size(f), f["index"]
        kn, hn = relative_gaussian(surface)
        if f["kind"] in ("Plane", "Cylinder", "Cone"):
            out["kind"].append(i)
        if hn <= TOLERANCE:
            out["H"].append(i)
        if 1 in f["degree"]:
            out["ruled"].append(i)
        if _corners(surface) * s**2 <= TOLERANCE:
            out["corners"].append(i)
        if kn / s**2 <= TOLERANCE:
            out["absolute"].append(i)
        if f["name"] not in DEVELOPABLE:
            out["not"].append(i)
    return {k: sorted(v) for k, v in out.items()}


def _first(faces, indices, names):
    """The first face (in file order) among ``indices`` whose construction is one of ``names``."""
    return next((f for f in sorted(faces, key=lambda f: f["index"]) if f["index"] in indices and f["name"] in names),
                None)


def _hint(case, got, exp):
    faces = case.info["faces"]
    got_set, exp_set = set(got), set(exp)
    indices = {f["index"] for f in faces}
    positions = [k for k, f in enumerate(faces) if f["index"] in exp_set]
    if got_set == set(positions) and got_set != exp_set:
        return Hint(_("these are positions in model.faces, not file indices: return face.index of each developable "
                      "face (a file's indices can have gaps, where a face could not be read)."), "positions")
    stray = sorted(got_set - indices)
    if stray:
        return Hint(_("{i} is not the index of a face of this model: return face.index of the developable faces.").format(
            i=stray[0]), "stray")
    m = _mistakes(faces)
    extra, missing = sorted(got_set - exp_set), sorted(exp_set - got_set)
    # the answer of a usual mistake, exactly: that mistake's hint (the order decides where two mistakes agree)
    if got_set == set(m["not"]):
        return Hint(_("these are the faces that are NOT developable: a developable face has K = 0 everywhere."), "not")
    f = _first(faces, missing, ("cylinder", "cone"))
    if got_set == set(m["H"]) and f is not None:
        return Hint(_("face {i} ({kind}) is developable: K = κ1·κ2 = 0 although H ≠ 0 there; decide by K, "
                      "not by H (one principal curvature may be non-zero).").format(i=f["index"], kind=f["kind"]), "H")
    f = _first(faces, missing, ("extrusion", "tangent"))
    if got_set == set(m["kind"]) and f is not None:
        return Hint(_("face {i} is a B-spline surface and still developable (an extrusion or the tangent surface of "
                      "a curve): decide by K on the surface, not by the face's kind.").format(i=f["index"]), "kind")
    f = _first(faces, extra, CURVED)
    if got_set == set(m["absolute"]) and f is not None:
        kn, size = relative_gaussian(_surface(f))[0], _size(f)
        return Hint(_("face {i} is large (s ≈ {s}): its |K| is small in absolute terms, but max |K|·s² ≈ {k}. Compare "
                      "K·s² with 1e-6, not K: K has the unit 1/length².").format(i=f["index"], s=decimal(f"{size:.3g}"),
                                                                                   k=decimal(f"{kn:.2g}")), "absolute")
    f = _first(faces, extra, ("twisted",))
    if f is not None:
        kn = relative_gaussian(_surface(f))[0]
        return Hint(_("face {i} is made of straight lines (a twisted bilinear patch, a hyperbolic paraboloid) but not "
                      "developable: K < 0, max |K|·s² ≈ {k}. Ruled is not developable: the tangent plane must stay the "
                      "same along each line.").format(i=f["index"], k=decimal(f"{kn:.2g}")), "ruled")
    f = _first(faces, extra, ("bump",))
    if f is not None and f["index"] in m["corners"] and f["index"] not in m["absolute"]:
        kn = relative_gaussian(_surface(f))[0]
        return Hint(_("face {i} is flat at its corners and along its border, but a control point inside is lifted: "
                      "max |K|·s² ≈ {k} inside. Sample the whole face (every knot span, its interior too), not only "
                      "corners.").format(i=f["index"], k=decimal(f"{kn:.2g}")), "corners")
    if missing:
        f = _first(faces, missing, DEVELOPABLE)
        s = _size(f)
        if s < 0.1:
            return Hint(_("face {i} is developable; it is tiny (s ≈ {s}), so rounding noise in K is large in absolute "
                          "terms: compare K·s² with 1e-6, not K.").format(i=f["index"], s=decimal(f"{s:.2g}")), "tiny")
        kn = relative_gaussian(_surface(f))[0]
        return Hint(_("face {i} ({kind}) is developable: K = 0 everywhere (max |K|·s² ≈ {k}, rounding), yet your "
                      "answer leaves it out.").format(i=f["index"], kind=f["kind"], k=decimal(f"{kn:.1g}")), "missing")
    f = _first(faces, extra, CURVED)
    kn = relative_gaussian(_surface(f))[0]
    return Hint(_("face {i} ({kind}) is not developable: max |K|·s² ≈ {k} on it.").format(
        i=f["index"], kind=f["kind"], k=decimal(f"{kn:.2g}")), "extra")


def _judge(case, value, exp):
    exp = np.asarray(exp, dtype=float)
    if not isinstance(value, np.ndarray) or value.ndim > 1 or not np.all(np.isfinite(value)) or np.any(
            value != np.round(value)):
        got = fmt(value) if isinstance(value, np.ndarray) else repr(value)
        return False, fmt(exp), got, _("return {what}.").format(what=_(_SUMMARY))
    got = np.unique(value.astype(int))
    shown = lambda a: str(sorted(int(x) for x in np.ravel(a)))  # file indices as integers: [1, 3, 6]
    if len(got) != value.size:
        return False, shown(exp), shown(value), _("each face once: an index appears twice in your answer.")
    ok = set(got.tolist()) == set(exp.astype(int).tolist())
    return ok, shown(exp), shown(value), "" if ok else _hint(case, got.tolist(), exp.astype(int).tolist())


def _error_hint(case, message):
    if "AttributeError" in message:
        return _("a face has .index, .kind and .surface (a lab.BSplineSurface with .domain, .control_points and "
                 ".curvature(u, v)); the model has .faces.")
    return ""


#: The library functions that would answer the task for the student: none — the exact curvature is the tool
#: the notebook teaches them to use; the judgement (where to look, how to compare) is theirs.
DEVELOPABLE_FACES = Task("developable_faces", _cases, _expected, _judge, protocol="model",
                         allowed="surface.curvature(u, v), surface.curvature_grid(u, v), numpy",
                         error_hint=_error_hint, summary=_SUMMARY)
