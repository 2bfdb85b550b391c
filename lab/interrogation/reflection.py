r"""Reflection mapping, reflection lines and isophotes on triangle meshes (Choi & Lee, §3).

Everything here works on plain arrays: vertex positions ``X`` (k, 3), unit
normals ``N`` (k, 3), triangles (t, 3) of vertex indices.  The PyVista front
end is :mod:`lab.interrogation`.

Reflection (Choi & Lee, §3, steps ① – ⑦).  With the view vector
:math:`\mathbf E = \mathbf e - \mathbf X` from a vertex towards the eye
:math:`\mathbf e` (or a constant direction for an eye at infinity), the
reflection vector lies in the plane of :math:`\mathbf N` and :math:`\mathbf E`
and makes the same angle with :math:`\mathbf N`:

.. math:: \mathbf R = 2\,(\mathbf N\cdot\mathbf E)\,\mathbf N - \mathbf E .

It does not depend on the orientation of :math:`\mathbf N`.  :math:`\mathbf R`
is left unnormalised (:math:`|\mathbf R| = |\mathbf E|`): the stripe and
light-line coordinates below are ratios ``P0 / P1`` of two per-vertex values,
and interpolating numerator and denominator linearly (rather than the ratio)
makes the mapped lines exact on a plane seen from a finite eye point.

Crisp stripe borders.  The paper colours each vertex by the stripe its
reflected ray hits and splits facets whose vertices differ (cases 1 – 3, eqs.
5 – 7), placing the border on an edge by the ratio of the mapped points.  We
use the equivalent exact form: every border is the zero set of a function that
is known at the vertices and interpolated linearly, and each triangle is split
along it (:func:`split_triangles`).  First along the borders between box faces
(which face a ray leaves the box through), then along the stripe borders of
each face.  Every output triangle then lies in one stripe of one face.

Reflection lines (Klass 1980, Choi & Lee, reference [3]) are the curves on
the surface whose reflected view rays meet one of a family of parallel light
lines; isophotes (Poeschl) are the curves of constant :math:`\mathbf N\cdot\mathbf L`.
Both are level sets, traced by :func:`lab.mesh.levels.level_lines`.
"""

from typing import NamedTuple

import numpy as np

__all__ = [
    "FACES",
    "FACE_PAIRS",
    "VIEW_DIRECTION",
    "StripeBox",
    "StripeMesh",
    "box_weights",
    "face_borders",
    "isophote_levels",
    "light_line_values",
    "reflect",
    "split_triangles",
    "stripe_box",
    "stripe_colors",
    "stripe_map",
    "stripe_phase",
    "view_vectors",
]

#: The direction from the surface towards the default eye (at infinity) of the stripe mapping; the
#: pictures and explorers look from the same side (:mod:`lab.view.render`), so the stripes are the ones seen.
VIEW_DIRECTION = (-1.0, -1.2, 1.6)

#: The six faces of the stripe box, in this order; face ``i`` has the outward normal
#: ``FACE_SIGN[i] * e_{FACE_AXIS[i]}``.
FACES = ("-x", "+x", "-y", "+y", "-z", "+z")
FACE_AXIS = np.array([0, 0, 1, 1, 2, 2])
FACE_SIGN = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])
#: The 15 pairs (i, j), i < j, of faces; column order of :func:`face_borders`.
FACE_PAIRS = np.array([(i, j) for i in range(6) for j in range(i + 1, 6)])

#: Default coordinate axis across which the stripes of each face are counted: the side
#: faces have horizontal stripes (counted along z), top and bottom stripes run along x
#: (counted along y), like the light tunnel a car body is inspected in.
DEFAULT_AXES = (2, 2, 2, 2, 1, 1)

#: Default stripe colour of each face (RGB in [0, 1]); the stripes between them have the background colour.
DEFAULT_COLORS = (
    (0.85, 0.10, 0.10),  # -x red
    (0.10, 0.60, 0.15),  # +x green
    (0.10, 0.25, 0.85),  # -y blue
    (0.95, 0.55, 0.05),  # +y orange
    (0.55, 0.15, 0.65),  # -z purple
    (0.05, 0.05, 0.05),  # +z black: the sky of a light tunnel
)


