"""Interrogation of tessellated surfaces: focal surfaces, parabolic lines, stripes, reflection lines, isophotes.

The methods of Choi & Lee (sections 3 and 4) and the classics they build on, as PyVista meshes.  Every function accepts

* a :class:`lab.Surface` (tessellated with :func:`lab.mesh.surface_mesh` on a ``resolution x resolution`` grid, 64),
* a :class:`lab.BezierPatches` (``patches.to_mesh(resolution)``, default 8 quads per patch edge), or
* a :class:`pyvista.PolyData` with point data ``K, H, k1, k2, N`` (as :mod:`lab.mesh` makes them), or
* a :class:`lab.Model` (``model.to_mesh(resolution, resolution)``, default 16 lines per face): level lines are joined
  across its face borders where their ends meet (:mod:`lab.interrogation.faces`).  The mathematics lives in
  :mod:`lab.focal` and :mod:`lab.reflection`.

Examples
--------
>>> import lab
>>> from lab.interrogation import meshes
>>> hood = lab.surfaces.hood()
>>> stripes = meshes.stripe_mapping(hood, n_stripes=10)          # doctest: +SKIP
>>> lines = meshes.parabolic_lines(lab.surfaces.torus())
>>> len(meshes.polylines(lines))
2
"""

import warnings

import numpy as np
import pyvista as pv

from ..geometry import validation as _v
from ..i18n import _, decimal
from ..mesh.build import _faces, surface_mesh
from ..mesh.levels import level_lines
from ..model.patches import BezierPatches
from ..model.surface import Surface
from . import faces as _models
from . import focal as _focal
from . import reflection as _refl

__all__ = ["FocalSheetWarning", "as_curvature_mesh", "focal_sheets", "focal_surface", "isophotes", "parabolic_lines",
           "polylines", "reflection_lines", "stripe_mapping"]

#: Point data a mesh must carry to be interrogated.
REQUIRED_POINT_DATA = ("K", "H", "k1", "k2", "N")

#: Default tessellation: grid of a Surface, quads per patch edge of BezierPatches, lines per face of a Model.
SURFACE_RESOLUTION = 64
PATCH_RESOLUTION = 8
MODEL_RESOLUTION = 16

#: Classical focal sheets keep radii of curvature up to this multiple of the mesh diagonal by default.
MAX_RADIUS_FACTOR = 100.0

#: |N.L - level| below this counts as on the level for isophotes (N.L is dimensionless).
ISOPHOTE_TOL = 1e-12

#: |K| below this times 1/diagonal² counts as zero for the parabolic lines (rounding noise).
K_ZERO_RTOL = 1e-9


class FocalSheetWarning(UserWarning):
    """Vertices of a classical focal sheet were dropped because their principal curvature is (near) zero, or
    points of a focal surface are not finite."""


# -- input ----------------------------------------------------------------------------


def as_curvature_mesh(surface, resolution=None):
    """A PolyData with point data ``K, H, k1, k2, N`` for a surface, a patch collection or such a mesh.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches, lab.Model or pyvista.PolyData
    resolution : int, optional
        Grid size for a Surface (default 64), quads per patch edge for
        BezierPatches (default 8), lines per face of a Model (default 16); not allowed with a mesh.

    Returns
    -------
    pyvista.PolyData
        A mesh given as input is returned as is (the functions here do not modify it).
    """
    if isinstance(surface, pv.PolyData):
        if resolution is not None:
            raise ValueError("resolution applies to surfaces and patches only; a mesh is used as it is")
        missing = [name for name in REQUIRED_POINT_DATA if name not in surface.point_data]
        if missing:
            raise ValueError(
                f"the mesh needs curvature point data {', '.join(REQUIRED_POINT_DATA)}; missing {', '.join(missing)} "
                "(make it with lab.mesh.surface_mesh or BezierPatches.to_mesh)"
            )
        if surface.n_points == 0 or surface.n_cells == 0:
            raise ValueError("the mesh is empty")
        if not np.all(np.isfinite(surface.point_data["N"])):
            raise ValueError("the mesh's normals N must be finite at every point; got NaN or inf")
        return surface
    if isinstance(surface, Surface):
        n = _v.as_positive_int(SURFACE_RESOLUTION if resolution is None else resolution, "resolution", minimum=2)
        return surface_mesh(surface, n, n)
    if isinstance(surface, BezierPatches):
        n = _v.as_positive_int(PATCH_RESOLUTION if resolution is None else resolution, "resolution", minimum=1)
        return surface.to_mesh(n)
    if _models.is_model(surface):
        n = _v.as_positive_int(MODEL_RESOLUTION if resolution is None else resolution, "resolution", minimum=2)
        return _models.fill_normals(surface.to_mesh(n, n))
    raise TypeError(
        f"expected a lab.Surface, a lab.BezierPatches, a lab.Model or a pyvista.PolyData with curvature point data; "
        f"got {type(surface).__name__}"
    )


