r"""Choi and Lee's own facet colouring for the stripe mapping (§3, cases 1–3, eqs. 5–7).

:func:`lab.interrogation.reflection.stripe_map` (the library's default)
splits every facet exactly along the zero sets of the interpolated stripe and
face-border functions.  The paper works with **colours** instead:

* every vertex gets the colour of the stripe its reflected ray hits (steps ① – ⑦);
* **case 1**, three equal colours: the facet keeps that colour;
* **case 2**, one vertex ``v3`` differs from ``v1`` and ``v2``: the facet is
  replaced by four facets (figure 13).  ``b3`` is the midpoint of ``v1 v2``
  (eq. 7); ``b1`` lies on ``v1 v3`` where the mapped segment ``v1' v3'``
  meets the border line L of ``v1``'s stripe on the map, at the same ratio,
  :math:`b_1 = v_1 + t (v_3 - v_1)`, :math:`t = |v_1' b_1'| / |v_1' v_3'|`
  (eq. 5); ``b2`` likewise on ``v2 v3`` (eq. 6).  The facets
  ``(v1, b3, b1)``, ``(b3, b2, b1)``, ``(b3, v2, b2)`` take ``v1``'s colour,
  ``(b1, b2, v3)`` takes ``v3``'s;
* **case 3**, three different colours: the facet is subdivided (here at its
  edge midpoints, whose colours are computed from their own reflected rays)
  until every piece is case 1 or 2.

On one box face the stripe coordinate φ is affine on the face's plane, so
:math:`t = (k - \varphi_1) / (\varphi_3 - \varphi_1)` for the border ``φ = k``
next to ``v1``'s stripe.  Where ``v1`` and ``v3`` see different faces the
mapped segment leaves the box surface; the paper does not say what to do, and
we put ``b1`` where the face border :func:`~.reflection.face_borders`,
interpolated linearly, vanishes.  Stripes of equal colour on both sides of a
narrow stripe of the other colour are case 1: the narrow stripe is lost,
which is the paper's approximation for small facets.

Like the exact split, new vertices interpolate position, normal and view
vector linearly from the input mesh, so both methods approximate the same
piecewise-linear surface and :func:`color_difference` measures only what the
algorithms do differently.
"""

import numpy as np

from .reflection import FACE_PAIRS, StripeMesh, box_weights, face_borders, reflect, stripe_colors, stripe_phase

__all__ = ["area_difference", "color_difference", "colors_at", "paper_stripe_map", "stripe_shading", "vertex_stripes"]


def vertex_stripes(box, X, N, E):
    """Face, stripe coordinate φ, stripe index and colour key of each vertex's reflected ray (steps ① – ⑦).

    Returns
    -------
    face : (k,) int ndarray
    phi : (k,) ndarray
        Stripe coordinate on that face.
    stripe : (k,) int ndarray
        ``floor(φ)`` clipped to ``0 … 2 n - 1``.
    key : (k,) int ndarray
        The colour: ``face`` for even (coloured) stripes, 6 for the background;
        faces of equal colour share a key.
    """
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    R = reflect(E, N)
    w, _ = box_weights(box, X, R)
    face = np.argmax(w, axis=1)
    P0, P1 = stripe_phase(box, X, R)
    rows = np.arange(len(X))
    phi = P0[rows, face] / P1[rows, face]
    stripe = np.clip(np.floor(phi), 0, 2 * box.n_stripes - 1).astype(int)
    return face, phi, stripe, _color_key(box, face, stripe)


def _color_key(box, face, stripe):
    palette = np.vstack([box.colors, box.background[None]])
    _, first = np.unique(np.round(palette, 9), axis=0, return_inverse=True)
    return first.ravel()[np.where(stripe % 2 == 0, face, 6)]


