r"""The task of notebook 13: the Gaussian curvature of each vertex of a triangle mesh by the angle deficit.

``deficit_curvature(points, faces)`` gets a mesh, ``points`` (n, 3) and ``faces`` (f, 3) of integer vertex indices,
and returns ``(K, A)``: per vertex the mixed Voronoi area A (Meyer et al. 2003, §3.3, figure 4) and
:math:`K = (2\pi - \sum\theta)/A`, with π instead of 2π at a boundary vertex (one on an edge of only one face).

The cases: a regular octahedron (closed, every deficit 2π/3), a grid with its middle vertex lifted (one inner vertex,
eight on the boundary), a flat fan of obtuse triangles (the mixed area's rule), refined meshes of the lab's torus and
saddle (:func:`lab.mesh.triangle_mesh`), and random bumpy grids with random diagonals.  The reference is computed
here, independently of :mod:`lab.geometry.discrete`, with corner angles ``atan2(|a × b|, a · b)`` (accurate to
rounding; a test compares it with 40-digit arithmetic); a result passes within 10⁻⁹ rad of deficit and 10⁻⁷ relative
area.  The hints come from the same computation done each classic wrong way (2π at the boundary, degrees, no area,
the barycentric or the whole one-ring area, the Voronoi share without the obtuse rule, the obtuse rule turned round,
the sign), the simplest that reproduces the student's numbers.
"""

from functools import lru_cache
from itertools import product

import numpy as np

from ...i18n import N_, _
from ..task import CaseSpec, Hint, Task, fmt

__all__ = ["DEFICIT_CURVATURE", "MESHES_BLOCK", "reference"]

#: What computes the answer, or its parts (the deficit, the mixed area, the boundary, the corner angles).
MESHES_BLOCK = (
    "lab.geometry.discrete.corner_angles", "lab.geometry.discrete.angle_deficit",
    "lab.geometry.discrete.mixed_areas", "lab.geometry.discrete.gaussian_curvature",
    "lab.geometry.discrete.boundary_vertices", "lab.geometry.discrete.cotangent_laplacian",
    "lab.geometry.discrete.mean_curvature", "lab.interrogation.estimators.estimate",
)

_SUMMARY = N_("two arrays (K, A), one value per vertex each: the Gaussian curvature and the mixed area")

#: The ways of computing, the right one first: how the boundary is treated, the angles' unit, the area, the sign.
BOUNDARY = ("pi", "2pi")
UNITS = ("rad", "deg")
AREAS = ("mixed", "barycentric", "ring", "voronoi", "obtuse_swapped", "none")
SIGNS = (1, -1)


def _angles(P):
    a = np.roll(P, -1, axis=1) - P
    b = np.roll(P, 1, axis=1) - P
    return np.arctan2(np.linalg.norm(np.cross(a, b), axis=-1), np.einsum("fki,fki->fk", a, b))


def _boundary(faces, n):
    edges = np.sort(np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]]), axis=1)
    unique, count = np.unique(edges, axis=0, return_counts=True)
    out = np.zeros(n, dtype=bool)
    out[unique[count == 1].ravel()] = True
    return out


def _areas(P, theta, kind):
    """The share of each corner (f, 3) of a face's area under the area ``kind``."""
    area = 0.5 * np.linalg.norm(np.cross(P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]), axis=-1)[:, None]
    if kind == "barycentric":
        return np.repeat(area / 3, 3, axis=1)
    if kind in ("ring", "none"):
        return np.repeat(area, 3, axis=1)
    opposite = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)
    l2 = np.einsum("fki,fki->fk", opposite, opposite)
    cot = np.cos(theta) / np.sin(theta)
    voronoi = (np.roll(l2, -2, axis=1) * np.roll(cot, -2, axis=1) + np.roll(l2, -1, axis=1) * np.roll(cot, -1, axis=1)) / 8
    if kind == "voronoi":
        return voronoi
    obtuse = theta > np.pi / 2
    big, small = (0.5, 0.25) if kind == "mixed" else (0.25, 0.5)
    return np.where(obtuse.any(axis=1, keepdims=True), np.where(obtuse, big, small) * area, voronoi)