class StripeBox(NamedTuple):
    """The reflection map of Choi & Lee, figure 9: an axis-aligned box with stripes on its faces.

    Attributes
    ----------
    lo, hi : (3,) ndarray
        Opposite corners.
    n_stripes : int
        Coloured stripes per face; they alternate with as many background stripes of the
        same width, so the stripe width on face ``i`` is ``(hi - lo)[axes[i]] / (2 n_stripes)``.
    axes : (6,) int ndarray
        Coordinate axis along which the stripes of each face are counted (stripes run across it).
    colors : (6, 3) ndarray
        Stripe colour of each face, RGB in [0, 1].
    background : (3,) ndarray
        Colour of the stripes in between.
    """

    lo: np.ndarray
    hi: np.ndarray
    n_stripes: int
    axes: np.ndarray
    colors: np.ndarray
    background: np.ndarray

    @property
    def widths(self):
        """Stripe width on each face, shape (6,)."""
        return (self.hi - self.lo)[self.axes] / (2 * self.n_stripes)


class StripeMesh(NamedTuple):
    """A triangle mesh split along stripe borders (:func:`stripe_map`).

    Attributes
    ----------
    points : (k, 3) ndarray
    normals : (k, 3) ndarray
        Unit normals, interpolated from the input and renormalised.
    triangles : (t, 3) int ndarray
    face : (t,) int ndarray
        Index into :data:`FACES` of the box face each triangle reflects.
    stripe : (t,) int ndarray
        Stripe index on that face, ``0 … 2 n_stripes - 1``; even stripes are coloured.
    parent : (t,) int ndarray
        Input triangle each output triangle lies in.
    phase : (t, 3) ndarray
        Stripe coordinate φ (on the triangle's face) at the three corners of each
        triangle, interpolated as the split used it; all three lie in
        ``[stripe, stripe + 1]`` up to rounding, also next to the box edges
        (the face borders are zero sets of the same homogeneous numerators as
        φ, :func:`face_borders`).
    weights : (k, 6) ndarray
        The face weights ``w`` (:func:`box_weights`) at the vertices, interpolated likewise.
    """

    points: np.ndarray
    normals: np.ndarray
    triangles: np.ndarray
    face: np.ndarray
    stripe: np.ndarray
    parent: np.ndarray
    phase: np.ndarray
    weights: np.ndarray


def _dot(a, b):
    return np.einsum("...i,...i->...", a, b)


def reflect(E, N):
    r"""Reflection of the view vector about the normal.

    .. math:: \mathbf R = 2 (\mathbf N\cdot\mathbf E)\mathbf N - \mathbf E

    Choi & Lee, §3, step ④: R lies in the plane of N and E and makes
    the same angle with N as E does.  Independent of the sign of N.

    Parameters
    ----------
    E : (..., 3) array_like
        View vectors (from the surface point towards the eye), any length.
    N : (..., 3) array_like
        Unit normals; broadcast against ``E``.

    Returns
    -------
    R : ndarray, shape ``broadcast(E, N).shape``
        ``|R| = |E|``.
    """
    E = np.asarray(E, dtype=float)
    N = np.asarray(N, dtype=float)
    return 2.0 * _dot(N, E)[..., None] * N - E


def view_vectors(points, eye=None, view=None):
    """View vectors ``E`` from each point towards the eye (step ② of Choi & Lee, §3).

    Parameters
    ----------
    points : (k, 3) array_like
    eye : (3,) array_like, optional
        Eye point: ``E = eye - X`` (not normalised).
    view : (3,) array_like, optional
        Direction towards an eye at infinity: ``E = view / |view|`` at every point.
        Exactly one of ``eye`` and ``view`` is given.

    Returns
    -------
    E : (k, 3) ndarray
    """
    X = np.asarray(points, dtype=float)
    if (eye is None) == (view is None):
        raise ValueError("give exactly one of eye (a point) and view (a direction towards an eye at infinity)")
    if eye is not None:
        return np.asarray(eye, dtype=float) - X
    d = np.asarray(view, dtype=float)
    return np.broadcast_to(d / np.linalg.norm(d), X.shape).copy()


