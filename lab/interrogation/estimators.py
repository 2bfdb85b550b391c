"""Curvature estimated on triangle meshes against the exact values: the lab's discrete operators, VTK's, libigl's
and trimesh's estimators, and how their error falls (or does not) as the mesh is refined (notebook 13).

The meshes are :func:`lab.mesh.triangle_mesh`: every vertex carries the exact K and H of its (u, v).  An error is
the largest difference over a set of vertices, relative to the mesh's largest exact |K| for K and to its largest
exact |κ| (max of |κ1|, |κ2|) for H, so a minimal surface (H = 0) has a scale too.  Vertices count as **inside**
when they are at least ``margin`` of the parameter domain's side from its boundary (``border_distance``), as the
**boundary** when they lie on an edge of only one triangle.

The estimators (:data:`ESTIMATORS`), each in the lab's sign of H (H < 0 on a sphere with outward normals; VTK,
libigl's quadric fit and trimesh report the opposite sign, turned here):

* ``lab``: the angle deficit over the mixed area and the cotangent Laplacian (:mod:`lab.geometry.discrete`, Meyer
  et al. 2003, §§3–4);
* ``VTK``: PyVista's ``PolyData.curvature`` (``vtkCurvatures``): the angle deficit 2π − Σθ at every vertex, boundary
  too, over a third of the adjacent triangles' area; H from the dihedral angles of the edges;
* ``libigl``: ``igl.gaussian_curvature`` (2π − Σθ at every vertex) over ``igl.massmatrix`` (Voronoi, the mixed area);
  H from the cotangent matrix, ``igl.cotmatrix``;
* ``libigl quadric``: ``igl.principal_curvature``, a quadric fitted to the neighbourhood: K = κ1 κ2, H = (κ1 + κ2)/2;
* ``trimesh``: ``discrete_gaussian_curvature_measure`` and ``discrete_mean_curvature_measure`` (Cohen-Steiner &
  Morvan's normal cycle) over a ball of radius twice the mean edge length, divided by the ball's area πr².

A convergence study (:func:`convergence`) measures the errors on meshes of several sizes and fits the order p of
error ≈ C hᵖ (h the mean edge length) on a log–log scale, over the finest meshes.
"""

from dataclasses import dataclass, field

import numpy as np

from ..geometry import discrete as _d
from ..geometry import validation as _v
from ..i18n import N_, _, decimal
from ..mesh.triangles import DIAGONALS, mesh_arrays, triangle_mesh
from ..model.surface import label as surface_label
from . import export

__all__ = ["DIAGONAL_NAMES", "ESTIMATORS", "Convergence", "EstimatorTable", "compare_estimators", "convergence",
           "diagonals_name", "estimate", "mesh_errors", "mesh_size"]

#: The estimators :func:`estimate` knows, in the order of the tables.
ESTIMATORS = ("lab", "VTK", "libigl", "libigl quadric", "trimesh")
#: Where an estimator comes from, for the message when it is missing.
_PACKAGES = {"libigl": "libigl", "libigl quadric": "libigl", "trimesh": "trimesh"}
#: The vertices of a mesh whose errors are measured.
REGIONS = ("inside", "boundary")
#: The share of the parameter domain's side that separates "inside" from the boundary.
MARGIN = 0.1
#: The ways of splitting the grid's quads (:data:`lab.mesh.triangles.DIAGONALS`) as people read them, marked for
#: translation (:func:`diagonals_name`).
DIAGONAL_NAMES = {"regular": N_("regular"), "alternating": N_("alternating"), "random": N_("random")}


def diagonals_name(diagonals):
    """``diagonals`` ("regular", "alternating", "random") as tables and notebooks write it, in the lab's language
    (German "regelmäßig", "abwechselnd", "zufällig"); the value a student passes stays the English one."""
    return _(DIAGONAL_NAMES[diagonals]) if diagonals in DIAGONAL_NAMES else diagonals


def mesh_size(mesh):
    """The mean edge length h of a triangle mesh (each interior edge counted twice, as its two triangles have it)."""
    points, faces = mesh_arrays(mesh)
    return float(np.mean(np.linalg.norm(points[faces] - points[np.roll(faces, 1, axis=1)], axis=-1)))


def _vtk(mesh):
    K = np.asarray(mesh.curvature("gaussian"), dtype=float)
    H = -np.asarray(mesh.curvature("mean"), dtype=float)
    return K, H


def _igl(points, faces, quadric):
    import igl

    if quadric:
        k1, k2 = igl.principal_curvature(points, faces)[2:4]
        return k1 * k2, -0.5 * (k1 + k2)
    area = igl.massmatrix(points, faces, igl.MASSMATRIX_TYPE_VORONOI).diagonal()
    K = igl.gaussian_curvature(points, faces) / area
    laplace = (igl.cotmatrix(points, faces) @ points) / area[:, None]
    H = 0.5 * np.einsum("ij,ij->i", laplace, igl.per_vertex_normals(points, faces))
    return K, H