class _Vertices:
    """Growing vertex table (position, normal, view vector) with labels and new points keyed by edge."""

    def __init__(self, box, X, N, E):
        self.box = box
        self.A = np.concatenate([X, N, E], axis=1)
        self.labels = list(vertex_stripes(box, X, N, E))
        self.cache = {}

    def add(self, a, b, t, tag):
        """Ids of the points ``a + t (b - a)`` on edges (a, b); one point per (undirected edge, tag)."""
        ids = np.empty(len(a), dtype=np.int64)
        new_rows = []
        for m, (i, j, s) in enumerate(zip(a.tolist(), b.tolist(), np.asarray(t, dtype=float).tolist())):
            key = (min(i, j), max(i, j), tag)
            if key not in self.cache:
                self.cache[key] = len(self.A) + len(new_rows)
                new_rows.append((i, j, s))
            ids[m] = self.cache[key]
        if new_rows:
            i, j, s = (np.array(c) for c in zip(*new_rows))
            rows = self.A[i] + s[:, None] * (self.A[j] - self.A[i])
            self.append(rows)
        return ids

    def append(self, rows):
        """Add vertices (rows of position, normal, view vector) with their labels; returns their ids."""
        new = vertex_stripes(self.box, rows[:, :3], rows[:, 3:6], rows[:, 6:])
        self.labels = [np.concatenate([old, n]) for old, n in zip(self.labels, new)]
        ids = np.arange(len(self.A), len(self.A) + len(rows))
        self.A = np.concatenate([self.A, rows])
        return ids


def _border_ratio(V, a, b):
    """Eqs. 5, 6: where on the edge a → b the border of a's stripe towards b's lies, as t in [0, 1]."""
    face, phi, _, _ = V.labels
    t = np.empty(len(a))
    same = face[a] == face[b]
    # on one face: φ is affine on the face's plane, so the ratio on the map is that of φ
    pa, pb = phi[a[same]], phi[b[same]]
    k = np.floor(pa) + (pb > pa)  # the upper or lower border of a's stripe
    with np.errstate(invalid="ignore", divide="ignore"):
        t[same] = np.where(pb != pa, (k - pa) / (pb - pa), 0.5)
    # different faces: the linearly interpolated face border g_ij (the paper does not say)
    if np.any(~same):
        ia, ib = a[~same], b[~same]
        X, N, E = V.A[:, :3], V.A[:, 3:6], V.A[:, 6:]
        ga = _pair_value(V.box, X[ia], N[ia], E[ia], face[ia], face[ib])
        gb = _pair_value(V.box, X[ib], N[ib], E[ib], face[ia], face[ib])
        with np.errstate(invalid="ignore", divide="ignore"):
            t[~same] = np.where(ga != gb, ga / (ga - gb), 0.5)
    return np.clip(np.nan_to_num(t, nan=0.5), 0.0, 1.0)


def _pair_value(box, X, N, E, i, j):
    """g_ij (:func:`face_borders`) for per-row face pairs (i, j)."""
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    g = face_borders(box, X, reflect(E, N))
    column = np.full((6, 6), -1)
    column[FACE_PAIRS[:, 0], FACE_PAIRS[:, 1]] = np.arange(len(FACE_PAIRS))
    return np.where(i < j, 1.0, -1.0) * g[np.arange(len(X)), column[np.minimum(i, j), np.maximum(i, j)]]