def _triangles(mesh):
    """Triangles (t, 3) of a surface mesh, without degenerate ones (collapsed quads at a pole)."""
    tri = mesh if mesh.is_all_triangles else mesh.triangulate()
    T = np.asarray(tri.faces).reshape(-1, 4)[:, 1:].astype(np.int64)
    good = (T[:, 0] != T[:, 1]) & (T[:, 1] != T[:, 2]) & (T[:, 0] != T[:, 2])
    return T[good]


def _remove_points(mesh, keep):
    """The mesh without the points where ``keep`` is False and without the cells touching them."""
    faces = [f for f in _faces(mesh) if np.all(keep[f])]
    new_id = np.cumsum(keep) - 1
    cells = np.concatenate([np.concatenate([[len(f)], new_id[f]]) for f in faces]) if faces else np.zeros(0, int)
    out = pv.PolyData(np.asarray(mesh.points)[keep], cells) if np.any(keep) else pv.PolyData()
    if out.n_points:
        for name in mesh.point_data:
            out.point_data[name] = np.asarray(mesh.point_data[name])[keep]
    return out


def _normals(mesh):
    """The point data N as float64 unit vectors (lab.mesh fills degenerate points with VTK's float32 normals)."""
    N = np.asarray(mesh.point_data["N"], dtype=float)
    return N / np.linalg.norm(N, axis=1, keepdims=True)


#: Worst case of one level-line pass (isophotes, reflection lines): a segment on every triangle (two points and
#: its cell; a quadrilateral cell is two triangles) and the level's values; of the stripe map: each triangle cut
#: by every stripe border of a face (2 n_stripes + 1 pieces), a piece's row with its triangle and labels.
LEVEL_BYTES_PER_TRIANGLE, LEVEL_BYTES_PER_POINT, STRIPE_BYTES_PER_PIECE = 64, 16, 400
#: At most this many levels or stripes: more than a picture can tell apart, and each costs a pass over the mesh.
MAX_LEVELS = 1000


def _check_levels(count, mesh, name, what, per_level=None):
    """``count`` in 1 … MAX_LEVELS, refused first if ``count * per_level`` bytes (a level pass) are too many."""
    count = _v.as_positive_int(count, name, minimum=1, maximum=MAX_LEVELS)
    per_level = LEVEL_BYTES_PER_TRIANGLE * 2 * mesh.n_cells + LEVEL_BYTES_PER_POINT * mesh.n_points \
        if per_level is None else per_level
    _v.check_memory(count * per_level, f"{what}({name}={count}) on a mesh of {mesh.n_cells} cells")
    return count


def _diagonal(points):
    return float(np.linalg.norm(np.ptp(points, axis=0)))


def _eye_or_view(eye, view):
    """Exactly one of eye (point) and view (direction); default: an eye at infinity in VIEW_DIRECTION."""
    if eye is not None and view is not None:
        raise ValueError("give either eye (a point) or view (a direction towards an eye at infinity), not both")
    if eye is not None:
        e = np.asarray(eye, dtype=float)
        if e.shape != (3,) or not np.all(np.isfinite(e)):
            raise ValueError(f"eye must be a finite 3-vector (a point); got {eye!r}")
        return e, None
    return None, _v.as_direction(_refl.VIEW_DIRECTION if view is None else view, "view")