def reference(points, faces, *, boundary="pi", unit="rad", area="mixed", sign=1):
    """``(K, A)`` of a mesh, computed the right way or (for the hints) one of the wrong ones (:data:`BOUNDARY`,
    :data:`UNITS`, :data:`AREAS`, :data:`SIGNS`); ``area="none"`` gives the deficit itself as K."""
    points, faces = np.asarray(points, dtype=float), np.asarray(faces, dtype=np.intp)
    P = points[faces]
    theta = _angles(P)
    n = len(points)
    total = np.bincount(faces.ravel(), weights=theta.ravel(), minlength=n)
    full = np.where(_boundary(faces, n), np.pi if boundary == "pi" else 2 * np.pi, 2 * np.pi)
    deficit = sign * (full - total) * (180 / np.pi if unit == "deg" else 1.0)
    A = np.bincount(faces.ravel(), weights=_areas(P, theta, area).ravel(), minlength=n)
    return (deficit if area == "none" else deficit / A), A


# -- the cases ---------------------------------------------------------------------------------------------------


def _grid_faces(nu, nv, flips):
    """Two triangles per quad of an nu × nv grid (row-major vertices), counter-clockwise; ``flips`` (nu-1, nv-1)
    chooses the diagonal."""
    node = np.arange(nu * nv).reshape(nu, nv)
    a, b, c, d = node[:-1, :-1], node[1:, :-1], node[1:, 1:], node[:-1, 1:]
    f = flips[..., None]
    first = np.where(f, np.stack([a, b, d], -1), np.stack([a, b, c], -1)).reshape(-1, 3)
    second = np.where(f, np.stack([b, c, d], -1), np.stack([a, c, d], -1)).reshape(-1, 3)
    return np.concatenate([first, second])


def _octahedron():
    points = np.array([[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]], dtype=float)
    faces = np.array([[0, 2, 4], [2, 1, 4], [1, 3, 4], [3, 0, 4], [2, 0, 5], [1, 2, 5], [3, 1, 5], [0, 3, 5]])
    return points, faces


def _lifted_grid():
    x = np.arange(3.0)
    X, Y = np.meshgrid(x, x, indexing="ij")
    Z = np.zeros_like(X)
    Z[1, 1] = 0.5
    return np.stack([X, Y, Z], -1).reshape(-1, 3), _grid_faces(3, 3, np.zeros((2, 2), dtype=bool))


def _obtuse_fan():
    """A hexagon stretched three times along x, its centre raised a little: six obtuse triangles around one inner
    vertex, whose mixed area differs from the Voronoi area."""
    angle = np.arange(6) * np.pi / 3
    ring = np.column_stack([3 * np.cos(angle), np.sin(angle), np.zeros(6)])
    points = np.vstack([[0.0, 0.0, 0.25], ring])
    faces = np.array([[0, 1 + k, 1 + (k + 1) % 6] for k in range(6)])
    return points, faces


def _surface_mesh(kind, n, diagonals):
    points, faces = _surface_mesh_once(kind, n, diagonals)
    return points.copy(), faces.copy()


@lru_cache(maxsize=8)
def _surface_mesh_once(kind, n, diagonals):
    from ...mesh.triangles import mesh_arrays, triangle_mesh
    from ...model import surfaces

    surface = surfaces.torus() if kind == "torus" else surfaces.saddle()
    return mesh_arrays(triangle_mesh(surface, n, diagonals=diagonals, seed=n))


def _bumpy(rng, n):
    """A random bumpy n × n grid on a 1/8 grid, jittered in the plane, with random diagonals, faces in random order and
    each face's corners turned cyclically (the orientation kept)."""
    x = np.arange(n, dtype=float)
    X, Y = np.meshgrid(x, x, indexing="ij")
    X = X + rng.integers(-2, 3, X.shape) / 8
    Y = Y + rng.integers(-2, 3, Y.shape) / 8
    Z = rng.integers(-4, 5, X.shape) / 8
    faces = _grid_faces(n, n, rng.random((n - 1, n - 1)) < 0.5)
    faces = faces[rng.permutation(len(faces))]
    turn = rng.integers(0, 3, len(faces))
    faces = np.stack([np.roll(f, -t) for f, t in zip(faces, turn)])
    return np.stack([X, Y, Z], -1).reshape(-1, 3), faces