def stripe_box(points, n_stripes=8, margin=0.5, axes=DEFAULT_AXES, colors=DEFAULT_COLORS, background=(1.0, 1.0, 1.0)):
    """The box of stripes enclosing ``points`` (Choi & Lee, §3, first step and figure 9).

    Parameters
    ----------
    points : (k, 3) array_like
        The surface (its bounding box sets the box).
    n_stripes : int
        Coloured stripes per face.
    margin : float
        The box is the bounding box grown by ``margin`` times its diagonal on every side,
        so that it encloses flat surfaces too.
    axes : sequence of 6 ints
        Axis (0, 1, 2) along which the stripes of each face are counted; not the face's own axis.
    colors : (6, 3) or (3,) array_like
        Stripe colour per face, or one for all.
    background : (3,) array_like
        Colour between the stripes.

    Returns
    -------
    StripeBox
    """
    X = np.asarray(points, dtype=float)
    lo, hi = X.min(axis=0), X.max(axis=0)
    diag = float(np.linalg.norm(hi - lo))
    grow = margin * diag
    colors = np.broadcast_to(np.asarray(colors, dtype=float), (6, 3)).copy()
    return StripeBox(lo - grow, hi + grow, int(n_stripes), np.asarray(axes, dtype=int), colors,
                     np.asarray(background, dtype=float))


def box_weights(box, X, R):
    r"""Which face of the box each ray ``X + s R`` leaves through, as the argmax of smooth weights.

    With :math:`d_i > 0` the distance from X to the plane of face i and
    :math:`\mathbf n_i` its outward normal, the ray meets that plane at
    :math:`s_i = d_i / (\mathbf R\cdot\mathbf n_i)`; it leaves through the face
    with the smallest positive :math:`s_i`, i.e. the largest
    :math:`w_i = \mathbf R\cdot\mathbf n_i / d_i` (step ⑥).  Unlike
    :math:`s_i`, :math:`w_i` is continuous, so the border between two faces is
    the zero set of :math:`w_i - w_j`.

    Returns
    -------
    w : (k, 6) ndarray
    d : (k, 6) ndarray
        The distances :math:`d_i`.
    """
    X = np.asarray(X, dtype=float)
    R = np.asarray(R, dtype=float)
    d = np.where(FACE_SIGN > 0, box.hi[FACE_AXIS] - X[:, FACE_AXIS], X[:, FACE_AXIS] - box.lo[FACE_AXIS])
    den = FACE_SIGN * R[:, FACE_AXIS]
    return den / d, d


def face_borders(box, X, R):
    r"""The borders between box faces as zero sets of numerators: :math:`g_{ij} = d_i d_j (w_i - w_j)`.

    With :math:`c_i = \mathbf R\cdot\mathbf n_i` and :math:`d_i` of
    :func:`box_weights`, :math:`g_{ij} = c_i d_j - c_j d_i`: positive where the
    ray meets the plane of face i before that of face j.  Unlike
    :math:`w_i - w_j` it is a product of per-vertex quantities in the same
    homogeneous form as the stripe numerators of :func:`stripe_phase`, and at
    every vertex :math:`2n P_1 - P_0` of face i equals :math:`g_{ij}` for the
    face j that closes face i's stripe range (``P_0 = g_{ij}`` for the face at
    its start).  Interpolated linearly together, a region where face i wins
    every :math:`g_{ij}` therefore has its stripe coordinate inside
    :math:`[0, 2n]`: the face a cell reflects and its stripes agree up to the
    box edges, also for a finite eye point.

    Returns
    -------
    g : (k, 15) ndarray
        Columns in the order of :data:`FACE_PAIRS`.
    """
    X = np.asarray(X, dtype=float)
    R = np.asarray(R, dtype=float)
    _, d = box_weights(box, X, R)
    c = FACE_SIGN * R[:, FACE_AXIS]
    i, j = FACE_PAIRS[:, 0], FACE_PAIRS[:, 1]
    return c[:, i] * d[:, j] - c[:, j] * d[:, i]