def paper_stripe_map(points, triangles, normals, box, E, *, max_depth=6):
    """The stripe mapping with the paper's facet colouring (cases 1–3, eqs. 5–7); see the module docstring.

    Parameters
    ----------
    points : (k, 3) array_like
    triangles : (t, 3) int array_like
    normals : (k, 3) array_like
        Unit normals.
    box : StripeBox
    E : (k, 3) array_like
        View vectors (:func:`~.reflection.view_vectors`).
    max_depth : int
        Subdivisions of a case-3 facet at most; a piece still of case 3 then
        takes the colour of its centroid (counted in ``unresolved``).

    Returns
    -------
    StripeMesh
        As :func:`~.reflection.stripe_map`; ``face`` and ``stripe`` are those of
        the vertex whose colour a cell takes, ``phase`` that vertex's φ three
        times, ``weights`` empty.
    unresolved : int
        Case-3 pieces left at ``max_depth``.
    """
    X = np.asarray(points, dtype=float)
    N = np.asarray(normals, dtype=float)
    E = np.asarray(E, dtype=float)
    T = np.asarray(triangles, dtype=np.int64)
    if not (isinstance(max_depth, (int, np.integer)) and max_depth >= 0):
        raise ValueError(f"max_depth must be a non-negative integer; got {max_depth!r}")
    V = _Vertices(box, X, N, E)
    out_T, out_src, out_parent = [], [], []
    parent = np.arange(len(T))
    unresolved = 0
    for depth in range(max_depth + 1):
        if len(T) == 0:
            break
        key = V.labels[3][T]
        e01, e12, e02 = key[:, 0] == key[:, 1], key[:, 1] == key[:, 2], key[:, 0] == key[:, 2]
        case1 = e01 & e12
        case3 = ~(e01 | e12 | e02)
        case2 = ~case1 & ~case3
        out_T.append(T[case1])
        out_src.append(T[case1, 0])
        out_parent.append(parent[case1])
        if np.any(case2):
            t2 = T[case2]
            odd = np.where(e01[case2], 2, np.where(e12[case2], 0, 1))  # the vertex of the other colour
            rot = (odd[:, None] + np.array([1, 2, 0])) % 3  # (v1, v2, v3) with v3 the odd one, orientation kept
            v1, v2, v3 = np.take_along_axis(t2, rot, axis=1).T
            b1 = V.add(v1, v3, _border_ratio(V, v1, v3), "border")
            b2 = V.add(v2, v3, _border_ratio(V, v2, v3), "border")
            b3 = V.add(v1, v2, np.full(len(v1), 0.5), "mid")
            out_T += [np.stack(f, axis=1) for f in ((v1, b3, b1), (b3, b2, b1), (b3, v2, b2), (b1, b2, v3))]
            out_src += [v1, v1, v1, v3]
            out_parent += [parent[case2]] * 4
        T3, p3 = T[case3], parent[case3]
        if depth == max_depth or len(T3) == 0:
            if len(T3):
                unresolved = len(T3)
                out_T.append(T3)
                out_src.append(V.append(V.A[T3].mean(axis=1)))  # the colour of the centroid
                out_parent.append(p3)
            break
        a, b, c = T3.T
        m_ab = V.add(a, b, np.full(len(a), 0.5), "mid")
        m_bc = V.add(b, c, np.full(len(a), 0.5), "mid")
        m_ca = V.add(c, a, np.full(len(a), 0.5), "mid")
        T = np.concatenate([np.stack(f, axis=1) for f in ((a, m_ab, m_ca), (m_ab, b, m_bc), (m_ca, m_bc, c),
                                                          (m_ab, m_bc, m_ca))])
        parent = np.tile(p3, 4)
    T_out = np.concatenate(out_T)
    src = np.concatenate(out_src)
    face, phi, stripe, _ = V.labels
    Nn = V.A[:, 3:6] / np.linalg.norm(V.A[:, 3:6], axis=1, keepdims=True)
    mesh = StripeMesh(V.A[:, :3], Nn, T_out, face[src], stripe[src], np.concatenate(out_parent),
                      np.repeat(phi[src][:, None], 3, axis=1), np.zeros((len(V.A), 0)))
    return mesh, unresolved


def colors_at(points, triangles, parent, cell_keys, original_points, original_triangles, order=12):
    """Colour keys of a split mesh at ``order²`` sample points (sub-triangle centroids) of every input triangle.

    Parameters
    ----------
    points, triangles : (k, 3), (c, 3) array_like
        The split mesh (a :class:`StripeMesh`'s or a stripe mapping's).
    parent : (c,) int array_like
        Input triangle of each cell.
    cell_keys : (c,) int array_like
        A colour key per cell (equal keys: equal colours).
    original_points, original_triangles : (k0, 3), (t, 3) array_like
        The input mesh that was split.
    order : int
        Samples per triangle edge.

    Returns
    -------
    keys : (t, s) int ndarray
        Colour key (see :func:`vertex_stripes`) at each sample; -1 where no cell covers it.
    weights : (s,) ndarray
        Quadrature weights of the samples (they sum to 1 on each triangle).
    """
    P = np.asarray(original_points, dtype=float)
    T0 = np.asarray(original_triangles, dtype=np.int64)
    # the centroids of the order² congruent sub-triangles: equal areas, none on an edge or a mid-line
    i, j = np.meshgrid(np.arange(order), np.arange(order), indexing="ij")
    up = i + j <= order - 1
    down = i + j <= order - 2
    lam = np.concatenate([np.stack([i[up] + 1 / 3, j[up] + 1 / 3], axis=1),
                          np.stack([i[down] + 2 / 3, j[down] + 2 / 3], axis=1)]) / order  # weights of corners 1, 2
    s = len(lam)
    wts = np.full(s, 1.0 / s)
    keys = np.full((len(T0), s), -1)
    cells = np.asarray(triangles, dtype=np.int64)
    par = np.asarray(parent, dtype=np.int64)
    ck = np.asarray(cell_keys)
    points = np.asarray(points, dtype=float)
    a = P[T0[par, 0]]
    e1, e2 = P[T0[par, 1]] - a, P[T0[par, 2]] - a
    G = np.stack([np.einsum("ij,ij->i", e1, e1), np.einsum("ij,ij->i", e1, e2), np.einsum("ij,ij->i", e2, e2)], 1)
    det = G[:, 0] * G[:, 2] - G[:, 1] ** 2

    def bary(Y):
        d = Y - a
        r1, r2 = np.einsum("ij,ij->i", d, e1), np.einsum("ij,ij->i", d, e2)
        return np.stack([(G[:, 2] * r1 - G[:, 1] * r2) / det, (G[:, 0] * r2 - G[:, 1] * r1) / det], axis=1)

    corners = [bary(points[cells[:, k]]) for k in range(3)]  # (c, 2) each
    for start in range(0, len(cells), 20000):
        sl = slice(start, start + 20000)
        c0, c1, c2 = (c[sl][:, None, :] for c in corners)
        q = lam[None]

        def cross(u, v, w):
            return (v[..., 0] - u[..., 0]) * (w[..., 1] - u[..., 1]) - (v[..., 1] - u[..., 1]) * (w[..., 0] - u[..., 0])

        area = cross(c0, c1, c2)
        sgn = np.sign(area)
        tol = 1e-12
        hit = ((sgn * cross(c0, c1, q) >= -tol) & (sgn * cross(c1, c2, q) >= -tol) & (sgn * cross(c2, c0, q) >= -tol)
               & (np.abs(area) > 0))
        rows, cols = np.nonzero(hit)
        keys[par[sl][rows], cols] = ck[sl][rows]
    return keys, wts