def _trimesh(points, faces, mesh):
    import trimesh

    shape = trimesh.Trimesh(points, faces, process=False)
    radius = 2 * mesh_size(mesh)
    ball = np.pi * radius**2
    K = trimesh.curvature.discrete_gaussian_curvature_measure(shape, points, radius) / ball
    H = -trimesh.curvature.discrete_mean_curvature_measure(shape, points, radius) / ball
    return K, H


def estimate(mesh, estimator="lab"):
    """``(K, H)`` at the vertices of a triangle mesh by one of :data:`ESTIMATORS` (the module docstring), in the lab's
    sign of H; an ``ImportError`` naming the package when that estimator's package is not installed."""
    estimator = _v.as_choice(estimator, ESTIMATORS, "estimator")
    points, faces = mesh_arrays(mesh)
    try:
        if estimator == "lab":
            return _d.gaussian_curvature(points, faces), _d.mean_curvature(points, faces)
        if estimator == "VTK":
            return _vtk(mesh)
        if estimator.startswith("libigl"):
            return _igl(points, faces, estimator == "libigl quadric")
        return _trimesh(points, faces, mesh)
    except ImportError as exc:
        package = _PACKAGES.get(estimator, "") if exc.name in (None, "igl", "trimesh") else exc.name
        raise ImportError(_("{estimator} needs the package {package}, which is not installed (pip install "
                            "{package})").format(estimator=estimator, package=package or exc.name)) from exc


def _regions(mesh, margin):
    return {"inside": np.asarray(mesh.point_data["border_distance"]) >= margin - 1e-12,
            "boundary": np.asarray(mesh.point_data["boundary"], dtype=bool)}


def _scales(mesh):
    K = np.asarray(mesh.point_data["K"])
    kappa = np.maximum(np.abs(mesh.point_data["k1"]), np.abs(mesh.point_data["k2"]))
    return {"K": max(float(np.max(np.abs(K))), 1e-300), "H": max(float(np.max(kappa)), 1e-300)}


def mesh_errors(mesh, K, H, *, margin=MARGIN):
    """``{(quantity, region): relative error}`` of estimated ``K``, ``H`` against the mesh's exact values (the module
    docstring); NaN where the region has no vertex (a closed surface has no boundary)."""
    margin = _v.as_number(margin, "margin", minimum=0.0, maximum=0.5)
    regions, scales = _regions(mesh, margin), _scales(mesh)
    out = {}
    for name, value in (("K", K), ("H", H)):
        error = np.abs(np.asarray(value, dtype=float) - np.asarray(mesh.point_data[name])) / scales[name]
        for region, where in regions.items():
            out[name, region] = float(np.max(error[where])) if np.any(where) else float("nan")
    return out


def _number(x):
    return "–" if not np.isfinite(x) else decimal(f"{x:.2g}" if x < 1e3 else f"{x:.1e}")


@dataclass
class EstimatorTable:
    """The errors of each estimator on one mesh: ``rows`` of ``{"estimator", ("K", "inside"), …}`` or, for an
    estimator whose package is missing, ``{"estimator", "missing": message}``."""

    rows: list
    vertices: int
    h: float
    margin: float = MARGIN

    def error(self, estimator, quantity, region):
        """One error of the table (NaN for a missing estimator or an empty region)."""
        row = next(r for r in self.rows if r["estimator"] == estimator)
        return row.get((quantity, region), float("nan"))

    def table(self):
        """The table as text, in the current language."""
        head = [_("estimator"), _("K inside"), _("K boundary"), _("H inside"), _("H boundary")]
        lines = [_("largest error relative to the largest exact |K| or |κ|; {n} vertices, h = {h}, inside: at "
                   "least {margin} of the domain from its boundary").format(
                       n=self.vertices, h=decimal(f"{self.h:.3g}"), margin=decimal(f"{self.margin:g}")),
                 f"{head[0]:<16}" + "".join(f"{x:>12}" for x in head[1:])]
        for row in self.rows:
            if "missing" in row:
                lines.append(f"{row['estimator']:<16}" + _("not installed") + f" ({row['missing']})")
                continue
            lines.append(f"{row['estimator']:<16}" + "".join(f"{_number(row[q, r]):>12}" for q in ("K", "H")
                                                             for r in REGIONS))
        return "\n".join(lines)

    def _table(self):
        """One row per estimator: its four errors (NaN for a missing one, with the reason in ``missing``)."""
        nan = float("nan")
        columns = {"estimator": [r["estimator"] for r in self.rows]}
        for q in ("K", "H"):
            for region in REGIONS:
                columns[f"{q}_{region}"] = [float(r.get((q, region), nan)) for r in self.rows]
        columns["missing"] = [r.get("missing", "") for r in self.rows]
        unit = _("largest error / largest exact |K| or |κ|")
        return export.Table(_("errors of the curvature estimators"), columns,
                            {name: unit for name in columns if name[:2] in ("K_", "H_")},
                            {"vertices": str(self.vertices), "h": repr(float(self.h)),
                             "inside": _("at least {margin} of the domain from its boundary").format(
                                 margin=repr(float(self.margin)))})

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __str__(self):
        return self.table()


