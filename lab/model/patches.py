"""The practical's collection of Bézier patches (the practical's sheet, §5, class ``bezier_patches``).

The patches are stored as one array of shape ``(N, m+1, n+1, 3)`` so that
:meth:`BezierPatches.refine` and the curvature at the corners are computed for
all patches at once.  Iterating over the collection gives :class:`BezierPatch`
views with the practical's per-patch interface (``degree``,
``control_points``, ``set_curvature``, ``set_colors``, ``curvature``,
``colors``), which write into the shared arrays.
"""

import math
import warnings

import numpy as np

from ..geometry import bezier, colormaps
from ..geometry import curvature as _curv
from ..geometry import validation as _v
from ..geometry.colormaps import ColorMap, colors_for
from ..geometry.curvature import CurvatureMode, DegeneratePointWarning, curvature_values, zero_tolerance
from ..geometry.derivatives import Derivatives, from_homogeneous
from ..geometry.grids import NO_SEAMS, Seams
from ..i18n import _

__all__ = ["CORNER_U", "CORNER_V", "BezierPatch", "BezierPatches", "ColorMap", "CurvatureMode"]

#: How far a colour component may leave [0, 1] by rounding in :meth:`BezierPatch.set_colors` (it is clipped).
COLOR_ROUNDING = 1e-9

#: Parameters of the four corners, indexed ``[a, b]`` for ``(u, v) = (a, b)``.
CORNER_U = np.array([[0.0, 0.0], [1.0, 1.0]])
CORNER_V = np.array([[0.0, 1.0], [0.0, 1.0]])


#: Patches per chunk of refine (descendants) and visualize_curvature.
PATCH_CHUNK = 512
#: Levels of subdivision per chunk in refine: more levels are done in stages of at most this many.
LEVELS_PER_CHUNK = 2
#: Largest depth refine() takes at all (its estimate of 4**num patches is then refused anyway; 4**(10**80) would
#: take forever to compute).
MAX_REFINE = 10**6
#: Bytes per patch of the stored corner curvature (4 floats) and colours (12 floats).
PATCH_RESULT_BYTES = 16 * 8


