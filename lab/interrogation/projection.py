r"""The nearest point of a part to each of many points: exact foot points on the faces (``lab.deviation``'s core).

For a point :math:`\mathbf p` and a face :math:`\mathbf S(u, v)` the foot point minimises
:math:`f(u, v) = \tfrac12|\mathbf S(u, v) - \mathbf p|^2`.  With :math:`\mathbf r = \mathbf S - \mathbf p` its
gradient and Hessian are

.. math::

    \nabla f = (\mathbf S_u\cdot\mathbf r,\ \mathbf S_v\cdot\mathbf r), \qquad
    \nabla^2 f = \begin{pmatrix} \mathbf S_u\cdot\mathbf S_u + \mathbf S_{uu}\cdot\mathbf r &
    \mathbf S_u\cdot\mathbf S_v + \mathbf S_{uv}\cdot\mathbf r \\ \cdot &
    \mathbf S_v\cdot\mathbf S_v + \mathbf S_{vv}\cdot\mathbf r \end{pmatrix},

and Newton's method on :math:`\nabla f = 0` converges quadratically from a good start (Piegl & Tiller, *The
NURBS Book*, 1997, §6.1, eqs. 6.5–6.7 state the same iteration as "point inversion").  The start is the nearest
vertex of a fine mesh of every face (a k-d tree, ``scipy.spatial.cKDTree``): the faces among a point's nearest
vertices are the candidates, and the candidate with the nearest foot wins.  Where the Hessian is not positive
definite (far from a concave face) the Gauss–Newton matrix :math:`J^\top J` takes its place; a step that
lengthens :math:`|\mathbf r|` is halved.

**Trims are respected.**  A foot whose (u, v) falls outside the face's trimmed region (or its domain) is not the
face's nearest point: the nearest point then lies on the face's border, and it is found on the trimming loops
(the lab's polylines of the loops, :class:`lab.trimming.TrimmedSurface`) by the one-dimensional Newton iteration
along the nearest loop segments, each a straight line in (u, v) mapped by the exact surface.
"""

from typing import NamedTuple

import numpy as np
from scipy.spatial import cKDTree

from ..geometry import validation as _v
from .faces import face_surface, is_face, is_model

__all__ = ["Feet", "Piece", "closest_points", "piece_triangles", "pieces", "seeds"]

#: Newton steps at most (quadratic convergence needs 3 to 6 from the mesh's nearest vertex).
MAX_STEPS = 40
#: A foot has converged when its last step moved it by less than this fraction of the part's size.
STEP_RTOL = 1e-13
#: The spacing of the mesh whose vertices start the search: this many steps across the part's size.
SEED_LINES = 160
#: The nearest mesh vertices whose faces are tried.
NEIGHBOURS = 8


class Piece(NamedTuple):
    """One face of a part as the projection sees it: its surface (the file's parameters), trimmed region,
    orientation and index."""

    index: int
    surface: object
    trim: object
    reversed: bool
    closed: tuple = (False, False)

    @property
    def period(self):
        """The length of the domain in each direction where the surface closes on itself (a full cylinder's
        angle), else 0: the foot's (u, v) wrap around there instead of stopping at the domain's end."""
        lo, hi = self.box
        return np.where(np.array(self.closed), hi - lo, 0.0)

    @property
    def box(self):
        """The (u, v) box the foot is kept in: the trim's loops' box within the domain, else the domain."""
        (u0, u1), (v0, v1) = self.surface.domain
        return np.array([u0, v0]), np.array([u1, v1])

    def loops(self):
        """The borders of the face in (u, v): the trimming loops, or the domain's rectangle."""
        if self.trim is not None:
            return [np.asarray(loop, dtype=float) for loop in self.trim.loops]
        lo, hi = self.box
        return [np.array([lo, [hi[0], lo[1]], hi, [lo[0], hi[1]]])]

    def inside(self, uv):
        """Which ``uv`` (k, 2) lie in the face's trimmed region (the domain, for an untrimmed face)."""
        if self.trim is not None:
            return np.asarray(self.trim.contains(uv[:, 0], uv[:, 1]), dtype=bool)
        lo, hi = self.box
        eps = np.where(np.array(self.closed), -1.0, 1e-12) * (hi - lo)  # a closed direction has no border
        return np.all((uv >= lo + eps) & (uv <= hi - eps), axis=1)

    def normal(self, uv):
        """The face's unit normal at ``uv`` (turned on a reversed face)."""
        N = self.surface.normal(uv[:, 0], uv[:, 1])
        return -N if self.reversed else N