def stripe_phase(box, X, R):
    r"""Homogeneous stripe coordinate of the ray ``X + s R`` on the plane of every face.

    The ray meets the plane of face i at
    :math:`\mathbf Y = \mathbf X + d_i \mathbf R / (\mathbf R\cdot\mathbf n_i)`;
    its stripe coordinate is :math:`\varphi_i = (Y_a - lo_a) / \text{width}_i`
    (a = ``box.axes[i]``; stripe ``floor(φ)``, borders at integers).  Returned
    as numerator and denominator, :math:`\varphi_i = P_0 / P_1` with
    :math:`P_1 = (\mathbf R\cdot\mathbf n_i)\,\text{width}_i`, positive where
    the ray heads towards face i, and
    :math:`P_0 = (X_a - lo_a)(\mathbf R\cdot\mathbf n_i) + d_i R_a`.  The
    border ``φ = k`` is the zero set of :math:`P_0 - k P_1`.

    Returns
    -------
    P0, P1 : (k, 6) ndarray
    """
    X = np.asarray(X, dtype=float)
    R = np.asarray(R, dtype=float)
    _, d = box_weights(box, X, R)
    den = FACE_SIGN * R[:, FACE_AXIS]
    a = box.axes
    P0 = (X[:, a] - box.lo[a]) * den + d * R[:, a]
    P1 = den * box.widths
    return P0, P1


def split_triangles(A, T, f, mask=None):
    """Split triangles along the zero set of a vertex function interpolated linearly.

    A triangle whose vertices have strictly opposite signs of ``f`` is cut
    along the segment where the linear interpolant vanishes: into three
    triangles (one vertex alone on its side) or two (the segment runs through
    a vertex where ``f = 0``).  New vertices lie on the cut edges; a vertex is
    shared by both triangles of an edge, and all columns of ``A`` (positions,
    normals and any further per-vertex quantities) are interpolated linearly,
    so that any function that is linear in the columns of ``A`` can be split
    along next.  Orientation is kept.  This is the facet splitting of
    Choi & Lee, §3, cases 2 and 3, with the border located exactly
    (eqs. 5 and 6 with the mapped ratio taken from ``f``).

    Parameters
    ----------
    A : (k, m) ndarray
        Per-vertex values.
    T : (t, 3) int ndarray
    f : (k,) ndarray
        Function values at the vertices.
    mask : (t,) bool ndarray, optional
        Only these triangles are split.

    Returns
    -------
    A : (k', m) ndarray
        The input rows followed by the new vertices.
    T : (t', 3) int ndarray
    parent : (t',) int ndarray
        Index of the input triangle each output triangle comes from.
    """
    k = len(A)
    fT = f[T]
    pos, neg = fT > 0, fT < 0
    cross = pos.any(axis=1) & neg.any(axis=1)
    if mask is not None:
        cross &= mask
    keep = np.nonzero(~cross)[0]
    idx = np.nonzero(cross)[0]
    if idx.size == 0:
        return A, T, np.arange(len(T))
    p, n = pos[idx], neg[idx]
    z = ~(p | n)
    has_zero = z.any(axis=1)
    lonely = np.where(has_zero, np.argmax(z, axis=1),
                      np.where(p.sum(axis=1) == 1, np.argmax(p, axis=1), np.argmax(n, axis=1)))
    order = (lonely[:, None] + np.arange(3)) % 3
    t = np.take_along_axis(T[idx], order, axis=1)
    a, b, c = t[:, 0], t[:, 1], t[:, 2]
    # edges to cut: (b, c) through a zero vertex a, else (a, b) and (a, c)
    e1 = np.where(has_zero[:, None], np.stack([b, c], 1), np.stack([a, b], 1))
    e2 = np.stack([a, c], 1)
    edges = np.concatenate([e1, e2[~has_zero]])
    edges.sort(axis=1)
    keys = edges[:, 0].astype(np.int64) * k + edges[:, 1]
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    lo, hi = edges[first, 0], edges[first, 1]
    s = f[lo] / (f[lo] - f[hi])
    newA = A[lo] + s[:, None] * (A[hi] - A[lo])
    new_id = k + inverse
    q1 = new_id[: len(idx)]
    q2 = np.full(len(idx), -1)
    q2[~has_zero] = new_id[len(idx):]
    z_i = np.nonzero(has_zero)[0]
    n_i = np.nonzero(~has_zero)[0]
    tris = [
        T[keep],
        np.stack([a[z_i], b[z_i], q1[z_i]], 1),
        np.stack([a[z_i], q1[z_i], c[z_i]], 1),
        np.stack([a[n_i], q1[n_i], q2[n_i]], 1),
        np.stack([q1[n_i], b[n_i], c[n_i]], 1),
        np.stack([q1[n_i], c[n_i], q2[n_i]], 1),
    ]
    parent = np.concatenate([keep, idx[z_i], idx[z_i], idx[n_i], idx[n_i], idx[n_i]])
    return np.concatenate([A, newA]), np.concatenate(tris), parent