def compare_estimators(mesh, *, estimators=ESTIMATORS, margin=MARGIN):
    """Every estimator's errors on ``mesh`` (a :func:`lab.mesh.triangle_mesh`), inside and at the boundary: an
    :class:`EstimatorTable`; an estimator whose package is not installed is listed as such."""
    rows = []
    for name in estimators:
        try:
            K, H = estimate(mesh, name)
        except ImportError as exc:
            rows.append({"estimator": name, "missing": str(exc)})
            continue
        rows.append({"estimator": name, **mesh_errors(mesh, K, H, margin=margin)})
    return EstimatorTable(rows, mesh.n_points, mesh_size(mesh), margin)


@dataclass
class Convergence:
    """A convergence study: for each mesh its size ``h`` and ``errors[(quantity, region)]`` (arrays over the meshes),
    and the fitted ``orders[(quantity, region)]``, the slope of log(error) over log(h) on the ``fit`` finest meshes."""

    surface: str
    estimator: str
    diagonals: str
    sizes: list
    h: np.ndarray
    errors: dict
    orders: dict = field(default_factory=dict)
    noise: float = 0.0
    fit: int = 3

    def table(self):
        """The study as text: one row per mesh, the fitted orders last."""
        keys = [k for k in self.errors if np.all(np.isfinite(self.errors[k]))]
        names = {("K", "inside"): _("K inside"), ("K", "boundary"): _("K boundary"), ("H", "inside"): _("H inside"),
                 ("H", "boundary"): _("H boundary")}
        grid, order = _("grid"), _("order p")
        lines = [_("{surface}, {estimator}, diagonals {diagonals}: largest relative error").format(
                     surface=self.surface, estimator=self.estimator, diagonals=diagonals_name(self.diagonals)),
                 f"{grid:>9} {'h':>9}" + "".join(f"{names[k]:>12}" for k in keys)]
        for n, h, *errors in zip(self.sizes, self.h, *(self.errors[k] for k in keys)):
            lines.append(f"{n:>4} × {n:<3} {decimal(f'{h:.3g}'):>9}" + "".join(f"{_number(e):>12}" for e in errors))
        lines.append(f"{order:>19}" + "".join(f"{decimal(f'{self.orders[k]:.2f}'):>12}" for k in keys))
        return "\n".join(lines)

    def _table(self):
        """One row per mesh: n, h and the errors; the fitted orders in the header (``order K_inside: …``)."""
        keys = list(self.errors)
        columns = {"n": [int(n) for n in self.sizes], "h": [float(x) for x in self.h]}
        columns.update({f"{q}_{region}": [float(e) for e in self.errors[q, region]] for q, region in keys})
        unit = _("largest error / largest exact |K| or |κ|")
        units = {"h": _("mean edge length"), **{f"{q}_{region}": unit for q, region in keys}}
        meta = {"surface": self.surface, "estimator": self.estimator, "diagonals": self.diagonals,
                "noise": repr(float(self.noise)), "fit": _("orders by least squares over the {fit} finest meshes")
                .format(fit=self.fit)}
        meta.update({f"order {q}_{region}": repr(float(self.orders.get((q, region), float("nan"))))
                     for q, region in keys})
        return export.Table(_("convergence of a curvature estimator"), columns, units, meta)

    to_csv = export.to_csv
    to_pandas = export.to_pandas

    def __str__(self):
        return self.table()


def fit_order(h, error, last=3):
    """The slope p of log(error) against log(h) by least squares over the ``last`` smallest h: error ≈ C hᵖ."""
    h, error = np.asarray(h, dtype=float), np.asarray(error, dtype=float)
    order = np.argsort(h)[:last]
    if len(order) < 2 or not np.all(np.isfinite(error[order])) or np.any(error[order] <= 0):
        return float("nan")
    return float(np.polyfit(np.log(h[order]), np.log(error[order]), 1)[0])


def convergence(surface, sizes=(9, 17, 33, 65), *, estimator="lab", diagonals="regular", noise=0.0, margin=MARGIN,
                fit=3, name=None):
    """Errors of ``estimator`` on :func:`lab.mesh.triangle_mesh` of ``surface`` with ``n × n`` vertices for each n
    of ``sizes``, and the fitted orders (:class:`Convergence`)."""
    sizes = [_v.as_positive_int(n, "size", minimum=3) for n in sizes]
    if len(sizes) < 2:
        raise ValueError(f"a convergence study needs at least two mesh sizes; got {sizes}")
    diagonals = _v.as_choice(diagonals, DIAGONALS, "diagonals")
    fit = _v.as_positive_int(fit, "fit", minimum=2)
    h, errors = [], {}
    for n in sizes:
        mesh = triangle_mesh(surface, n, diagonals=diagonals, noise=noise)
        K, H = estimate(mesh, estimator)
        h.append(mesh_size(mesh))
        for key, value in mesh_errors(mesh, K, H, margin=margin).items():
            errors.setdefault(key, []).append(value)
    h = np.array(h)
    errors = {k: np.array(v) for k, v in errors.items()}
    orders = {k: fit_order(h, v, fit) for k, v in errors.items()}
    label = name or surface_label(surface)
    return Convergence(label, estimator, diagonals, sizes, h, errors, orders, float(noise), fit)