def _closed(surface):
    """Whether the surface closes on itself in u and in v: its two ends of the domain are one curve (to 1e-10 of
    its size at 9 points), as a full cylinder's angle does; a spline's periodic flag need not say so."""
    (u0, u1), (v0, v1) = surface.domain
    t = np.linspace(0.0, 1.0, 9)
    out = []
    for axis in (0, 1):
        if axis == 0:
            a, b = surface.evaluate(np.full(9, u0), v0 + t * (v1 - v0)), surface.evaluate(np.full(9, u1), v0 + t * (v1 - v0))
        else:
            a, b = surface.evaluate(u0 + t * (u1 - u0), np.full(9, v0)), surface.evaluate(u0 + t * (u1 - u0), np.full(9, v1))
        size = float(np.linalg.norm(np.ptp(np.concatenate([a, b]), axis=0)))
        out.append(bool(size > 0 and np.max(np.linalg.norm(a - b, axis=1)) <= 1e-10 * size))
    return tuple(out)


def _piece(index, surface, trim, reversed):
    return Piece(int(index), surface, trim, bool(reversed), _closed(surface))


def pieces(part):
    """The faces of ``part`` as :class:`Piece` records: a lab.Model's faces, a face, a trimmed or plain surface."""
    if is_model(part):
        if not part.faces:
            raise ValueError(f"the model has no faces to project on; problems: {[str(p) for p in part.problems]}")
        return [_piece(f.index, face_surface(f), f.trim, f.reversed) for f in part.faces]
    if is_face(part):
        return [_piece(part.index, face_surface(part), part.trim, part.reversed)]
    if hasattr(part, "contains") and hasattr(part, "surface") and hasattr(part, "loops"):  # a TrimmedSurface
        return [_piece(0, part.surface, part, False)]
    if hasattr(part, "derivatives") and hasattr(part, "domain"):
        return [_piece(0, part, None, False)]
    raise TypeError(f"the part must be a lab.Model, a face of one, a lab surface or a lab.TrimmedSurface; "
                    f"got {type(part).__name__}")


class Feet(NamedTuple):
    """Foot points: ``points`` (n, 3), ``face`` (n,) the face's index, ``uv`` (n, 2) in the face's (file)
    parameters, ``distance`` (n,) signed by the face's normal, ``normal`` (n, 3) the face's normal at the foot,
    ``border`` (n,) True where the foot lies on a face's border (the nearest point of the face is not inside it)."""

    points: np.ndarray
    face: np.ndarray
    uv: np.ndarray
    distance: np.ndarray
    normal: np.ndarray
    border: np.ndarray


def _dot(a, b):
    return np.einsum("ij,ij->i", a, b)