def _lines_mesh(lines_per_value, value_names):
    """A PolyData of polylines with cell data per line.

    ``lines_per_value`` is a list of ``(values, [polyline, ...])``; ``values``
    is a tuple matching ``value_names``.
    """
    points, cells, data = [], [], {name: [] for name in value_names}
    offset = 0
    for values, lines in lines_per_value:
        for line in lines:
            points.append(line)
            n = len(line)
            ids = np.arange(offset, offset + n)
            closed = n > 2 and np.array_equal(line[0], line[-1])
            if closed:  # a closed loop reuses its first point
                ids[-1] = offset
                points[-1] = line[:-1]
                offset += n - 1
            else:
                offset += n
            cells.append(np.concatenate([[n], ids]))
            for name, v in zip(value_names, values):
                data[name].append(v)
    if not cells:
        return pv.PolyData()
    out = pv.PolyData(np.concatenate(points), lines=np.concatenate(cells))
    for name in value_names:
        out.cell_data[name] = np.asarray(data[name])
    return out


def polylines(lines):
    """The polylines of a line mesh (as returned here) as a list of (n, 3) arrays; closed ones repeat their first point.

    Parameters
    ----------
    lines : pyvista.PolyData

    Returns
    -------
    list of (n, 3) ndarray
    """
    if not isinstance(lines, pv.PolyData):
        raise TypeError(f"expected a pyvista.PolyData of lines; got {type(lines).__name__}")
    out, conn, i = [], np.asarray(lines.lines), 0
    pts = np.asarray(lines.points)
    while i < len(conn):
        n = conn[i]
        out.append(pts[conn[i + 1 : i + 1 + n]])
        i += n + 1
    return out


# -- focal surfaces (Choi & Lee, §4) ------------------------------------------------


def focal_surface(surface, scale=1.0, function="mean", *, resolution=None):
    r"""The generalized focal surface (Choi & Lee, eqs. 8, 9).

    .. math:: \mathbf F = \mathbf X + a\, f(\kappa_1, \kappa_2)\, \mathbf N

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
        See the module docstring.
    scale : float
        The scale factor ``a``; the focal surface of a sphere of radius r for
        ``function="mean"`` lies ``scale / r`` inside it.
    function : str or callable
        ``"gaussian"`` (K), ``"mean"`` (H), ``"strain-energy"`` (κ1² + κ2²),
        ``"k1"``, ``"k2"`` (or a :class:`lab.CurvatureMode`), or any callable
        ``f(k1, k2)`` on arrays.
    resolution : int, optional

    Returns
    -------
    pyvista.PolyData
        The same cells as the tessellated surface, vertices moved to F.  Point
        data: the input's (``K, H, k1, k2, N``, ...), plus ``f`` (the function
        value), ``displacement`` (``scale * f``, signed along N) and ``X`` (the
        surface point), ``finite`` (False where f or the scale gave no finite point: warned).  Field data ``scale``
        and ``function`` (its name).
    """
    mesh = as_curvature_mesh(surface, resolution)
    f_callable = _focal.focal_function(function)
    a = _v.as_number(scale, "scale")
    X = np.asarray(mesh.points, dtype=float)
    N = _normals(mesh)
    F, f = _focal.focal_points(X, N, mesh.point_data["k1"], mesh.point_data["k2"], a, f_callable)
    finite = np.all(np.isfinite(F), axis=1)
    if not finite.all():
        bad = int(np.count_nonzero(~finite))
        warnings.warn(f"{bad} of {len(F)} focal points are not finite (the function f gave inf or NaN there, or the "
                      "scale overflowed); they are marked False in the point data 'finite'", FocalSheetWarning,
                      stacklevel=2)
    out = mesh.copy(deep=True)
    out.points = F
    out.point_data["f"] = f
    out.point_data["displacement"] = a * f
    out.point_data["X"] = X
    out.point_data["finite"] = finite
    out.field_data["scale"] = np.array([a])
    if isinstance(function, str):
        name = getattr(function, "value", function)
    else:
        name = getattr(function, "__name__", "callable")
    out.field_data["function"] = np.array([str(name)])
    return out