def _cases(rng, graded):
    fixed = [
        (_("a regular octahedron: closed, every vertex's deficit 2π − 4·60° = 2π/3"), _octahedron()),
        (_("a 3 × 3 grid with its middle vertex lifted: one inner vertex, eight on the boundary (π − Σθ there)"),
         _lifted_grid()),
        (_("a fan of six obtuse triangles around one inner vertex: the mixed area's rule for obtuse triangles"),
         _obtuse_fan()),
        (_("the torus (R = 2, r = 1), 12 × 12 vertices: closed, K from −1 to 1/3"),
         _surface_mesh("torus", 12, "regular")),
        (_("the saddle z = x² − y², 9 × 9 vertices, diagonals alternating: with a boundary"),
         _surface_mesh("saddle", 9, "alternating")),
    ]
    if graded:
        fixed += [(_("the saddle refined, 16 × 16 vertices, random diagonals"), _surface_mesh("saddle", 16, "random")),
                  (_("the torus refined, 16 × 16 vertices, random diagonals"), _surface_mesh("torus", 16, "random"))]
    cases = [CaseSpec(name, (np.asarray(p, dtype=float), np.asarray(f, dtype=np.int64))) for name, (p, f) in fixed]
    for k in range(3 if graded else 1):
        n = int(rng.integers(4, 7))
        points, faces = _bumpy(rng, n)
        cases.append(CaseSpec(_("a random bumpy {n} × {n} grid, random diagonals, no. {k}").format(n=n, k=k + 1),
                              (points, faces.astype(np.int64))))
    return cases


# -- judging -------------------------------------------------------------------------------------------------------

_HINTS = {
    "2pi": N_("at a boundary vertex (on an edge of only one triangle) the angles of a flat half-disc add up to π: its "
              "deficit is π − Σθ, not 2π − Σθ."),
    "deg": N_("the angles are in degrees: the deficit needs radians (np.arccos and np.arctan2 give radians; "
              "2π − Σθ)."),
    "none": N_("K is the deficit per area: divide each vertex's angle deficit by its mixed area A (you returned the "
               "deficit itself)."),
    "barycentric": N_("you divided by a third of the adjacent triangles' area (the barycentric area): the task asks "
                      "for the mixed Voronoi area, ⅛(|PQ|² cot R + |PR|² cot Q) of a triangle PQR at P (Meyer et al. "
                      "2003, §3.3)."),
    "ring": N_("you divided by the whole area of the adjacent triangles: a vertex has only its share of each, the "
               "mixed Voronoi area ⅛(|PQ|² cot R + |PR|² cot Q) of a triangle PQR at P."),
    "voronoi": N_("in a triangle with an obtuse angle the Voronoi share does not lie in the triangle: there the mixed "
                  "area gives half the triangle's area to the obtuse corner and a quarter to each other corner."),
    "obtuse_swapped": N_("in an obtuse triangle the obtuse corner gets half of the triangle's area and the two others "
                         "a quarter each, not the other way round."),
    "sign": N_("the sign: the deficit is 2π − Σθ (positive at the tip of a cone), not Σθ − 2π."),
}


def _simplest(points, faces, K, tolerance):
    """The mistakes (keys of :data:`_HINTS`) of the simplest wrong computation whose K matches ``K``, or None."""
    options = []
    for boundary, unit, area, sign in product(BOUNDARY, UNITS, AREAS, SIGNS):
        mistakes = [m for m, right in ((boundary, "pi"), (unit, "rad"), (area, "mixed")) if m != right]
        mistakes += ["sign"] if sign < 0 else []
        if mistakes:
            options.append((len(mistakes), mistakes, (boundary, unit, area, sign)))
    for _count, mistakes, (boundary, unit, area, sign) in sorted(options, key=lambda o: o[0]):
        wrong, _A = reference(points, faces, boundary=boundary, unit=unit, area=area, sign=sign)
        if np.all(np.isfinite(wrong)) and np.all(np.abs(K - wrong) <= tolerance(wrong)):
            return mistakes
    return None


def _hint(mistakes):
    texts = [_(_HINTS[m]) for m in mistakes]
    text = texts[0] if len(texts) == 1 else _("{n} mistakes: {list}").format(
        n=len(texts), list=" ".join(f"({k + 1}) {t}" for k, t in enumerate(texts)))
    return Hint(text, "+".join(mistakes))


def _tolerance(A):
    """Per vertex: 10⁻⁹ rad of deficit over the area and 10⁻⁷ relative."""
    return lambda K: 1e-7 * np.abs(K) + 1e-9 / np.abs(A)