class _Seeds:
    """The start of the search: the vertices of a mesh of every face, their face, (u, v) and normal, in a k-d tree."""

    def __init__(self, parts, lines):
        points, faces, uv, normals, reach = [], [], [], [], []
        extents = [_extent(piece) for piece in parts]
        spacing = float(np.linalg.norm(np.ptp(np.concatenate([e[1] for e in extents]), axis=0))) / lines
        for k, piece in enumerate(parts):
            # as many lines as the face's longer side in space holds at the part's spacing: equal triangles on
            # small and large faces keep the faces' reach (below) small, and with it the second search
            n_u, n_v = (int(np.clip(np.ceil(x / (spacing or 1.0)) + 1, 4, 4 * lines)) for x in extents[k][0])
            UV, tri = piece_triangles(piece, n_u, n_v)
            d = piece.surface.derivatives(UV[:, 0], UV[:, 1])
            with np.errstate(invalid="ignore", divide="ignore"):
                N = np.cross(d.bu, d.bv)
                N /= np.linalg.norm(N, axis=1, keepdims=True)
            # how far a point of the face can lie from its nearest vertex: the largest triangle's reach (from its
            # centre to a corner), with room for the surface's bulge over the flat triangle
            T = d.b[tri]
            # (within a triangle the nearest corner is at most its longest side / sqrt(3) away; 0.7 of it leaves
            # room for the surface's bulge over the flat triangle)
            edges = np.linalg.norm(T - np.roll(T, 1, axis=1), axis=2)
            reach.append(0.7 * float(edges.max()) if len(tri) else 0.0)
            points.append(d.b)
            faces.append(np.full(len(UV), k))
            uv.append(UV)
            normals.append(-N if piece.reversed else N)
        self.points, self.piece = np.concatenate(points), np.concatenate(faces)
        self.uv, self.normal = np.concatenate(uv), np.concatenate(normals)
        self.reach = np.array(reach)
        self.size = float(np.linalg.norm(np.ptp(self.points, axis=0))) or 1.0
        self.tree = cKDTree(self.points)


def _extent(piece):
    """A face's lengths in space along u and along v (the longest of 9 iso-curves each, as 16-gons over its (u, v)
    box) and the points sampled."""
    lo, hi = piece.box
    if piece.trim is not None:
        X = np.concatenate(piece.trim.loops)
        lo, hi = np.maximum(lo, X.min(axis=0)), np.minimum(hi, X.max(axis=0))
    U, V = np.meshgrid(np.linspace(lo[0], hi[0], 17), np.linspace(lo[1], hi[1], 9), indexing="ij")
    along_u = piece.surface.evaluate(U.ravel(), V.ravel()).reshape(17, 9, 3)
    along_v = piece.surface.evaluate(*np.meshgrid(np.linspace(lo[0], hi[0], 9), np.linspace(lo[1], hi[1], 17),
                                                  indexing="ij")).reshape(9, 17, 3)
    lengths = (np.nan_to_num(np.linalg.norm(np.diff(along_u, axis=0), axis=2)).sum(axis=0).max(),
               np.nan_to_num(np.linalg.norm(np.diff(along_v, axis=1), axis=2)).sum(axis=1).max())
    X = along_u.reshape(-1, 3)
    return lengths, X[np.all(np.isfinite(X), axis=1)]


def _seed_uv(piece, lines):
    """(u, v) of the vertices of a mesh of the face (see :func:`piece_triangles`)."""
    return piece_triangles(piece, lines)[0]


def piece_triangles(piece, lines, lines_v=None):
    """A triangulation in (u, v) of a face: its trimmed region (:func:`lab.trimming.triangulate` on ``lines``
    iso-parameter lines over the loops' box), or a grid of ``lines`` x ``lines`` over its domain.

    Returns (u, v) (k, 2) and triangles (t, 3)."""
    n_u, n_v = lines, lines if lines_v is None else lines_v
    if piece.trim is not None:
        X = np.concatenate(piece.trim.loops)
        lo, hi = X.min(axis=0), X.max(axis=0)
        size = np.where(hi > lo, hi - lo, 1.0)
        from .trimming import triangulate

        # the loops' box as a box of the lines' aspect, so that the grid's cells are squares there: the triangles
        # then follow the lines in both directions, and none is larger than a cell
        box = np.array([n_u - 1, n_v - 1], dtype=float) / max(n_u - 1, n_v - 1)
        outer, *holes = [(np.asarray(L) - lo) / size * box for L in piece.trim.loops]
        uv, tri = triangulate(outer, holes, ((0.0, box[0]), (0.0, box[1])), n_u, n_v,
                              max_area=float(box[0] * box[1]) / ((n_u - 1) * (n_v - 1)))
        (u0, u1), (v0, v1) = piece.surface.domain
        uv = lo + uv / box * size
        return np.column_stack([np.clip(uv[:, 0], u0, u1), np.clip(uv[:, 1], v0, v1)]), np.asarray(tri)
    lo, hi = piece.box
    U, V = np.meshgrid(np.linspace(lo[0], hi[0], n_u), np.linspace(lo[1], hi[1], n_v), indexing="ij")
    k = np.arange(n_u * n_v).reshape(n_u, n_v)
    a, b, c, d = k[:-1, :-1].ravel(), k[1:, :-1].ravel(), k[1:, 1:].ravel(), k[:-1, 1:].ravel()
    tri = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return np.column_stack([U.ravel(), V.ravel()]), tri