def focal_sheets(surface, *, tol=None, resolution=None, warn=True):
    r"""The classical focal sheets, the centres of principal curvature :math:`\mathbf X + \mathbf N / \kappa_i`.

    Vertices where :math:`|\kappa_i| <` ``tol`` (centre of curvature at or
    near infinity) are dropped from sheet i, with the cells touching them.  How
    many were dropped is stored in the field data ``dropped`` of each sheet
    and, when any were, said in a :class:`FocalSheetWarning`.  A cylinder's
    κ1 = 0 sheet is thus empty and its κ2 sheet is the axis; both sheets of a
    sphere collapse to its centre.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    tol : float, optional
        Smallest ``|κ|`` kept; default ``1 / (100 × mesh diagonal)``, i.e.
        radii of curvature up to 100 times the size of the surface.
    resolution : int, optional
    warn : bool
        Issue the warning (the count is in the field data either way).

    Returns
    -------
    sheet1, sheet2 : pyvista.PolyData
        Point data of the kept vertices (``K, H, k1, k2, N``, ``X`` the
        surface point, ``radius`` = 1/κ_i); field data ``dropped`` (int) and ``tol``.
    """
    mesh = as_curvature_mesh(surface, resolution)
    X = np.asarray(mesh.points, dtype=float)
    if tol is None:
        tol = 1.0 / (MAX_RADIUS_FACTOR * max(_diagonal(X), 1e-300))
    else:
        tol = _v.as_number(tol, "tol", positive=True)
    N = _normals(mesh)
    sheets = []
    for name in ("k1", "k2"):
        kappa = np.asarray(mesh.point_data[name], dtype=float)
        F, keep = _focal.focal_sheet(X, N, kappa, tol)
        sheet = mesh.copy(deep=True)
        sheet.point_data["X"] = X
        sheet.point_data["radius"] = np.where(keep, 1.0 / np.where(keep, kappa, 1.0), np.nan)
        sheet.points = np.where(keep[:, None], F, X)  # dropped points are removed below
        dropped = int(np.count_nonzero(~keep))
        if dropped:
            sheet = _remove_points(sheet, keep)
            if warn:
                warnings.warn(
                    decimal(_("focal sheet of {name}: dropped {dropped} of {n} vertices where |{name}| < {tol} "
                              "(radius of curvature beyond {radius}) and the cells touching them").format(
                        name=name, dropped=dropped, n=len(X), tol=f"{tol:.3g}", radius=f"{1 / tol:.3g}")),
                    FocalSheetWarning, stacklevel=2)
        sheet.field_data["dropped"] = np.array([dropped])
        sheet.field_data["tol"] = np.array([tol])
        sheets.append(sheet)
    return sheets[0], sheets[1]


def parabolic_lines(surface, *, tol=None, resolution=None):
    """The parabolic lines (K changes sign), where the focal surface of K crosses the surface (Choi & Lee, §4).

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    tol : float, optional
        ``|K| <= tol`` counts as zero; default ``1e-9 / diagonal²``.  Flat and
        cylindrical regions (K = 0 over an area) give no lines; see
        :func:`lab.focal.parabolic_lines`.
    resolution : int, optional

    Returns
    -------
    pyvista.PolyData
        Polylines (``polylines(result)`` gives them as arrays), with cell data
        ``line`` (index of the polyline).
    """
    mesh = as_curvature_mesh(surface, resolution)
    X = np.asarray(mesh.points, dtype=float)
    if tol is None:
        tol = K_ZERO_RTOL / max(_diagonal(X), 1e-150) ** 2  # 1e-300**2 would underflow to 0
    else:
        tol = _v.as_number(tol, "tol", minimum=0)
    lines = _models.joined(_focal.parabolic_lines(X, _triangles(mesh), mesh.point_data["K"], tol), _models.join_tol(mesh))
    return _lines_mesh([((i,), [line]) for i, line in enumerate(lines)], ("line",))


