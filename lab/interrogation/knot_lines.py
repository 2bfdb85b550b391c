"""A close look at one knot line: the surface on both sides of it as two unwelded pieces (each with its own one-sided
normals and curvature), and how level lines drawn on them (reflection lines, isophotes) cross it.

Reflection lines follow the normal (Klass 1980): across a G2 edge they run on smoothly, across a G1 edge (the
curvature jumps) they stay connected but turn, across a G0 edge (the normal jumps) they break.  On a welded
mesh the knot line's vertices carry one normal for both sides, the lines are interpolated across the jump and a
break looks like a steep bend; on the two pieces here each side keeps its own limit, so the break is a gap.
"""

import numpy as np

from ..geometry import validation as _v

#: The one-sided limits are taken this fraction of the parameter range inside each side (the evaluator's span
#: choice at the knot itself is the right-hand one).
INSIDE = 1e-9


def knot_line_mesh(surface, direction, value, half_width, *, along=None, n=(80, 40)):
    """The surface next to its knot line ``direction = value`` as two unwelded grids, one per side.

    Parameters
    ----------
    surface : lab.Surface
        E.g. a :class:`lab.BSplineSurface` with an interior knot ``value`` in ``direction``.
    direction : {"u", "v"}
        The parameter that is constant on the knot line (as :attr:`lab.Continuity.edges`' ``direction``).
    value : float
        The knot.
    half_width : float
        How far (in the parameter) each side reaches from the knot line.
    along : (float, float), optional
        The range of the other parameter (default: all of it).
    n : (int, int)
        Grid lines along the knot line and across each side.

    Returns
    -------
    pyvista.PolyData
        Quads with the point data of :func:`lab.mesh.surface_mesh` (exact, one-sided on the knot line), ``uv``
        and ``face`` (0: the side below ``value``, 1: above), so that :func:`lab.reflection_lines` joins the lines
        of the two sides where they meet and a picture with ``edges=True`` draws the knot line.
    """
    from ..mesh import grid_mesh

    direction = _v.as_choice(direction, ("u", "v"), "direction")
    value = _v.as_number(value, "value")
    half_width = _v.as_number(half_width, "half_width", positive=True)
    (u0, u1), (v0, v1) = surface.domain
    lo, hi = (u0, u1) if direction == "u" else (v0, v1)
    if not lo < value < hi:
        raise ValueError(f"value must lie inside the {direction} range ({lo}, {hi}) of the surface; got {value}")
    a, b = (v0, v1) if direction == "u" else (u0, u1)
    if along is not None:
        a, b = (_v.as_number(x, "along entry") for x in along)
    n_along, n_across = (_v.as_positive_int(k, "n entry", minimum=2) for k in n)
    eps = INSIDE * (hi - lo)
    sides = (np.linspace(max(lo, value - half_width), value - eps, n_across),
             np.linspace(value + eps, min(hi, value + half_width), n_across))
    t = np.linspace(a, b, n_along)
    points, data, uvs = [], {}, []
    for across in sides:
        u, v = (across, t) if direction == "u" else (t, across)
        bb, N, curv = surface.sample_grid(u, v)
        points.append(bb)
        for key, x in (("K", curv.K), ("H", curv.H), ("k1", curv.k1), ("k2", curv.k2),
                       ("degenerate", curv.degenerate), ("N", N)):
            data.setdefault(key, []).append(x)
        uv = np.empty(bb.shape[:2] + (2,))
        uv[..., 0], uv[..., 1] = u[:, None], v[None, :]
        uvs.append(uv)
    mesh = grid_mesh(np.stack(points), {k: np.stack(x) for k, x in data.items()}, weld_points=False,
                     first_data={"uv": np.stack(uvs)})
    mesh.point_data["face"] = np.repeat([0, 1], mesh.n_points // 2)
    mesh.field_data["knot_line"] = np.array([0.0 if direction == "u" else 1.0, value, 2 * eps])
    return mesh


def line_crossings(lines, mesh, *, reach=3):
    """Where the polylines ``lines`` drawn on a :func:`knot_line_mesh` meet its knot line: per meeting the gap
    between the two sides' ends and the angle between their directions.

    Each polyline is cut where it passes from one side to the other; every end of a piece on the knot line (within
    two grid steps of it) is paired with the nearest such end of the same light line (cell data ``light_line``,
    or all lines together) on the other side.

    Parameters
    ----------
    lines : pyvista.PolyData
        Polylines, e.g. :func:`lab.reflection_lines` of ``mesh``.
    mesh : pyvista.PolyData
        The :func:`knot_line_mesh` they were drawn on.
    reach : int
        The direction at an end is that of the chord to the point ``reach`` points back along the line.

    Returns
    -------
    gap : ndarray (m,)
        Distance between the paired ends (0 where a line runs on).
    angle : ndarray (m,)
        Angle between the two sides' directions at the knot line, degrees.
    where : ndarray (m, 3)
        The end on side 0.
    """
    from scipy.spatial import cKDTree

    reach = _v.as_positive_int(reach, "reach", minimum=1)
    if "knot_line" not in mesh.field_data or "face" not in mesh.point_data:
        raise ValueError("mesh must come from lab.interrogation.knot_line_mesh (point data 'face' and 'uv')")
    X = np.asarray(mesh.points, dtype=float)
    face = np.asarray(mesh.point_data["face"])
    tree = cKDTree(X)
    axis, value, eps = np.asarray(mesh.field_data["knot_line"])
    uv = np.asarray(mesh.point_data["uv"])
    row = np.flatnonzero((np.abs(uv[:, int(axis)] - value) <= eps) & (face == 0))
    row = row[np.argsort(uv[row, 1 - int(axis)])]
    A, B = X[row[:-1]], X[row[1:]]  # the knot line as segments

    def to_line(P):
        t = np.clip(np.einsum("pk,sk->ps", P, B - A) - np.einsum("sk,sk->s", A, B - A), 0, None)
        t = np.minimum(t / np.einsum("sk,sk->s", B - A, B - A), 1.0)
        return np.min(np.linalg.norm(P[:, None] - (A + t[..., None] * (B - A)), axis=-1), axis=1)

    size = float(np.linalg.norm(np.ptp(X, axis=0)))
    ends = {0: [], 1: []}  # side -> (light line, end point, direction into the knot line)
    ids = np.asarray(lines.cell_data["light_line"]) if "light_line" in lines.cell_data else np.zeros(lines.n_cells, int)
    for cell in range(lines.n_cells):
        P = np.asarray(lines.get_cell(cell).points, dtype=float)
        if len(P) < 2:
            continue
        side = face[tree.query(P)[1]].astype(int)
        side[to_line(P) <= 1e-6 * size] = -1  # on the knot line: an end of the pieces on both sides
        for s in (0, 1):
            inside = np.flatnonzero(side != 1 - s)  # the points of side s and those on the knot line
            for piece in np.split(inside, np.flatnonzero(np.diff(inside) > 1) + 1):
                if len(piece) < 2 or np.all(side[piece] == -1):
                    continue
                k = min(reach, len(piece) - 1)
                for end, back in ((piece[0], piece[k]), (piece[-1], piece[-1 - k])):
                    if to_line(P[end][None])[0] <= 1e-6 * size:
                        d = P[end] - P[back]
                        ends[s].append((ids[cell], P[end], d / np.linalg.norm(d)))
    gap, angle, where = [], [], []
    for j, p, d in ends[0]:
        others = [(q, e) for k, q, e in ends[1] if k == j]
        if not others:
            continue
        q, e = min(others, key=lambda o: np.linalg.norm(o[0] - p))
        gap.append(float(np.linalg.norm(q - p)))
        # d points into the knot line from side 0, -e out of it into side 1
        angle.append(float(np.degrees(np.arccos(np.clip(d @ -e, -1.0, 1.0)))))
        where.append(p)
    return np.array(gap), np.array(angle), np.array(where).reshape(-1, 3)