def _judge(case, value, exp):
    K_exp, A_exp = (np.asarray(x, dtype=float) for x in exp)
    n = len(K_exp)
    shown = fmt(K_exp)
    if isinstance(value, np.ndarray) and value.shape == (2, n):
        value = list(value)
    if isinstance(value, np.ndarray) and value.shape == (n,):
        return False, shown, fmt(value), _("return two arrays, (K, A): the curvature and the area it is divided by.")
    if not isinstance(value, list) or len(value) != 2 or any(v.shape != (n,) for v in value):
        got = fmt(value) if isinstance(value, np.ndarray) else (
            ", ".join(str(v.shape) for v in value) if isinstance(value, list) else repr(value))
        return False, shown, got, _("return {what}.").format(what=_(_SUMMARY)) + " " + _(
            "This mesh has {n} vertices.").format(n=n)
    K, A = value
    if not (np.all(np.isfinite(K)) and np.all(np.isfinite(A))):
        return False, shown, fmt(K), _("NaN or inf: every vertex of these meshes has triangles around it and a "
                                       "positive mixed area.")
    k_ok = bool(np.all(np.abs(K - K_exp) <= _tolerance(A_exp)(K_exp)))
    a_ok = bool(np.all(np.abs(A - A_exp) <= 1e-7 * np.abs(A_exp)))
    if k_ok and a_ok:
        return True, shown, fmt(K), ""
    points, faces = case.args
    if k_ok:
        found = _simplest_area(points, faces, A)
        hint = Hint(_(_HINTS[found]), found) if found else _(
            "K is right but A is not the area you divided by: return the mixed area of each vertex.")
        return False, fmt(A_exp), fmt(A), hint
    mistakes = _simplest(points, faces, K, _tolerance(A_exp)) or _separately(points, faces, K, A)
    if mistakes:
        return False, shown, fmt(K), _hint(mistakes)
    if np.allclose(K * A, K_exp * A_exp, rtol=1e-7, atol=1e-9):
        return False, shown, fmt(K), _("the deficits are right (K · A agrees) but the area is not the mixed area: "
                                       "per triangle PQR, ⅛(|PQ|² cot R + |PR|² cot Q) at P, or area/2 at an obtuse "
                                       "corner and area/4 at the others.")
    return False, shown, fmt(K), _("K = (2π − Σθ)/A with the corner angles θ of the triangles at the vertex (π − Σθ "
                                   "at a boundary vertex) and A the mixed area (Meyer et al. 2003).")


def _separately(points, faces, K, A):
    """The mistakes of the deficit K · A and of the area A, each judged on its own (when the student's area is not
    one of the ways above, e.g. cotangents of angles in degrees): a list, or None when either is unexplained."""
    deficit = K * A
    found = []
    for boundary, unit, sign in product(BOUNDARY, UNITS, SIGNS):
        wrong = reference(points, faces, boundary=boundary, unit=unit, area="none", sign=sign)[0]
        if np.allclose(deficit, wrong, rtol=1e-7, atol=1e-9):
            found = [m for m, right in ((boundary, "pi"), (unit, "rad")) if m != right] + (["sign"] if sign < 0 else [])
            break
    else:
        return None
    area = "mixed" if np.allclose(A, reference(points, faces)[1], rtol=1e-7, atol=0) else _simplest_area(points, faces, A)
    if area is None and "deg" not in found:
        return None
    return (found + ([area] if area not in (None, "mixed") else [])) or None


def _simplest_area(points, faces, A):
    for kind in AREAS[1:-1]:
        if np.allclose(A, reference(points, faces, area=kind)[1], rtol=1e-7, atol=0):
            return kind
    return None


def _error_hint(case, message):
    if "IndexError" in message:
        return _("faces holds vertex indices (f, 3): points[faces] gives the corners, shape (f, 3, 3).")
    if "ZeroDivision" in message or "divide" in message:
        return _("every vertex of these meshes lies on at least one triangle of positive area.")
    return ""


DEFICIT_CURVATURE = Task("deficit_curvature", _cases, lambda c: reference(*c.args), _judge, blocked=MESHES_BLOCK,
                         foreign=("libigl", "trimesh"),  # igl.gaussian_curvature and igl.massmatrix(VORONOI) are the
                                                         # deficit and the mixed area; trimesh's measures the deficit
                         allowed="numpy (np.cross, np.linalg.norm, np.arctan2 or np.arccos, np.bincount or np.add.at, "
                                 "np.unique)", error_hint=_error_hint, summary=_SUMMARY)