# -- reflection (Choi & Lee, §3) ------------------------------------------------------


def _colors(value, name, count):
    try:
        if isinstance(value, str) or (np.ndim(value) == 1 and len(value) in (3, 4) and not isinstance(value[0], str)):
            return np.broadcast_to(np.asarray(pv.Color(value).float_rgb), (count, 3)).copy()
        values = list(value)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a colour or {count} colours; got {value!r} ({exc})") from None
    if len(values) != count:
        raise ValueError(f"{name} must be a colour or {count} colours (one per face); got {len(values)}")
    try:
        return np.array([pv.Color(c).float_rgb for c in values])
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name}: not a colour: {exc}") from None


def stripe_mapping(surface, *, n_stripes=8, eye=None, view=None, margin=0.5, axes=_refl.DEFAULT_AXES,
                   colors=_refl.DEFAULT_COLORS, background="white", resolution=None, method="exact", shaded=False):
    """Reflection mapping of a box of stripes onto the surface, with crisp stripe borders (Choi & Lee, §3).

    The box encloses the surface (its bounding box grown by ``margin`` times
    the diagonal), each face carries ``n_stripes`` coloured stripes alternating
    with background stripes of equal width.  At each vertex the view vector is
    reflected about the normal, the reflected ray meets the box, and the
    stripe it hits gives the colour.  Facets are split exactly along the
    stripe and face borders (:func:`lab.reflection.stripe_map`), so every cell
    of the result has one colour and the borders are clean lines.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    n_stripes : int
        Coloured stripes per box face (1 … 1000).
    eye : (3,) array_like, optional
        Eye point.
    view : (3,) array_like, optional
        Direction towards an eye at infinity; default :data:`lab.reflection.VIEW_DIRECTION`
        (the camera of :func:`lab.render.screenshot`).  Give ``eye`` or ``view``.
    margin : float
        Box margin as a fraction of the diagonal (> 0).
    axes : sequence of 6 ints
        Per face (order ``-x, +x, -y, +y, -z, +z``) the axis 0/1/2 across which its
        stripes are counted (the stripes run perpendicular to it).
    colors : colour or sequence of 6 colours
        Stripe colour of each face (names or RGB).
    background : colour
        Colour between the stripes.
    resolution : int, optional
    method : {"exact", "paper"}
        ``"exact"``: split along the exact zero sets (:func:`lab.reflection.stripe_map`);
        ``"paper"``: Choi and Lee's colour cases 1–3 with the four-facet split of
        eqs. 5–7 (:func:`lab.interrogation.reflection_paper.paper_stripe_map`).
    shaded : bool
        The paper's colour plate 1: each cell lit by its stripe, in the stripe's
        colour (:func:`lab.interrogation.reflection_paper.stripe_shading`); the
        mesh then carries field data ``lit`` and is drawn without further lighting.

    Returns
    -------
    pyvista.PolyData
        Triangles; cell data ``RGB`` (uint8, active scalars), ``face`` (0–5),
        ``stripe`` (index on the face; even = coloured) and ``parent`` (input
        triangle); point data ``N`` (interpolated unit normals); field data
        ``unresolved`` (paper: case-3 pieces left at the depth limit).  Plot
        with ``plotter.add_mesh(m, scalars="RGB", rgb=True)``.
    """
    from . import reflection_paper as _paper

    method = _v.as_choice(method, ("exact", "paper"), "method")
    mesh = as_curvature_mesh(surface, resolution)
    n_stripes = _check_levels(n_stripes, mesh, "n_stripes", "stripe_mapping", 2 * STRIPE_BYTES_PER_PIECE * 2 * mesh.n_cells)
    margin = _v.as_number(margin, "margin", positive=True)
    axes_arr = np.asarray(axes)
    bad_axes = axes_arr.shape != (6,) or not np.issubdtype(axes_arr.dtype, np.integer)
    if bad_axes or np.any((axes_arr < 0) | (axes_arr > 2)):
        raise ValueError(f"axes must be 6 axis indices 0, 1 or 2 (one per face -x, +x, -y, +y, -z, +z); got {axes!r}")
    if np.any(axes_arr == _refl.FACE_AXIS):
        bad = [_refl.FACES[i] for i in np.nonzero(axes_arr == _refl.FACE_AXIS)[0]]
        raise ValueError(f"the stripes of a face cannot be counted along its own normal axis; faces {', '.join(bad)}")
    eye_pt, view_dir = _eye_or_view(eye, view)
    X = np.asarray(mesh.points, dtype=float)
    with np.errstate(invalid="ignore", divide="ignore"):
        undefined = ~(np.isfinite(X).all(axis=1) & np.isfinite(_normals(mesh)).all(axis=1))
    if np.any(undefined):  # a stripe box around NaN points has no stripes to count
        raise ValueError(f"the surface is degenerate at {int(undefined.sum())} of its {len(X)} mesh points (e.g. point "
                         f"{int(np.flatnonzero(undefined)[0])}): its point or normal is not finite there (NaN or inf: not "
                         "defined, or derivatives beyond the float range); the stripe mapping needs a surface defined everywhere")
    if _diagonal(X) == 0:
        raise ValueError("the surface has zero extent")
    box = _refl.stripe_box(X, n_stripes, margin, axes_arr, _colors(colors, "colors", 6),
                           _colors(background, "background", 1)[0])
    if eye_pt is not None and np.any(np.linalg.norm(X - eye_pt, axis=1) == 0):
        raise ValueError("the eye point lies on the surface")
    E = _refl.view_vectors(X, eye=eye_pt, view=view_dir)
    unresolved = 0
    if method == "exact":
        sm = _refl.stripe_map(X, _triangles(mesh), _normals(mesh), box, E)
    else:
        sm, unresolved = _paper.paper_stripe_map(X, _triangles(mesh), _normals(mesh), box, E)
    faces = np.hstack([np.full((len(sm.triangles), 1), 3), sm.triangles]).ravel()
    out = pv.PolyData(sm.points, faces)
    out.point_data["N"] = sm.normals
    out.cell_data["face"] = sm.face
    out.cell_data["stripe"] = sm.stripe
    out.cell_data["parent"] = sm.parent
    rgb = _refl.stripe_colors(box, sm.face, sm.stripe)
    if shaded:
        rgb = _paper.stripe_shading(sm, box, (lambda Y: eye_pt - Y) if eye_pt is not None else view_dir)
        out.field_data["lit"] = np.array([1])
    out.cell_data["RGB"] = np.round(255 * rgb).astype(np.uint8)
    out.field_data["unresolved"] = np.array([unresolved])
    out.set_active_scalars("RGB", preference="cell")
    out.field_data["box_lo"] = box.lo
    out.field_data["box_hi"] = box.hi
    out.field_data["stripe_widths"] = box.widths
    return out


