"""Per-student surfaces: each student's own variant of an assignment's surface (``lab.my_surface``).

A **family** (:data:`FAMILIES`, one per assignment that has one) turns a few bounded parameters into a surface of the
same character as the assignment's common surface: notebook 05's is the practical's B-spline surface with its control
net's x, y mapped by ``x → a x + s y``, ``y → b y`` and its heights scaled by ``c`` (an affine map of the plane with a
positive determinant and a vertical scaling multiply the Hessian's determinant of the height function by a positive
number: the sign of K at every point stays that of the common surface, and no point becomes degenerate).

Which variant a student has is decided by the instructor's release (``curvature-lab release --per-student``,
:mod:`lab.teaching.course.variants`: an HMAC of the student's user name under the course's secret, mapped onto the
parameters' grids).  The secret never leaves the course repository; the hand-out carries only the table
``variants.json`` of ``student → assignment → parameters`` (:func:`read_table`), and this module reads it:

* in the grader's sandbox (``LAB_GRADING``): the student's own parameters as the grader hands them over in
  ``LAB_VARIANT``, else the common surface;
* in a student's JupyterLab: the table named by ``LAB_VARIANTS``, else the ``variants.json`` of the hand-out the
  notebook runs in (the first folder above the working folder with a ``.lab-release`` mark), else the one beside the
  library; the student is ``JUPYTERHUB_USER``, else the login name.  No table: the common surface (a release without
  ``--per-student``); a table without the student: the common surface, said so.

Runs in the student's kernel and in the sandbox: it holds parameters and surfaces, never an answer.
"""

import getpass
import hashlib
import json
import math
import os
from dataclasses import dataclass, field
from pathlib import Path

from ... import repository
from ...i18n import _

__all__ = ["ENV_TABLE", "ENV_VARIANT", "FAMILIES", "FORMAT", "RELEASE_MARK", "TABLE", "Family", "Table", "Variant",
           "current_user", "find_table", "my_surface", "read_table", "resolve", "table_id"]

#: The name of the table in a hand-out, and what its ``format`` says.
TABLE = "variants.json"
FORMAT = "curvature-lab variants 1"
#: The mark of a hand-out's root (written by ``curvature-lab release``).
RELEASE_MARK = ".lab-release"
#: The student's own variant in the graded run: ``{"student": name, "variants": {assignment: parameters}}`` (JSON).
ENV_VARIANT = "LAB_VARIANT"
#: The path of a variants table, for a hub whose students do not work inside the hand-out.
ENV_TABLE = "LAB_VARIANTS"
#: Largest table read (bytes): 200 students of a few assignments take a few hundred kB.
MAX_TABLE = 16 << 20


@dataclass(frozen=True)
class Family:
    """The variants of one assignment's surface: parameters on bounded grids and how they make a surface.

    ``parameters``: ``{name: (low, high, step)}``, each value ``low + k step`` up to ``high`` (dyadic steps: the
    values and the control net stay exact in binary); the common surface has ``common``.
    """

    assignment: str
    parameters: dict
    common: dict
    build: object = field(repr=False, default=None)
    describe: object = field(repr=False, default=None)
    #: What must be the same as the common surface's (the release checks every variant): ``character(surface)``.
    character: object = field(repr=False, default=None)
    #: The graded tasks about this surface (their answers must differ from variant to variant).
    tasks: tuple = ()

    def grid(self, name):
        """The values parameter ``name`` may take."""
        low, high, step = self.parameters[name]
        return [low + k * step for k in range(round((high - low) / step) + 1)]

    def from_digest(self, digest):
        """Parameters from 32 bytes (an HMAC): two bytes per parameter pick a value of its grid."""
        if len(digest) < 2 * len(self.parameters):
            raise ValueError("too few bytes for the parameters")
        out = {}
        for k, name in enumerate(sorted(self.parameters)):
            values = self.grid(name)
            out[name] = values[int.from_bytes(digest[2 * k:2 * k + 2], "big") % len(values)]
        return out

    def validate(self, params, where=""):
        """``params`` as ``{name: float}``, every parameter present, finite and in its range; ``ValueError``
        otherwise (``where`` names the table and student)."""
        if not isinstance(params, dict) or set(params) != set(self.parameters):
            raise ValueError(f"{where}: the parameters of {self.assignment} are {', '.join(sorted(self.parameters))};"
                             f" got {params!r}"[:500])
        out = {}
        for name, (low, high, _step) in self.parameters.items():
            value = params[name]
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
                    or not low <= value <= high:
                raise ValueError(f"{where}: {name} must be a number from {low:g} to {high:g}; got {value!r}"[:500])
            out[name] = float(value)
        return out

    def surface(self, params=None):
        """The surface of ``params`` (None: the common surface)."""
        return self.build(self.common if params is None else self.validate(params, self.assignment))