def _newton(surface, P, uv, lo, hi, tol, period=None):
    """Minimise |S(u, v) - P| from ``uv`` within the box [lo, hi] (projected Newton, one evaluation per step).

    Returns the feet's (u, v) and the derivatives there."""
    uv = uv.copy()
    best = np.full(len(P), np.inf)
    previous = uv.copy()
    active = np.arange(len(P))
    for _step in range(MAX_STEPS):
        if not len(active):
            break
        d = surface.derivatives(uv[active, 0], uv[active, 1])
        r = d.b - P[active]
        dist = np.sqrt(_dot(r, r))
        worse = dist > best[active] * (1 + 1e-12) + tol * 1e-3
        if np.any(worse):  # the step lengthened |r|: halve it and look again
            w = active[worse]
            step = uv[w] - previous[w]
            if period is not None and np.any(period > 0):
                step = np.where(period > 0, step - period * np.round(step / np.where(period > 0, period, 1.0)), step)
            uv[w] = np.clip(previous[w] + 0.5 * step, lo, hi)
        ok = ~worse
        a_idx = active[ok]
        best[a_idx] = dist[ok]
        bu, bv, r = d.bu[ok], d.bv[ok], r[ok]
        E, F, G = _dot(bu, bu), _dot(bu, bv), _dot(bv, bv)
        g1, g2 = _dot(bu, r), _dot(bv, r)
        a, b, c = E + _dot(d.buu[ok], r), F + _dot(d.buv[ok], r), G + _dot(d.bvv[ok], r)
        det = a * c - b * b
        bad = ~((a > 0) & (det > 1e-12 * (E * G + 1e-300)))  # not positive definite: Gauss-Newton
        a, b, c = np.where(bad, E, a), np.where(bad, F, b), np.where(bad, G, c)
        damp = 1e-14 * (E + G) + 1e-300
        a, c = a + damp, c + damp
        det = a * c - b * b
        du, dv = -(c * g1 - b * g2) / det, -(a * g2 - b * g1) / det
        new = uv[a_idx] + np.column_stack([du, dv])
        if period is not None and np.any(period > 0):  # a closed direction: round the seam, not stop at it
            new = np.where(period > 0, lo + np.mod(new - lo, np.where(period > 0, period, 1.0)), new)
        new = np.clip(new, lo, hi)
        moved = new - uv[a_idx]
        if period is not None and np.any(period > 0):
            moved = np.where(period > 0, moved - period * np.round(moved / np.where(period > 0, period, 1.0)), moved)
        length = np.sqrt(_dot(moved[:, :1] * bu + moved[:, 1:] * bv, moved[:, :1] * bu + moved[:, 1:] * bv))
        previous[a_idx] = uv[a_idx]
        uv[a_idx] = new
        done = length <= tol
        still = np.ones(len(active), dtype=bool)
        still[np.flatnonzero(ok)[done]] = False
        active = active[still]
    d = surface.derivatives(uv[:, 0], uv[:, 1])
    return uv, d