def stripe_map(points, triangles, normals, box, E):
    """Split a triangle mesh so that each triangle reflects one stripe of one box face (Choi & Lee, §3).

    Steps ④ – ⑦ per vertex (reflection vector, exit face, stripe coordinate),
    then the facets are split along the face borders (zero sets of
    ``w_i - w_j``, :func:`box_weights`) and, inside each face's region, along
    the stripe borders (zero sets of ``P0 - k P1``, :func:`stripe_phase`), all
    interpolated linearly from the vertices (:func:`split_triangles`).  This
    replaces the paper's approximate four-facet split (case 2, eqs. 5 – 7) and
    its recursive subdivision (case 3) by an exact split of the piecewise-linear
    map, so the stripe borders are straight inside each input triangle and
    continuous across triangles.

    Parameters
    ----------
    points : (k, 3) array_like
    triangles : (t, 3) int array_like
    normals : (k, 3) array_like
        Unit normals.
    box : StripeBox
        Must enclose the points strictly.
    E : (k, 3) array_like
        View vectors (:func:`view_vectors`).

    Returns
    -------
    StripeMesh
    """
    X = np.asarray(points, dtype=float)
    N = np.asarray(normals, dtype=float)
    T = np.asarray(triangles, dtype=np.int64)
    R = reflect(E, N)
    w, _ = box_weights(box, X, R)
    P0, P1 = stripe_phase(box, X, R)
    # one matrix of per-vertex columns, all interpolated together when a triangle is split
    cols = {"X": slice(0, 3), "N": slice(3, 6), "w": slice(6, 12), "P0": slice(12, 18), "P1": slice(18, 24),
            "g": slice(24, 39)}
    A = np.concatenate([X, N, w, P0, P1, face_borders(box, X, R)], axis=1)
    parent = np.arange(len(T))

    # 1. face borders (zero sets of g_ij, not of w_i - w_j: see face_borders), only in triangles whose
    #    vertices leave the box through different faces
    vface = np.argmax(w, axis=1)
    mixed = np.any(vface[T] != vface[T[:, :1]], axis=1)
    if np.any(mixed):
        for pair, (i, j) in enumerate(FACE_PAIRS):
            P1T = A[:, cols["P1"]][T]
            cand = (P1T > 0).any(axis=1)  # faces that can be hit somewhere in a triangle
            f = A[:, cols["g"]][:, pair]
            A, T, par = split_triangles(A, T, f, mixed & cand[:, i] & cand[:, j])
            parent, mixed = parent[par], mixed[par]
    face = _winning_face(A[:, cols["g"]][T].mean(axis=1), A[:, cols["w"]][T].mean(axis=1))

    # 2. stripe borders inside each face's region
    for i in range(6):
        sel = face == i
        if not np.any(sel):
            continue
        phi = A[:, cols["P0"]][:, i] / np.where(A[:, cols["P1"]][:, i] > 0, A[:, cols["P1"]][:, i], np.nan)
        phiT = phi[T[sel]]
        kmin, kmax = np.nanmin(phiT), np.nanmax(phiT)
        # borders 0 and 2n are the face's own borders with its neighbours (already split along, see face_borders)
        for kk in range(max(int(np.floor(kmin)) + 1, 1), min(int(np.ceil(kmax)), 2 * box.n_stripes)):
            sel = face == i
            f = A[:, cols["P0"]][:, i] - kk * A[:, cols["P1"]][:, i]
            A, T, par = split_triangles(A, T, f, sel)
            parent, face = parent[par], face[par]

    ti = np.arange(len(T))
    P0T = A[:, cols["P0"]][T][ti, :, face]  # (t, 3): numerator of the triangle's face at its corners
    P1T = A[:, cols["P1"]][T][ti, :, face]
    with np.errstate(divide="ignore", invalid="ignore"):  # a corner whose ray runs along the wall has P1 = 0
        phi = P0T.mean(axis=1) / P1T.mean(axis=1)  # at the centroid
        phase = P0T / P1T
    stripe = np.clip(np.floor(np.nan_to_num(phi)), 0, 2 * box.n_stripes - 1).astype(int)
    bad = ~np.isfinite(phase)  # such a corner: the bound of the triangle's stripe it tends to (phi where 0/0)
    phase[bad] = np.clip(np.where(np.isnan(phase), phi[:, None], phase), stripe[:, None], stripe[:, None] + 1)[bad]
    Nn = A[:, cols["N"]]
    Nn = Nn / np.linalg.norm(Nn, axis=1, keepdims=True)
    return StripeMesh(A[:, cols["X"]], Nn, T, face, stripe, parent, phase, A[:, cols["w"]])