def _refine(P, w, grid, num):
    """``num`` levels of :meth:`BezierPatches.refine`: nets ``(4**num N, ...)`` (and weights).

    The levels are done in stages of at most :data:`LEVELS_PER_CHUNK` levels
    (the first stage takes the rest: 7 = 1 + 2 + 2 + 2).  In a stage, every
    patch is subdivided ``k`` times in a row (:func:`lab.bezier.subdivide`,
    level by level, as refining level by level would), about
    :data:`PATCH_CHUNK` descendants at a time, and its ``2**k x 2**k``
    descendants are written straight into the stage's result.  So every
    depth does its work in chunks of the same shape (a fixed number of
    patches and levels: time per patch independent of the depth), and
    besides the result only the stage before it (1/16 of its size) and one
    chunk are held.  With a grid ``(rows, cols)`` descendant ``(a, b)`` of
    patch ``(i, j)`` goes to ``(i 2**k + a, j 2**k + b)``; otherwise the
    descendants of a patch follow it, in the order of the halves.
    """
    if num > LEVELS_PER_CHUNK:
        P, w, grid = _refine(P, w, grid, num - LEVELS_PER_CHUNK)
        num = LEVELS_PER_CHUNK
    n, f = len(P), 2**num
    tail_P, tail_w = P.shape[1:], None if w is None else w.shape[1:]
    new_P = np.empty((n * f * f,) + tail_P)
    new_w = None if w is None else np.empty((n * f * f,) + tail_w)
    per = max(1, PATCH_CHUNK // (f * f))  # patches per chunk: whole rows of the grid, or pieces of one row
    rows, cols = grid if grid is not None else (1, n)
    step_rows, step_cols = (max(1, per // cols), cols) if per >= cols else (1, per)
    for i0 in range(0, rows, step_rows):
        i1 = min(i0 + step_rows, rows)
        for j0 in range(0, cols, step_cols):
            j1 = min(j0 + step_cols, cols)
            if i1 - i0 > 1:
                sl = slice(i0 * cols, i1 * cols)  # whole rows
            else:
                sl = slice(i0 * cols + j0, i0 * cols + j1)
            Q, Qw = P[sl], None if w is None else w[sl]
            for _level in range(num):
                Q, Qw = bezier._subdivide(Q, 0.5, 0.5, Qw)  # (k, 2, 2, ...): the four halves of each
                Q = Q.reshape((-1,) + tail_P)
                Qw = None if Qw is None else Qw.reshape((-1,) + tail_w)
            for target, src, tail in ((new_P, Q, tail_P), (new_w, Qw, tail_w)):
                if target is None:
                    continue
                k = sl.stop - sl.start
                if grid is None:
                    target.reshape((n, f * f) + tail)[sl] = src.reshape((k, f * f) + tail)
                    continue
                # src is (k, a1, b1, a2, b2, ...): the row of a descendant is the binary number a1 a2 ..., its column b1 b2 ...
                src = src.reshape((i1 - i0, k // (i1 - i0)) + (2,) * (2 * num) + tail)
                order = (0, 1) + tuple(range(2, 2 * num + 2, 2)) + tuple(range(3, 2 * num + 2, 2))
                order += tuple(range(2 * num + 2, src.ndim))
                block = src.transpose(order).reshape((i1 - i0, k // (i1 - i0), f, f) + tail)  # [i, j, a, b]
                rest = tuple(range(4, block.ndim))
                target.reshape((rows, f, cols, f) + tail)[i0:i1, :, j0:j1] = block.transpose((0, 2, 1, 3) + rest)
    return new_P, new_w, None if grid is None else (rows * f, cols * f)


class BezierPatch:
    """View of one patch of a :class:`BezierPatches` collection (the practical's ``bezier_surface``)."""

    __slots__ = ("_index", "_owner")

    def __init__(self, owner, index):
        self._owner = owner
        self._index = index

    @property
    def degree(self):
        """Degrees ``(m, n)`` along u and v."""
        return self._owner.degree

    @property
    def control_points(self):
        """Control net, shape ``(m+1, n+1, 3)``, first index along u (a view: do not modify)."""
        return self._owner.control_points[self._index]

    @property
    def weights(self):
        """Weights ``(m+1, n+1)`` of a rational patch, or None."""
        w = self._owner.weights
        return None if w is None else w[self._index]

    @property
    def curvature(self):
        """Stored corner values ``[[c00, c01], [c10, c11]]`` (index ``[u, v]``)."""
        return self._owner.curvature[self._index]

    @property
    def colors(self):
        """Stored corner colours, shape ``(2, 2, 3)`` indexed ``[u, v]``."""
        return self._owner.colors[self._index]

    def set_curvature(self, c00, c01, c10, c11):
        """Store the curvature at the corners; ``c01`` is the value at ``u = 0, v = 1``."""
        values = []
        for name, c in (("c00", c00), ("c01", c01), ("c10", c10), ("c11", c11)):
            if isinstance(c, (float, np.floating)) and math.isnan(c):
                warnings.warn(f"set_curvature: {name} is NaN (no curvature, as at a degenerate point); the corner "
                              "is painted grey", DegeneratePointWarning, stacklevel=2)
                values.append(math.nan)
                continue
            values.append(_v.as_number(c, f"set_curvature: {name}"))
        self._owner.curvature[self._index] = np.reshape(values, (2, 2))

    def set_colors(self, c00, c01, c10, c11):
        """Store the colours at the corners, each an ``(r, g, b)`` tuple in [0, 1]; ``c01`` is at ``u = 0, v = 1``.

        Components that leave [0, 1] by rounding only (at most :data:`COLOR_ROUNDING`, as ``1 + 1e-16`` from a
        student's h) are clipped into it, as the practical's framework accepted them.
        """
        try:  # the usual case in one array (a student's loop calls this for every patch)
            rgb = np.array((c00, c01, c10, c11), dtype=float)
        except (TypeError, ValueError, OverflowError):
            rgb = None
        if (rgb is not None and rgb.shape == (4, 3) and np.isfinite(rgb).all() and rgb.min() >= -COLOR_ROUNDING
                and rgb.max() <= 1 + COLOR_ROUNDING):
            self._owner.colors[self._index] = np.clip(rgb, 0.0, 1.0).reshape(2, 2, 3)
            return
        rgb = []  # say which corner is wrong
        for name, c in (("c00", c00), ("c01", c01), ("c10", c10), ("c11", c11)):
            try:
                arr = np.asarray(c, dtype=float)
            except (TypeError, ValueError):
                raise TypeError(f"set_colors: {name} must be an (r, g, b) tuple; got {_v._short(c)}") from None
            except OverflowError:  # an int beyond the float range
                raise ValueError(f"set_colors: {name} components must lie in [0, 1]; got {_v._short(c)}") from None
            if arr.shape != (3,):
                raise ValueError(f"set_colors: {name} must be an (r, g, b) tuple of 3 numbers; got shape {arr.shape}")
            if not np.all(np.isfinite(arr)) or arr.min() < -COLOR_ROUNDING or arr.max() > 1 + COLOR_ROUNDING:
                raise ValueError(f"set_colors: {name} components must lie in [0, 1]; got {tuple(arr.tolist())}")
            rgb.append(np.clip(arr, 0.0, 1.0))
        self._owner.colors[self._index] = np.reshape(rgb, (2, 2, 3))

    def __repr__(self):
        return "<BezierPatch {}>".format(_("{index} of degree {degree}").format(index=self._index, degree=self.degree))


def _as_seams(seams):
    """``seams`` as :class:`lab.grids.Seams`: ``(periodic, collapsed)`` with ``periodic`` two booleans (u, v) and
    ``collapsed`` two pairs of booleans (the edges u_min, u_max and v_min, v_max)."""
    wanted = "Seams((periodic_u, periodic_v), ((u_min, u_max), (v_min, v_max))) of booleans"

    def flags(x, shape):
        arr = np.asarray(x, dtype=object) if not isinstance(x, (str, bytes)) else None
        if arr is None or arr.shape != shape or not all(isinstance(b, (bool, np.bool_)) for b in arr.flat):
            raise TypeError(f"seams must be {wanted}; got {seams!r}")
        return tuple(map(bool, arr.flat))

    if isinstance(seams, Seams) or (isinstance(seams, (tuple, list)) and len(seams) in (1, 2)):
        parts = tuple(seams)
    else:
        raise TypeError(f"seams must be {wanted}; got {seams!r}")
    periodic = flags(parts[0], (2,))
    collapsed = flags(parts[1], (2, 2)) if len(parts) == 2 else (False,) * 4
    return Seams(periodic, (collapsed[:2], collapsed[2:]))


class BezierPatches:
    """A collection of Bézier patches of one degree, as in the practical's ``bezier_patches``.

    Parameters
    ----------
    control_points : (N, m+1, n+1, 3) array_like
        The nets, first index along u.  A single net ``(m+1, n+1, 3)`` is one patch.
    weights : (N, m+1, n+1) array_like, optional
        Weights of rational patches.
    grid_shape : (rows, columns), optional
        See :attr:`grid_shape`.
    seams : lab.grids.Seams, optional
        Where the tiled rectangle closes on itself or collapses (a torus, a
        sphere's poles); see :attr:`seams`.

    Attributes
    ----------
    curvature : ndarray, shape (N, 2, 2)
        Corner values stored by :meth:`BezierPatch.set_curvature` (NaN until set).
    colors : ndarray, shape (N, 2, 2, 3)
        Corner colours stored by :meth:`BezierPatch.set_colors` (NaN until set).
    """

    CURVATURE_GAUSSIAN = CurvatureMode.GAUSSIAN
    CURVATURE_AVERAGE = CurvatureMode.AVERAGE
    CURVATURE_PRINCIPAL_MAX = CurvatureMode.PRINCIPAL_MAX
    CURVATURE_PRINCIPAL_MIN = CurvatureMode.PRINCIPAL_MIN
    CURVATURE_STRAIN_ENERGY = CurvatureMode.STRAIN_ENERGY
    COLOR_MAP_LINEAR = ColorMap.LINEAR
    COLOR_MAP_CUT = ColorMap.CUT
    COLOR_MAP_CLASSIFICATION = ColorMap.CLASSIFICATION

    def __init__(self, control_points, weights=None, grid_shape=None, seams=None):
        P = _v.as_control_net(control_points, "control points", batch=True)
        if P.ndim == 3:  # a single net is one patch
            P = P[None]
            if weights is not None and np.ndim(weights) == 2:
                weights = np.asarray(weights)[None]
        if P.ndim != 4:
            raise ValueError(f"control points must have shape (N, m+1, n+1, 3); got {P.shape}")
        self._P = P
        self._w = _v.as_weights(weights, P.shape[:3])
        if grid_shape is not None:
            if not isinstance(grid_shape, (tuple, list, np.ndarray)) or np.asarray(grid_shape, dtype=object).ndim != 1:
                raise TypeError(f"grid_shape must be (rows, columns), two integers; got {grid_shape!r}")
            grid_shape = tuple(_v.as_positive_int(x, "grid_shape entry", minimum=1) for x in grid_shape)
            if len(grid_shape) != 2 or grid_shape[0] * grid_shape[1] != len(P):
                raise ValueError(f"grid_shape must be (rows, columns) with rows * columns = {len(P)} patches; "
                                 f"got {grid_shape}")
        self._grid = grid_shape
        if seams is not None and grid_shape is None:
            raise ValueError("seams describe the edges of a grid of patches: give grid_shape too")
        self._seams = NO_SEAMS if seams is None else _as_seams(seams)
        self._reset()

    @property
    def grid_shape(self):
        """``(rows, columns)`` when the patches tile a rectangle of the (u, v) plane in row-major order
        (patch ``i * columns + j`` is the i-th along u and j-th along v, neighbours share edges), else None.

        Set by ``to_bezier_patches`` of B-spline and Bézier surfaces and kept by :meth:`refine`;
        meshes use it to weld shared corners by index.
        """
        return self._grid

    @property
    def seams(self):
        """:class:`lab.grids.Seams` of the rectangle the patches tile: which of its edges meet (periodic
        surfaces) or collapse to a point (a sphere's poles), from the surface; meshes weld them by index."""
        return self._seams

    def _reset(self):
        self._size = None
        n = len(self._P)
        self.curvature = np.full((n, 2, 2), np.nan)
        self.colors = np.full((n, 2, 2, 3), np.nan)

    # -- the practical's interface ------------------------------------------------

    @property
    def control_points(self):
        """All nets, shape ``(N, m+1, n+1, 3)``."""
        return self._P

    @property
    def weights(self):
        """All weights ``(N, m+1, n+1)``, or None for polynomial patches."""
        return self._w

    @property
    def degree(self):
        """Degrees ``(m, n)`` along u and v."""
        return self._P.shape[1] - 1, self._P.shape[2] - 1

    def __len__(self):
        return len(self._P)

    def __getitem__(self, index):
        index = _v.as_positive_int(int(index) if isinstance(index, np.integer) else index, "patch index")
        if index >= len(self):
            raise IndexError(f"patch index {index} out of range for {len(self)} patches")
        return BezierPatch(self, index)

    def __iter__(self):
        return (BezierPatch(self, i) for i in range(len(self)))

    def refine(self, num=1, *, memory_limit=None):
        """Replace every patch by its four halves (de Casteljau at u = v = 1/2), ``num`` times.

        Afterwards there are ``4**num`` times as many patches; stored curvature
        and colours are cleared.  Returns ``self``.

        The memory needed is estimated first (:meth:`refine_bytes`) and the
        call refused with a ``ValueError`` above ``memory_limit`` (default:
        :func:`lab.memory_limit`, a share of the available memory), so that
        ``refine(14)`` says so instead of taking the machine down.  All levels
        are done patch by patch in one pass, the descendants written straight
        into one new array (:func:`_refine`), so the time and the memory per
        patch do not grow with the number of patches.
        """
        num = _v.as_positive_int(num, "num", minimum=0, maximum=MAX_REFINE)
        n_final = len(self) * 4**num
        _v.check_memory(self.refine_bytes(num), f"refine({num}) of {len(self)} patches ({_v.format_count(n_final)} patches)",
                        memory_limit)
        if num:
            self._P, self._w, self._grid = _refine(self._P, self._w, self._grid, num)
        self._reset()
        return self

    def refine_bytes(self, num):
        """Estimated peak memory of :meth:`refine` ``(num)``, in bytes: the new nets and the cleared curvature
        and colours of the result, the old nets, the stage before the last (:func:`_refine`) and the
        temporaries of one chunk."""
        num = _v.as_positive_int(num, "num", minimum=0, maximum=MAX_REFINE)
        per_patch = self._P[0].nbytes + (0 if self._w is None else self._w[0].nbytes)
        n_final = len(self) * 4**num
        stage = n_final // 4**LEVELS_PER_CHUNK * per_patch if num > LEVELS_PER_CHUNK else 0
        chunk = max(PATCH_CHUNK, 4 ** min(num, LEVELS_PER_CHUNK)) * 16 * per_patch if num else 0
        return n_final * (per_patch + PATCH_RESULT_BYTES) + len(self) * per_patch + stage + chunk

    def visualize_curvature(self, curvature_mode, color_map, **options):
        """Compute the curvature at every corner and colour it (the practical's task, reference solution).

        For each patch: derivatives at the corners from the forward-difference
        nets, the chosen curvature from the fundamental forms, stored with
        ``set_curvature``; then the colour map over all corner values, stored
        with ``set_colors``.  Done for all patches at once, :data:`PATCH_CHUNK`
        patches at a time (so the time and the extra memory per patch stay
        constant however many patches there are).

        Parameters
        ----------
        curvature_mode : CurvatureMode or str
            ``CURVATURE_GAUSSIAN``, ``CURVATURE_AVERAGE``, ``CURVATURE_PRINCIPAL_MAX``
            or ``CURVATURE_PRINCIPAL_MIN`` (or ``CURVATURE_STRAIN_ENERGY``).
        color_map : ColorMap or str
            ``COLOR_MAP_LINEAR`` (h∘f2), ``COLOR_MAP_CUT`` (h∘f1),
            ``COLOR_MAP_CLASSIFICATION`` (h∘f3), or any name in
            :data:`lab.colormaps.COLOR_MAPS`.
        **options
            Passed to the colour map, e.g. ``vmin``, ``vmax`` for :func:`lab.colormaps.dill`.
        """
        curvature_mode = _curv.as_mode(curvature_mode)
        name = self._color_map_name(color_map)
        for sl, curv in self._corner_curvature_chunks():
            self.curvature[sl] = curvature_values(curv, curvature_mode)
        colors_for(self.curvature, name, tol=zero_tolerance(curvature_mode, self.size), out=self.colors, **options)

    # -- vectorised helpers -------------------------------------------------------

    @staticmethod
    def _color_map_name(color_map):
        names = list(colormaps.COLOR_MAPS)
        value = color_map.value if isinstance(color_map, ColorMap) else color_map
        return _v.as_choice(value, names, "colour map")

    @property
    def size(self):
        """Diagonal of the bounding box of the patch corners (the model's length scale; cached)."""
        if self._size is None:
            m, n = self.degree
            corners = self._P[:, :: max(m, 1), :: max(n, 1)]  # a view: the four corner points of every patch
            self._size = float(np.linalg.norm(corners.max(axis=(0, 1, 2)) - corners.min(axis=(0, 1, 2))))
        return self._size

    def _check_points(self, u, v, per_point, what, memory_limit):
        """Check the parameters and that ``N`` patches times their points fit in the memory limit."""
        u, v = _v.as_parameters(u, v, ((0.0, 1.0), (0.0, 1.0)))
        _v.check_memory(per_point * len(self) * u.size, f"{what} of {len(self)} patches at {u.size} points each",
                        memory_limit)
        return u, v

    def derivatives(self, u, v, *, memory_limit=None):
        """Derivatives of every patch at the points ``(u, v)``; fields of shape ``(N,) + S + (3,)``."""
        u, v = self._check_points(u, v, 400, "derivatives", memory_limit)
        return bezier.derivatives(self._P, u, v, self._w)

    def evaluate(self, u, v, *, memory_limit=None):
        """Points of every patch at ``(u, v)``, shape ``(N,) + S + (3,)``."""
        u, v = self._check_points(u, v, 100, "points", memory_limit)
        return bezier.evaluate(self._P, u, v, self._w)

    def curvature_at(self, u, v, *, memory_limit=None):
        """Exact curvature of every patch at the points ``(u, v)`` (shape ``(N,) + S``).

        Degenerate points get the limit from inside the patch (see
        :func:`lab.curvature.fill_degenerate`).
        """
        u, v = self._check_points(u, v, 800, "curvature", memory_limit)
        return self._with_limits(_curv.from_derivatives(bezier.derivatives(self._P, u, v, self._w)), u, v)

    def _with_limits(self, curv, u, v, patches=slice(None)):
        """Replace values at degenerate points by their limits from inside the patch (of ``self[patches]``)."""
        P = self._P[patches]
        w = None if self._w is None else self._w[patches]

        def derivatives_at(index, uu, vv):
            wk = None if w is None else w[index[0]]
            return bezier.derivatives(P[index[0]], uu, vv, wk, paired=True)

        return _curv.with_limits(curv, u, v, (0.5, 0.5), derivatives_at)

    def corner_derivatives(self, patches=slice(None)):
        """Derivatives at the four corners of every patch, fields ``(N, 2, 2, 3)`` indexed ``[patch, u, v]``.

        Read off the corners of the forward-difference nets
        (:func:`lab.bezier.corner_derivatives`), as in the practical's figure 3.
        ``patches`` (a slice) restricts it to some patches.
        """
        w = None if self._w is None else self._w[patches]
        D = Derivatives(*bezier._corner_values(bezier.homogeneous(self._P[patches], w)))  # nets checked on entry
        return D if w is None else from_homogeneous(D)

    def corner_curvature(self, derivatives=None):
        """Exact curvature at the four corners of every patch, fields of shape ``(N, 2, 2)`` indexed ``[patch, u, v]``.

        ``derivatives`` may pass in :meth:`corner_derivatives` when the caller already has them.
        """
        if derivatives is not None:
            return self._with_limits(_curv.from_derivatives(derivatives), CORNER_U, CORNER_V)
        out = None
        for sl, curv in self._corner_curvature_chunks():
            if out is None:
                out = [np.empty((len(self),) + np.shape(x)[1:], dtype=np.asarray(x).dtype) for x in curv]
            for o, x in zip(out, curv):
                o[sl] = x
        return _curv.Curvature(*out)

    def _corner_curvature_chunks(self):
        """``(slice, Curvature)`` of the corners of :data:`PATCH_CHUNK` patches at a time."""
        for start in range(0, max(len(self), 1), PATCH_CHUNK):
            sl = slice(start, min(start + PATCH_CHUNK, len(self)))
            curv = _curv.from_derivatives(self.corner_derivatives(sl))
            yield sl, self._with_limits(curv, CORNER_U, CORNER_V, sl)

    # -- output -------------------------------------------------------------------

    def to_mesh(self, resolution=1):
        """A welded :class:`pyvista.PolyData` of the patches; see :func:`lab.mesh.patches_mesh`."""
        from ..mesh import patches_mesh

        return patches_mesh(self, resolution=resolution)

    def write_cbez(self, path):
        """Export for geomview as coloured Bézier patches (``CBEZ333`` for bicubic); see :func:`lab.mesh.write_cbez`."""
        from ..mesh import write_cbez

        write_cbez(self, path)

    def write_off(self, path, resolution=1):
        """Export for geomview as a coloured OFF mesh; see :func:`lab.mesh.write_off`."""
        from ..mesh import write_off

        write_off(self.to_mesh(resolution), path)

    def copy(self):
        """An independent copy (nets, weights, stored curvature and colours)."""
        new = type(self).__new__(type(self))
        new._P = self._P.copy()
        new._w = None if self._w is None else self._w.copy()
        new.curvature = self.curvature.copy()
        new.colors = self.colors.copy()
        new._size = self._size
        new._grid = self._grid
        new._seams = self._seams
        return new

    def __repr__(self):
        text = _("{n} rational patches of degree {degree}") if self._w is not None else _("{n} patches of degree {degree}")
        return f"{type(self).__name__}({text.format(n=len(self), degree=self.degree)})"