def _border_feet(piece, P, tol, cache):
    """The nearest points of the face's border (its loops, each segment a straight line in (u, v)) to ``P``.

    Returns (u, v) (k, 2) and the points (k, 3)."""
    key = piece.index
    if key not in cache:
        dense = []
        for loop in piece.loops():
            closed = np.vstack([loop, loop[:1]])
            steps = max(1, int(np.ceil(512 / len(loop))))
            t = np.arange(steps) / steps
            seg = closed[:-1, None, :] + t[None, :, None] * (closed[1:] - closed[:-1])[:, None, :]
            dense.append(seg.reshape(-1, 2))
        starts = [np.vstack([D, D[:1]]) for D in dense]
        A = np.concatenate([s[:-1] for s in starts])
        B = np.concatenate([s[1:] for s in starts])
        before = np.arange(len(A)) - 1  # the segment that ends where segment i starts: i - 1, or its loop's last
        first = np.cumsum([0] + [len(D) for D in dense[:-1]])
        before[first] = first + np.array([len(D) for D in dense]) - 1
        X = piece.surface.evaluate(A[:, 0], A[:, 1])
        cache[key] = (A, B, before, cKDTree(X))
    A, B, before, tree = cache[key]
    _d, j = tree.query(P)
    # the segments on both sides of the nearest loop vertex: the one starting at it (t = 0) and the one ending there
    best_uv, best_x, best_d = None, None, None
    for seg, t0 in ((j, 0.0), (before[j], 1.0)):
        a, b = A[seg], B[seg]
        t = np.full(len(P), t0)
        e = b - a
        for _step in range(30):
            uv = a + t[:, None] * e
            d = piece.surface.derivatives(uv[:, 0], uv[:, 1])
            St = d.bu * e[:, :1] + d.bv * e[:, 1:]
            Stt = d.buu * e[:, :1] ** 2 + 2 * d.buv * e[:, :1] * e[:, 1:] + d.bvv * e[:, 1:] ** 2
            r = d.b - P
            f1, f2 = _dot(St, r), _dot(St, St) + _dot(Stt, r)
            f2 = np.where(f2 > 0, f2, _dot(St, St) + 1e-300)
            new = np.clip(t - f1 / f2, 0.0, 1.0)
            if np.all(np.abs(new - t) * np.sqrt(_dot(St, St)) <= tol):
                t = new
                break
            t = new
        uv = a + t[:, None] * e
        x = piece.surface.evaluate(uv[:, 0], uv[:, 1])
        dist = np.linalg.norm(x - P, axis=1)
        if best_d is None:
            best_uv, best_x, best_d = uv, x, dist
        else:
            better = dist < best_d
            best_uv[better], best_x[better], best_d[better] = uv[better], x[better], dist[better]
    return best_uv, best_x