def color_difference(mesh_a, mesh_b, box, original_points, original_triangles, order=12):
    """Fraction of the surface area where two :class:`StripeMesh` splits of the same input mesh differ in colour.

    Samples every input triangle at barycentric points (:func:`colors_at`) and
    weighs them by the triangle's area (:func:`area_difference`).
    """
    parts = [(m.points, m.triangles, m.parent, _color_key(box, m.face, m.stripe)) for m in (mesh_a, mesh_b)]
    return area_difference(*parts, original_points, original_triangles, order)


def area_difference(a, b, original_points, original_triangles, order=12):
    """Fraction of the area of the input mesh where two splits ``(points, triangles, parent, cell_keys)`` differ."""
    P = np.asarray(original_points, dtype=float)
    T0 = np.asarray(original_triangles, dtype=np.int64)
    ka, w = colors_at(*a, P, T0, order)
    kb, _ = colors_at(*b, P, T0, order)
    area = 0.5 * np.linalg.norm(np.cross(P[T0[:, 1]] - P[T0[:, 0]], P[T0[:, 2]] - P[T0[:, 0]]), axis=1)
    differ = (ka != kb).astype(float) @ w
    return float(differ @ area / area.sum())


def stripe_shading(stripe_mesh, box, E, *, ambient=0.2, diffuse=0.8):
    r"""The paper's shaded reflection mapping (colour plate 1): light from the stripe, in the stripe's colour.

    Choi and Lee let "the light for any point on the test surface come from
    the corresponding point on the reflection map", coloured like that stripe,
    seen from the eye of the mapping.  The light direction is the reflected
    ray, so the Lambert factor is :math:`|\mathbf N\cdot\hat{\mathbf R}| =
    |\mathbf N\cdot\hat{\mathbf E}|`: every cell's stripe colour is scaled by
    ``ambient + diffuse |N·Ê|`` at its centroid (grazing views darker, a
    frontal view full colour), a white surface lit by coloured light.

    Parameters
    ----------
    stripe_mesh : StripeMesh
    box : StripeBox
    E : callable or (3,) array_like
        ``E(X)`` giving view vectors at points ``X``, or a constant view direction.

    Returns
    -------
    (t, 3) ndarray
        RGB in [0, 1].
    """
    X = stripe_mesh.points[stripe_mesh.triangles].mean(axis=1)
    N = stripe_mesh.normals[stripe_mesh.triangles].mean(axis=1)
    N /= np.linalg.norm(N, axis=1, keepdims=True)
    V = E(X) if callable(E) else np.broadcast_to(np.asarray(E, dtype=float), X.shape)
    V = V / np.linalg.norm(V, axis=1, keepdims=True)
    shade = ambient + diffuse * np.abs(np.einsum("ij,ij->i", N, V))
    return np.clip(stripe_colors(box, stripe_mesh.face, stripe_mesh.stripe) * shade[:, None], 0, 1)