def _practical_variant(p):
    """The practical's B-spline surface with x → a x + s y, y → b y, z → c z applied to its control net."""
    import numpy as np

    from ...model.surface import BSplineSurface
    from ...model.surfaces import practical

    base = practical()
    P = base.control_points
    X, Y, Z = P[..., 0], P[..., 1], P[..., 2]
    net = np.stack([p["stretch_x"] * X + p["shear"] * Y, p["stretch_y"] * Y, p["height"] * Z], axis=-1)
    return BSplineSurface(net, base.knots_u, base.knots_v, *base.degree)


def _practical_character(surface):
    """The sign of K at every corner of the patches refined once, and that no corner is degenerate: what a variant
    shares with the common surface (the bump's elliptic cap, the hyperbolic rest, the parabolic lines between)."""
    import numpy as np

    c = surface.to_bezier_patches().refine(1).corner_curvature()
    return np.sign(c.K).astype(int).tobytes() + bytes([bool(np.any(c.degenerate))])


def _practical_text(p):
    return _("the practical's control net with x → {a} x + {s} y, y → {b} y and the heights times {c}").format(
        a=f"{p['stretch_x']:.10g}", s=f"{p['shear']:.10g}", b=f"{p['stretch_y']:.10g}", c=f"{p['height']:.10g}")


#: Notebook 05's family: the practical's surface, stretched, sheared and raised within ±1/8 (steps of 1/128).
PRACTICAL = Family(
    "05_visualize_curvature",
    {"stretch_x": (0.875, 1.125, 1 / 128), "stretch_y": (0.875, 1.125, 1 / 128), "shear": (-0.125, 0.125, 1 / 128),
     "height": (0.875, 1.125, 1 / 128)},
    {"stretch_x": 1.0, "stretch_y": 1.0, "shear": 0.0, "height": 1.0},
    _practical_variant, _practical_text, _practical_character, ("own_surface",))

#: The assignments that have per-student surfaces, by id.
FAMILIES = {PRACTICAL.assignment: PRACTICAL}


def family(assignment):
    """The :class:`Family` of ``assignment``; ``ValueError`` naming the ones there are."""
    try:
        return FAMILIES[assignment]
    except (KeyError, TypeError):
        raise ValueError(_("{assignment} has no per-student surface; these assignments have one: {known}").format(
            assignment=repr(assignment), known=", ".join(FAMILIES))) from None


@dataclass(frozen=True)
class Table:
    """A variants table: ``students[name][assignment]`` is that student's parameters; ``id`` names the table."""

    id: str
    students: dict
    path: str = ""

    def params(self, student, assignment):
        """The parameters of ``student`` for ``assignment``, or None (not on the roster, or no variant)."""
        return self.students.get(student, {}).get(assignment)