def _winning_face(g, w):
    """The face that wins every pairwise border ``g_ij`` (values at cell centroids); ties by the weights ``w``."""
    wins = np.zeros((len(g), 6))
    for pair, (i, j) in enumerate(FACE_PAIRS):
        wins[:, i] += g[:, pair] > 0
        wins[:, j] += g[:, pair] < 0
    best = wins == wins.max(axis=1, keepdims=True)
    return np.argmax(np.where(best, w, -np.inf), axis=1)


def stripe_colors(box, face, stripe):
    """RGB in [0, 1] of stripes: the face colour for even stripe indices, the background for odd ones.

    Parameters
    ----------
    box : StripeBox
    face, stripe : (t,) int array_like

    Returns
    -------
    (t, 3) ndarray
    """
    face = np.asarray(face)
    colored = (np.asarray(stripe) % 2) == 0
    return np.where(colored[:, None], box.colors[face], box.background[None, :])


# -- light lines and isophotes ------------------------------------------------------------


def light_line_values(points, R, origin, plane_normal, direction, spacing):
    r"""Homogeneous coordinate of the light line that each reflected ray ``X + s R`` meets (Klass).

    The light lines lie in the plane through ``origin`` with unit normal
    :math:`\mathbf n` (the surface lies below it), parallel to the unit vector
    :math:`\mathbf d`, at spacing :math:`\delta`: line j is
    :math:`\text{origin} + j\,\delta\,\mathbf w + t\,\mathbf d` with
    :math:`\mathbf w = \mathbf n \times \mathbf d`.  The ray meets the plane at
    :math:`\mathbf Y = \mathbf X + h\,\mathbf R / (\mathbf R\cdot\mathbf n)`,
    :math:`h = (\text{origin} - \mathbf X)\cdot\mathbf n`, and
    :math:`\varphi = (\mathbf Y - \text{origin})\cdot\mathbf w / \delta = P_0 / P_1` with

    .. math::

        P_1 = (\mathbf R\cdot\mathbf n)\,\delta, \qquad
        P_0 = ((\mathbf X - \text{origin})\cdot\mathbf w)(\mathbf R\cdot\mathbf n) + h\,(\mathbf R\cdot\mathbf w).

    The reflection line of light line j is the zero set of :math:`P_0 - j P_1`
    where :math:`P_1 > 0` (rays heading for the plane).

    Returns
    -------
    P0, P1 : (k,) ndarray
        ``P1 <= 0`` where the ray misses the plane.
    """
    X = np.asarray(points, dtype=float)
    R = np.asarray(R, dtype=float)
    n = np.asarray(plane_normal, dtype=float)
    d = np.asarray(direction, dtype=float)
    w = np.cross(n, d)
    Rn = R @ n
    h = (np.asarray(origin, dtype=float) - X) @ n
    P0 = ((X - origin) @ w) * Rn + h * (R @ w)
    return P0, Rn * spacing


def isophote_levels(count):
    r"""Levels :math:`\cos\alpha_j` of ``count`` isophotes at equal angles :math:`\alpha_j = j\pi/(\text{count}+1)`.

    The set is symmetric about 0, so the isophotes (curves
    :math:`\mathbf N\cdot\mathbf L = \cos\alpha_j`) do not depend on the
    orientation of the normal.

    Returns
    -------
    angles, levels : (count,) ndarray
        Angles in radians and their cosines.
    """
    alpha = np.arange(1, count + 1) * np.pi / (count + 1)
    return alpha, np.cos(alpha)