def reflection_lines(surface, direction=(1.0, 0.0, 0.0), count=9, *, spacing=None, plane_normal=(0.0, 0.0, 1.0),
                     height=None, eye=None, view=None, resolution=None):
    """Reflection lines of a family of parallel light lines (Klass 1980, Choi & Lee, reference [3]).

    ``count`` light lines parallel to ``direction``, ``spacing`` apart, lie in
    a plane with normal ``plane_normal`` at ``height`` beyond the surface's
    bounding box, centred over it.  A reflection line is where the view ray,
    reflected at the surface, meets a light line: the level set ``φ = j`` of
    the light-line coordinate of :func:`lab.reflection.light_line_values`.
    Where the reflected ray does not reach the plane there are no lines.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    direction : (3,) array_like
        Direction of the light lines; its component along ``plane_normal`` is removed.
    count : int
        Number of light lines (1 … 1000).
    spacing : float, optional
        Distance between light lines; default: the plane's extent across the
        lines (3 × the diagonal) divided by ``count``.
    plane_normal : (3,) array_like
        Normal of the light plane, pointing away from the surface.
    height : float, optional
        Distance of the light plane beyond the bounding box, default: the diagonal.
    eye, view : (3,) array_like, optional
        Eye point, or direction towards an eye at infinity (default
        :data:`lab.reflection.VIEW_DIRECTION`).
    resolution : int, optional

    Returns
    -------
    pyvista.PolyData
        Polylines with cell data ``light_line`` (index j of the light line).
        Field data ``light_origin``, ``light_across`` (unit vector from one light
        line to the next), ``spacing``.
    """
    mesh = as_curvature_mesh(surface, resolution)
    count = _check_levels(count, mesh, "count", "reflection_lines")
    n = _v.as_direction(plane_normal, "plane_normal")
    d = _v.as_direction(direction, "direction")
    d = d - (d @ n) * n
    if np.linalg.norm(d) < 1e-9:
        raise ValueError("direction must not be parallel to plane_normal (the light lines lie in the light plane)")
    d /= np.linalg.norm(d)
    eye_pt, view_dir = _eye_or_view(eye, view)
    X = np.asarray(mesh.points, dtype=float)
    diag = _diagonal(X)
    if diag == 0:
        raise ValueError("the surface has zero extent")
    height = diag if height is None else _v.as_number(height, "height", positive=True)
    spacing = 3.0 * diag / count if spacing is None else _v.as_number(spacing, "spacing", positive=True)
    w = np.cross(n, d)
    centre = 0.5 * (X.min(axis=0) + X.max(axis=0))
    top = np.max(X @ n)
    origin = centre + (top + height - centre @ n) * n - 0.5 * (count - 1) * spacing * w
    E = _refl.view_vectors(X, eye=eye_pt, view=view_dir)
    R = _refl.reflect(E, _normals(mesh))
    P0, P1 = _refl.light_line_values(X, R, origin, n, d, spacing)
    valid = P1 > 0
    T = _triangles(mesh)
    groups = []
    join = _models.join_tol(mesh)
    for j in range(count):
        values = np.where(valid, P0 - j * P1, np.nan)
        groups.append(((j,), _models.joined(level_lines(X, T, values, 0.0), join)))
    out = _lines_mesh(groups, ("light_line",))
    out.field_data["light_origin"] = origin
    out.field_data["light_across"] = w
    out.field_data["spacing"] = np.array([spacing])
    return out