def table_id(students):
    """The id of a table's content: 16 hex digits of the SHA-256 of its students and parameters (no secret in it)."""
    text = json.dumps(students, sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def read_table(path):
    """The :class:`Table` in the file ``path`` (what ``release --per-student`` writes); ``ValueError`` saying what is
    wrong with it."""
    path = Path(path)
    with open(path, "rb") as fh:
        raw = fh.read(MAX_TABLE + 1)
    if len(raw) > MAX_TABLE:
        raise ValueError(f"{path}: larger than {MAX_TABLE >> 20} MiB: not a variants table")
    try:
        data = json.loads(raw.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError) as exc:
        raise ValueError(f"{path}: not JSON ({exc})") from None
    if not isinstance(data, dict) or data.get("format") != FORMAT or not isinstance(data.get("students"), dict):
        raise ValueError(f"{path}: not a variants table (its format must be {FORMAT!r}, with a 'students' object)")
    students = {}
    for student, variants in data["students"].items():
        if not isinstance(variants, dict):
            raise ValueError(f"{path}: student {student!r}: expected an object of assignments")  # noqa: TRY004 - a bad file
        students[student] = {a: family(a).validate(p, f"{path}: {student}") for a, p in variants.items()}
    return Table(table_id(students), students, str(path))


def find_table():
    """The path of the variants table this kernel uses, or None (see the module docstring)."""
    named = os.environ.get(ENV_TABLE, "")
    if named:
        return Path(named)
    here = Path.cwd()
    for folder in (here, *here.parents):
        if (folder / RELEASE_MARK).is_file():
            return folder / TABLE if (folder / TABLE).is_file() else None
    root = Path(repository())
    if (root / RELEASE_MARK).is_file() and (root / TABLE).is_file():
        return root / TABLE
    return None


def current_user():
    """The student: ``JUPYTERHUB_USER`` (a hub's user name), else the login name."""
    name = os.environ.get("JUPYTERHUB_USER", "")
    if name:
        return name
    try:
        return getpass.getuser()
    except (KeyError, OSError):  # no login name (a container without a passwd entry)
        return ""


@dataclass(frozen=True)
class Variant:
    """Whose surface it is: ``student``, the ``params`` (None: the common surface) and ``status``: ``"own"`` (the
    student's own variant), ``"common"`` (no per-student release), ``"not on roster"`` (a per-student release
    without this student: the common surface)."""

    assignment: str
    student: str
    params: dict = None
    status: str = "common"

    def __str__(self):
        if self.status == "own":
            return _("your surface (the variant of {student}): {what}").format(
                student=self.student, what=FAMILIES[self.assignment].describe(self.params))
        if self.status == "not on roster":
            return _("the common surface of the course: {student} is not on the roster of this per-student hand-out; "
                     "tell your instructor").format(student=self.student or "?")
        return _("the common surface of the course (this hand-out gives every student the same one)")


def resolve(assignment, *, student=None, table=None):
    """The :class:`Variant` of ``assignment`` for this kernel (see the module docstring), or for ``student`` in
    ``table`` when given."""
    family(assignment)
    if table is None and student is None:
        if os.environ.get("LAB_GRADING") == "1":
            return _graded_variant(assignment)
        path = find_table()
        if path is None:
            return Variant(assignment, current_user())
        table = read_table(path)
    student = current_user() if student is None else student
    if table is None:
        return Variant(assignment, student)
    params = table.params(student, assignment)
    if params is None:
        return Variant(assignment, student, None, "not on roster")
    return Variant(assignment, student, params, "own")


def _graded_variant(assignment):
    """The graded run's variant: what the grader put into ``LAB_VARIANT`` (the student's own parameters)."""
    try:
        given = json.loads(os.environ.get(ENV_VARIANT, "") or "{}")
    except ValueError:
        given = {}
    params = given.get("variants", {}).get(assignment) if isinstance(given, dict) else None
    student = str(given.get("student", "")) if isinstance(given, dict) else ""
    if params is None:
        return Variant(assignment, student)
    return Variant(assignment, student, family(assignment).validate(params, ENV_VARIANT), "own")


def my_surface(assignment="05_visualize_curvature"):
    """Your own surface of an assignment: in a per-student hand-out every student has a variant of its own.

    An instructor may give each student a variant of an assignment's surface (``curvature-lab release
    --per-student``): the same kind of surface, with the same signs of the curvature everywhere and the same work to
    do, but other numbers, so that a classmate's numbers are not yours.  Your variant comes from your user name on
    the hub (``JUPYTERHUB_USER``, else your login name) and the hand-out's table ``variants.json``; it is the same in
    every run, in your checks and in the grader.  Without a per-student hand-out everybody gets the common surface
    (for notebook 05: ``lab.surfaces.practical()``).

    Parameters
    ----------
    assignment : str, optional
        The assignment (notebook) id; the ones with per-student surfaces are ``"05_visualize_curvature"``.

    Returns
    -------
    lab.BSplineSurface
        The surface.  Its attribute ``variant`` says whose it is and how it differs from the common one:
        ``print(surface.variant)``.

    Raises
    ------
    ValueError
        For an assignment without per-student surfaces, or a variants table that is not one.

    Examples
    --------
    >>> import lab
    >>> surface = lab.my_surface("05_visualize_curvature")
    >>> print(surface.variant)  # doctest: +SKIP
    your surface (the variant of ada): the practical's control net with x → 0.953125 x + 0.0625 y, …
    """
    variant = resolve(assignment)
    surface = family(assignment).surface(variant.params)
    surface.variant = variant
    return surface