def closest_points(points, part, *, lines=SEED_LINES, neighbours=NEIGHBOURS, seeds=None):
    """The nearest point of ``part`` to each of ``points``: face, (u, v), foot point and signed distance.

    Parameters
    ----------
    points : (n, 3) array_like
    part : lab.Model, a face of one, lab surface or lab.TrimmedSurface
    lines : int
        The start mesh's spacing: this many steps across the part's size (each face gets as many iso-parameter
        lines as its longer side holds, 4 at least); its vertices start Newton's iteration.
    neighbours : int
        How many of the nearest mesh vertices name the faces that are tried.
    seeds : optional
        The start mesh of an earlier call on the same part (``closest_points.seeds(part)``), to skip building it.

    Returns
    -------
    Feet
    """
    P = _v._as_float_array(points, "points")
    if P.ndim != 2 or P.shape[1] != 3:
        raise ValueError(f"points must have shape (n, 3); got {P.shape}")
    if not np.all(np.isfinite(P)):
        raise ValueError(f"points must be finite; {int(np.count_nonzero(~np.all(np.isfinite(P), axis=1)))} of "
                         f"{len(P)} are not")
    parts = pieces(part)
    seeds = seeds if seeds is not None else _Seeds(parts, _v.as_positive_int(lines, "lines", minimum=4))
    n = len(P)
    k = min(_v.as_positive_int(neighbours, "neighbours", minimum=1), len(seeds.points))
    tol = STEP_RTOL * seeds.size
    best = np.full(n, np.inf)
    feet = np.zeros((n, 3))
    uv_out = np.zeros((n, 2))
    piece_out = np.zeros(n, dtype=int)
    border = np.zeros(n, dtype=bool)
    seed_normal = np.zeros((n, 3))
    if n == 0:
        return Feet(feet, piece_out, uv_out, np.zeros(0), feet.copy(), border)
    tried = np.zeros((n, len(parts)), dtype=bool)
    cache = {}

    def attempt(rows, starts):
        """Newton from the seed vertices ``starts`` for the points ``rows`` (at most one start per point and face)."""
        which = seeds.piece[starts]
        tried[rows, which] = True
        for p in np.unique(which):
            piece = parts[p]
            sel = which == p
            r, s = rows[sel], starts[sel]
            lo, hi = piece.box
            uv, d = _newton(piece.surface, P[r], seeds.uv[s], lo, hi, tol, piece.period)
            x = d.b
            on_border = ~piece.inside(uv)
            if np.any(on_border):
                buv, bx = _border_feet(piece, P[r[on_border]], tol, cache)
                uv[on_border], x[on_border] = buv, bx
            dist = np.linalg.norm(x - P[r], axis=1)
            better = dist < best[r]
            rb = r[better]
            best[rb], feet[rb], uv_out[rb] = dist[better], x[better], uv[better]
            piece_out[rb], border[rb], seed_normal[rb] = p, on_border[better], seeds.normal[s[better]]

    def nearest_per_face(dist, idx, rows):
        """Per row the nearest listed vertex of each face not yet tried whose lower bound on the distance to the
        face (vertex distance minus the face's reach) is below the best distance found: (rows, starts)."""
        which = seeds.piece[np.minimum(idx, len(seeds.points) - 1)]
        ok = np.isfinite(dist) & ~tried[rows[:, None], which]
        ok &= dist - seeds.reach[which] < best[rows][:, None]
        r, c = np.nonzero(ok)  # row-major: within a row the nearer vertices first
        _keys, first = np.unique(r * len(parts) + which[r, c], return_index=True)  # each face's nearest per row
        return rows[r[first]], idx[r[first], c[first]]

    # first the faces of the nearest vertices, then every face that could still hold a nearer foot: a face is
    # at least (its nearest vertex's distance - its reach) away, so the rest need no Newton step
    dist, idx = seeds.tree.query(P, k=k)
    attempt(*nearest_per_face(dist.reshape(n, k), idx.reshape(n, k), np.arange(n)))
    rows, wide = np.arange(n), max(4 * k, 32)
    while len(rows):
        wide = min(wide, len(seeds.points))
        dist, idx = seeds.tree.query(P[rows], k=wide)
        dist, idx = dist.reshape(len(rows), wide), idx.reshape(len(rows), wide)
        bound = best[rows] + seeds.reach.max()
        dist = np.where(dist <= bound[:, None], dist, np.inf)
        attempt(*nearest_per_face(dist, idx, rows))
        # rows whose listed vertices all lie within the bound may have more beyond: look at more of them
        full = np.isfinite(dist[:, -1]) & (wide < len(seeds.points))
        rows, wide = rows[full], wide * 4
    normal = np.zeros((n, 3))
    for p in np.unique(piece_out):
        sel = piece_out == p
        normal[sel] = parts[p].normal(uv_out[sel])
    missing = ~np.all(np.isfinite(normal), axis=1)
    normal[missing] = seed_normal[missing]  # a degenerate foot (a collapsed side): the mesh's normal there
    sign = np.sign(_dot(P - feet, normal))
    sign[sign == 0] = 1.0  # beside a face in its tangent plane (a border foot): no side, counted above
    distance = np.where(best <= tol, 0.0, sign * best)
    index = np.array([parts[p].index for p in range(len(parts))])[piece_out]
    return Feet(feet, index, uv_out, distance, normal, border)


def seeds(part, lines=SEED_LINES):
    """The start mesh of :func:`closest_points` for ``part``, to reuse over several calls."""
    return _Seeds(pieces(part), _v.as_positive_int(lines, "lines", minimum=4))


closest_points.seeds = seeds