def isophotes(surface, light=(0.0, 0.0, 1.0), count=9, *, resolution=None):
    r"""Isophotes (Poeschl): curves of constant :math:`\mathbf N\cdot\mathbf L`, at ``count`` equally spaced angles.

    The levels are :math:`\cos\alpha_j`, :math:`\alpha_j = j\pi/(\text{count}+1)`
    (:func:`lab.reflection.isophote_levels`): the angle between the normal and
    the light direction steps by ``180° / (count + 1)``; the curves do not
    depend on the orientation of the normal.

    Parameters
    ----------
    surface : lab.Surface, lab.BezierPatches or pyvista.PolyData
    light : (3,) array_like
        Light direction L (non-zero).
    count : int
        Number of isophote levels (1 … 1000).
    resolution : int, optional

    Returns
    -------
    pyvista.PolyData
        Polylines with cell data ``level`` (j - 1), ``angle`` (α_j in degrees) and ``value`` (cos α_j).
    """
    mesh = as_curvature_mesh(surface, resolution)
    L = _v.as_direction(light, "light")
    count = _check_levels(count, mesh, "count", "isophotes")
    X = np.asarray(mesh.points, dtype=float)
    T = _triangles(mesh)
    values = _normals(mesh) @ L
    alpha, levels = _refl.isophote_levels(count)
    # |N.L - c| <= 1e-12 is rounding noise: such vertices count as on the level (see level_lines)
    join = _models.join_tol(mesh)
    groups = [((j, np.degrees(a), c), _models.joined(level_lines(X, T, values, c, tol=ISOPHOTE_TOL), join))
              for j, (a, c) in enumerate(zip(alpha, levels))]
    return _lines_mesh(groups, ("level", "angle", "value"))
