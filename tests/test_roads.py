"""Every road to an answer is withheld: the library's public functions that return curvature values, principal
directions or colours are found by reading their docstrings (not from a list someone keeps), and each is called, with
real arguments, in the grading sandbox's copy of the library for every graded task whose answer is made of what it
returns.  It must raise the withheld marker (it, or what it calls, is withheld), or be unusable there (OpenCASCADE and
rhino3dm are not installed in the sandbox of an assignment that reads no CAD file), or be listed in :data:`CANNOT`
with the reason it cannot give that answer.  A new function that returns curvature makes this test fail until it
is withheld or explained.
"""

import importlib
import importlib.util
import inspect
import json
import pkgutil
import re
import subprocess
import sys
from pathlib import Path

import pytest

import lab
from lab.teaching.grader import assignments, notebook
from lab.teaching.kernel import protocol
from lab.teaching.sandbox import bubblewrap, withhold
from lab.teaching.tasks import TASKS

ROOT = Path(__file__).resolve().parent.parent

#: What a graded task's answer is made of.
NEEDS = {"fundamental_forms": {"curvature"}, "curvatures": {"curvature"}, "principal_directions": {"curvature", "directions"},
         "visualize_curvature": {"curvature", "colours"}, "h": {"colours"}, "f1": {"colours"}, "f2": {"colours"},
         "f3": {"colours"}, "deficit_curvature": {"discrete"}}
#: How a docstring's summary or Returns section says what a function returns.
KINDS = {"curvature": re.compile(r"curvature|\bk1\b|κ1|principal|fundamental form", re.IGNORECASE),
         "directions": re.compile(r"\bdirections?\b", re.IGNORECASE), "colours": re.compile(r"colou?rs?\b", re.IGNORECASE),
         "discrete": re.compile(r"angle deficit|mixed (Voronoi )?area|discrete", re.IGNORECASE)}
#: What a road returns in truth where its docstring names curvature only as its input.
KIND_OF = {"lab.geometry.colormaps.colors_for": {"colours"}, "lab.geometry.colormaps.symmetric": {"colours"},
           "lab.mesh.build.color_curvature": {"colours"},
           # estimates from the triangles of a mesh it is given, not the exact curvature the other tasks compare to 1e-9
           "lab.geometry.discrete.gaussian_curvature": {"discrete"}, "lab.geometry.discrete.mean_curvature": {"discrete"},
           "lab.geometry.discrete.cotangent_laplacian": {"discrete"}, "lab.interrogation.estimators.estimate": {"discrete"}}
#: Roads a task allows (its ``allowed`` helpers, what the student wrote in an earlier task): not withheld.
ALLOWED = {
    "visualize_curvature": {"lab.geometry.colormaps.h", "lab.geometry.colormaps.f1", "lab.geometry.colormaps.f2",
                            "lab.geometry.colormaps.f3"},
    # the fundamental forms are the earlier task's answer and this one's input to the Weingarten map; a comb is the
    # normal curvature along an iso-line, no direction of principal curvature
    "principal_directions": {"lab.geometry.curvature.fundamental_forms", "lab.geometry.curvature.unit_normal",
                             "lab.model.surface.Surface.fundamental_forms", "lab.model.surface.Surface.normal",
                             "lab.interrogation.combs.iso_comb", "lab.interrogation.combs.comb",
                             "lab.interrogation.continuity.measures"},
}
#: Roads that return something of a kind but cannot give a task's answer, with the reason.
CANNOT = {
    "lab.teaching.course.mark.mark": "the instructor's marking panel of written answers (and not in the sandbox at all)",
    "lab.teaching.kernel.variants.my_surface": "the student's own surface: its curvature methods are roads of their "
                                               "own, each withheld",
    "lab.geometry.analytic.to_float": "turns a given sympy expression into floats: no curvature of its own",
    "lab.geometry.bezier.split": "subdivides a net (de Casteljau): control points, no direction field",
    "lab.geometry.colormaps.dill": "Dill's five bands, not the ramp h or the maps f1, f2, f3",
    "lab.geometry.colormaps.dill_names": "the names of Dill's bands",
    "lab.geometry.colormaps.map_range": "the range a named map uses (two numbers), no colour",
    "lab.geometry.curvature.as_mode": "parses a mode's name",
    "lab.geometry.curvature.zero_tolerance": "a tolerance from a size",
    "lab.geometry.curvature.curvature_values": "picks K, H, k1 or k2 from a Curvature it is given",
    "lab.geometry.curvature.fill_degenerate": "fills flagged points of a Curvature it is given from its neighbours",
    "lab.geometry.directions.CurvatureDirections.classify": "classifies given k1, k2 (elliptic, parabolic, …)",
    "lab.interrogation.maps.min_radius": "1 / max(|k1|, |k2|) of given k1, k2",
    "lab.interrogation.focal.focal_function": "f(k1, k2) of given principal curvatures (Choi & Lee's K, H, κ1²+κ2²)",
    "lab.interrogation.reflection.stripe_colors": "the stripe colours of a box for given reflection vectors",
    "lab.interrogation.geodesics.geodesic": "a geodesic path's points (its direction is the one it is given)",
    "lab.interrogation.geodesics.paths.geodesic": "a geodesic path's points (its direction is the one it is given)",
    "lab.interrogation.geodesics.normal_section": "a normal section's points (its direction is the one it is given)",
    "lab.interrogation.geodesics.paths.normal_section": "a normal section's points (its direction is given)",
    "lab.model.patches.BezierPatch.set_colors": "stores the colours it is given",
    "lab.model.patches.BezierPatch.set_curvature": "stores the values it is given",
    "lab.model.patches.BezierPatch.colors": "the colours stored by set_colors (the student's own)",
    "lab.model.patches.BezierPatches.copy": "copies the patches with what they store",
    "lab.model.patches.BezierPatches.refine_bytes": "the memory refine(num) would take",
    "lab.model.surface.Surface.sample_grid": "points of a grid (its docstring mentions the curvature grid it matches)",
    "lab.model.surface.Surface.sample_points": "points at parameters",
    "lab.model.surface.BSplineSurface.insert_knot": "a refined control net (knot insertion in a direction)",
    "lab.view.render.set_camera": "places the camera (a view direction)",
    "lab.view.render.plot_mesh": "draws a mesh it is given, with the scalars it carries",
    "lab.view.render.stored_legend": "the legend of the colours the patches store (the student's own)",
    "lab.view.figures.trimming_figure": "a picture of trimming loops and their directions",
    "lab.interrogation.stripe_methods.compare_stripe_methods": "reflection stripes, no curvature or map colour",
    "lab.interrogation.combs.border_combs": "curvature combs along borders: normal curvature of curves on the surface "
                                            "(from its derivatives, withheld where they are)",
    "lab.geometry.validation.choice_name": "the name of an enum's choice",
    "lab.interrogation.cad.geomview.parse_header": "parses a geomview file's header word",
    "lab.interrogation.cad.orientation.flip": "flips the signs of a Curvature it is given",
    "lab.interrogation.maps.below_radius": "compares given k1, k2 with a radius",
    "lab.interrogation.focal.focal_sheet": "X + N / κ for a given κ",
    "lab.interrogation.reflection_paper.color_difference": "compares two reflection stripe meshes",
    "lab.interrogation.reflection_paper.colors_at": "stripe colour keys of a split mesh",
    "lab.interrogation.reflection_paper.paper_stripe_map": "reflection stripes (Choi & Lee), no curvature or map colour",
    "lab.interrogation.reflection_paper.stripe_shading": "shading of reflection stripes",
    "lab.interrogation.reflection_paper.vertex_stripes": "the stripe of each reflected ray",
    "lab.mesh.build.patches_mesh": "a mesh of the patches with the colours they store (the student's own)",
    "lab.mesh.geomview.read_cbez": "reads a file (with the colours someone stored)",
    "lab.mesh.geomview.read_geomview": "reads a file (with the colours someone stored)",
    "lab.mesh.geomview.read_off": "reads a file (with the colours someone stored)",
    "lab.view.legend.measure_title": "a colour bar's title",
    "lab.view.legend.Legend.colors": "a legend's colour swatches for the range it is given",
    "lab.view.style.bar_box": "where a colour bar goes in a picture",
    "lab.view.style.fit_camera": "points a camera (a view direction)",
    "lab.interrogation.probe.probe_lines": "draws the lines of a probe result (made by lab.probe, withheld)",
    "lab.view.legend.map_range": "the range of values a colour map spans (two numbers), no colour",
    "lab.geometry.palettes.ramp": "Crameri's batlow and vik (cmcrameri's tables), not the ramp h",
    "lab.geometry.palettes.bands": "Dill's bands in five colours of batlow, not the ramp h or the maps f1, f2, f3",
    "lab.geometry.palettes.classes": "three colours of vik for a classification, not h∘f3's",
    "lab.geometry.vision.delta_e": "the CAM02-UCS distance of colours it is given",
    "lab.geometry.vision.lightness": "the lightness of colours it is given",
    "lab.geometry.vision.smallest_difference": "the smallest distance among colours it is given",
    "lab.view.legend.Legend.simulated": "a legend's colours as seen with a colour-vision deficiency",
    "lab.interrogation.deviation.deviation": "signed distances of points to a part (vik colours of distances), no "
                                             "curvature",
    "lab.interrogation.deviation.deviation_colors": "vik's colours of signed distances against a tolerance, not the "
                                                    "ramp h or the maps f1, f2, f3",
    "lab.interrogation.deviation.Deviation.colors": "vik's colours of a scan's distances, not the ramp h or f1, f2, f3",
    "lab.interrogation.deviation.Deviation.map": "a mesh coloured by a scan's distances (vik), no curvature colours",
    "lab.interrogation.projection.Piece.period": "the length of a closed face's domain (a number per direction), no "
                                                 "direction field",
}
#: The explorers are widgets: they are built on the library's curvature, so building one in the sandbox raises the
#: marker where that is withheld; their pictures and legends are read from what they hold.
WIDGETS = re.compile(r"^lab\.view\.explorers\.")

#: The net of the patch every road is called on (the same in the script below).
PART = [[[0, 0, 0], [0, 1, 0.2], [0, 2, 0]], [[1, 0, 0.3], [1, 1, 1.0], [1, 2, -0.2]], [[2, 0, 0], [2, 1, 0.4], [2, 2, 0.1]]]

CALL = r"""
import inspect, json, os, sys
import numpy as np
import lab
from lab.teaching.kernel.protocol import MARKER

P = np.array([[[0, 0, 0], [0, 1, 0.2], [0, 2, 0]], [[1, 0, 0.3], [1, 1, 1.0], [1, 2, -0.2]],
              [[2, 0, 0], [2, 1, 0.4], [2, 2, 0.1]]], dtype=float)
made = {}


def fixture(name):
    if name not in made:
        made[name] = {
            "surface": lambda: lab.BezierSurface(P), "base": lambda: lab.BezierSurface(P),
            "patches": lambda: lab.BezierPatches(np.stack([P, P + [0, 0, 0.5]])),
            "u": lambda: 0.3, "v": lambda: 0.6, "uv": lambda: np.array([0.3, 0.6]), "start": lambda: (0.3, 0.6),
            "starts": lambda: [(0.3, 0.6)], "which": lambda: 1, "length": lambda: 0.1, "direction": lambda: "u",
            "value": lambda: 0.5, "x": lambda: np.linspace(-1, 1, 5), "values": lambda: np.linspace(-1, 1, 5),
            "name": lambda: "linear", "color_map": lambda: "linear", "curvature_mode": lambda: "gaussian",
            "mode": lambda: "gaussian", "num": lambda: 1, "P": lambda: P, "u0": lambda: 0.3, "v0": lambda: 0.6,
            "uv": lambda: np.array([[0.3, 0.6], [0.4, 0.6], [0.5, 0.6]]),
            "d": derivatives, "dA": derivatives, "dB": derivatives, "tA": lambda: np.array([[1.0, 0.0, 0.0]]),
            "tB": lambda: np.array([[1.0, 0.0, 0.0]]),
            "bu": lambda: derivatives().bu, "bv": lambda: derivatives().bv, "buu": lambda: derivatives().buu,
            "buv": lambda: derivatives().buv, "bvv": lambda: derivatives().bvv,
            "model": model, "face": lambda: model().faces[0], "trimmed": lambda: lab.TrimmedSurface(fixture("surface")),
            "mesh": mesh, "measure": lambda: "gaussian", "index": lambda: 0,
        }[name]()
    return made[name]


def derivatives():
    rng = np.random.default_rng(3)
    b, bu, bv, buu, buv, bvv = rng.normal(size=(6, 1, 3))
    return lab.Derivatives(b, bu, bv, buu, buv, bvv)


def model():
    # a part read from a file: OpenCASCADE where the sandbox has it, the lab's own reader otherwise
    if os.path.exists("part.brep"):
        try:
            return lab.read("part.brep")
        except ImportError:
            pass
    from lab.interrogation.cad.model import Face, Model
    return Model([Face(0, "bspline", lab.BezierSurface(P))], name="part")


def mesh():
    import pyvista as pv
    m = pv.Plane(i_resolution=2, j_resolution=2)
    for key in ("K", "H", "k1", "k2"):
        m.point_data[key] = np.linspace(-1, 1, m.n_points)
    m.point_data["degenerate"] = np.zeros(m.n_points, dtype=bool)
    return m


def instance(qual):
    cls = qual.rsplit(".", 1)[0]
    if cls.endswith("Surface") and not cls.endswith("TrimmedSurface"):
        return fixture("surface")
    if cls.endswith("TrimmedSurface"):
        return lab.TrimmedSurface(fixture("surface"))
    if cls.endswith("BezierPatches"):
        return fixture("patches")
    if cls.endswith("Model"):
        return model()
    if cls.endswith("Face"):
        return model().faces[0]
    raise LookupError(f"no instance for {cls}")


out = {}
for qual in json.loads(sys.argv[1]):
    module, _, rest = qual.partition(":")
    try:
        obj = __import__(module, fromlist=["_"])
        for part in rest.split("."):
            obj = getattr(obj, part)
        func = obj.fget if isinstance(obj, property) else obj
        params = [p for p in inspect.signature(func).parameters.values()
                  if p.default is p.empty and p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)]
        try:  # a withheld body raises at once, whatever it is given
            func(*[None] * len(params))
        except BaseException as exc:  # noqa: BLE001
            if MARKER in str(exc):
                out[qual] = "withheld"
                continue
        args = [instance(rest) if p.name == "self" else fixture(p.name) for p in params]
        if rest.endswith("_grid"):  # one side of a grid in each direction
            args[1:3] = [np.array([0.3, 0.6]), np.array([0.3, 0.6])]
        # a map and a measure where a function takes them as options: the colours, not a refusal
        options = {p.name: fixture(p.name) for p in inspect.signature(func).parameters.values()
                   if p.name in ("curvature_mode", "color_map") and p.default is None}
        func(*args, **options)
        out[qual] = "returned"
    except KeyError as exc:
        out[qual] = f"no fixture for the argument {exc}"
    except BaseException as exc:  # noqa: BLE001 - what happened is the answer
        text = f"{type(exc).__name__}: {exc}"
        out[qual] = "withheld" if MARKER in text else text[:300]
print(json.dumps(out))
"""


def _kinds(obj):
    doc = inspect.getdoc(obj) or ""
    text = doc.split("\n\n")[0] + " " + (doc.split("Returns\n-------", 1)[1][:400] if "Returns\n-------" in doc else "")
    return {kind for kind, pattern in KINDS.items() if pattern.search(text)}


def roads():
    """``{"module:Qual.name": kinds}`` of the public functions and methods (in the ``__all__`` of every module of the
    library outside ``lab.teaching``) that return what a task needs."""
    found, seen = {}, set()

    def add(module, qual, obj):
        func = obj.fget if isinstance(obj, property) else obj
        code = getattr(func, "__code__", None)
        if code is None or code in seen:
            return
        kinds = _kinds(func)
        if kinds:
            seen.add(code)
            found[f"{module}:{qual}"] = kinds

    def add_class(cls):
        for name, member in inspect.getmembers(cls):
            if not name.startswith("_") and (inspect.isfunction(member) or isinstance(member, property)):
                owner = next(k for k in cls.__mro__ if name in vars(k))
                add(owner.__module__, f"{owner.__qualname__}.{name}", member)

    modules = [importlib.import_module(m.name) for m in pkgutil.walk_packages(lab.__path__, "lab.")
               if not m.name.startswith(("lab.teaching", "lab.cli", "lab.i18n"))]
    for module in [lab, *modules]:
        for member in (getattr(module, n, None) for n in getattr(module, "__all__", ())):
            if inspect.isfunction(member):
                add(member.__module__, member.__qualname__, member)
            elif inspect.isclass(member) and member.__module__.startswith("lab."):
                add_class(member)
    return found


def _dotted(road):
    module, _, qual = road.partition(":")
    return f"{module}.{qual}"


def _code(dotted):
    """The code object of the function or property named ``lab.module.Qual.name`` (one function has several names)."""
    parts = dotted.split(".")
    for cut in range(len(parts) - 1, 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except ImportError:
            continue
        for part in parts[cut:]:
            obj = getattr(obj, part)
        return (obj.fget if isinstance(obj, property) else obj).__code__
    raise LookupError(dotted)


def _excused():
    return {_code(name) for name in CANNOT}


def test_the_enumeration_finds_the_known_roads():
    """The docstrings name what they return: the OpenCASCADE comparison, a face's curvature, the probe, the maps."""
    found = {_dotted(r) for r in roads()}
    for road in ("lab.interrogation.cad.kernel.occ_curvature", "lab.interrogation.cad.model.Face.curvature",
                 "lab.interrogation.probe.probe", "lab.geometry.colormaps.h", "lab.geometry.colormaps.colors_for",
                 "lab.model.surface.Surface.curvature", "lab.interrogation.umbilics.umbilics"):
        assert road in found, road
    codes = {_code(_dotted(r)) for r in roads()}
    assert all(_code(name) in codes for name in CANNOT), [n for n in CANNOT if _code(n) not in codes]  # none stale


@pytest.fixture(scope="module")
def verdicts(tmp_path_factory):
    """``{task: {road: verdict}}``: each road called in the sandbox copy of the library a task is graded with."""
    candidates, excused = roads(), _excused()
    out, by_blocked = {}, {}
    for task, needs in NEEDS.items():
        blocked = tuple(withhold.withheld([task]))
        allowed = {_code(name) for name in ALLOWED.get(task, ())}
        mine = sorted(r for r, kinds in candidates.items()
                      if KIND_OF.get(_dotted(r), kinds) & needs and _code(_dotted(r)) not in excused | allowed
                      and not WIDGETS.match(_dotted(r)))
        if blocked not in by_blocked:
            package = withhold.prepare_package(blocked, list(TASKS), tmp_path_factory.mktemp("pkg"))
            if importlib.util.find_spec("OCP") is not None:  # a real part for the roads through OpenCASCADE
                lab.write(lab.BezierSurface(PART), str(package.parent / "part.brep"))
            by_blocked[blocked] = package
        package = by_blocked[blocked]
        done = subprocess.run([sys.executable, "-c", CALL, json.dumps(mine)], capture_output=True, text=True,
                              env={"PYTHONPATH": str(package.parent), "PATH": "/usr/bin:/bin", "LAB_GRADING": "1",
                                   "PYVISTA_OFF_SCREEN": "true"},
                              cwd=package.parent, timeout=600, check=False)
        assert done.returncode == 0, done.stderr[-3000:]
        out[task] = json.loads(done.stdout.strip().splitlines()[-1])
    return out


@pytest.mark.parametrize("task", list(NEEDS))
def test_every_road_to_the_answer_raises_in_the_sandbox(verdicts, task):
    open_roads = {road: verdict for road, verdict in verdicts[task].items() if verdict != "withheld"}
    assert open_roads == {}, f"{task}: these return what its answer is made of, in its graded sandbox"


def test_an_assignment_without_cad_files_has_no_cad_kernel(tmp_path):
    """OpenCASCADE's and rhino3dm's curvature (``BRepLProp_SLProps``, ``Surface.CurvatureAt``) are roads the lab
    cannot withhold function by function: the sandbox of an assignment that reads no CAD file does not have them,
    the real-part assignment (11) does.  Likewise libigl's and trimesh's discrete curvature (the angle deficit, the
    mixed area) are absent from the sandbox of notebook 13, whose task is to compute them, and present elsewhere."""
    pytest.importorskip("OCP")
    plain = assignments.load(ROOT / "exercises" / "en" / "05_visualize_curvature.ipynb")
    real = assignments.load(ROOT / "exercises" / "en" / "11_real_part.ipynb")
    meshes = assignments.load(ROOT / "exercises" / "en" / "13_meshes_and_scans.ipynb")
    assert not assignments.reads_cad(plain) and assignments.reads_cad(real)
    script = ("import importlib, json\ndef works(m, name):\n    try:\n        return hasattr(importlib.import_module(m), name)\n"
              "    except ImportError:\n        return False\n"
              "print(json.dumps({'OCP': works('OCP.BRepLProp', 'BRepLProp_SLProps'), "
              "'rhino3dm': works('rhino3dm', 'Surface'), 'numpy': works('numpy', 'cross'), "
              "'igl': works('igl', 'gaussian_curvature'), 'trimesh': works('trimesh.curvature', "
              "'discrete_gaussian_curvature_measure')}))")
    seen = {}
    for found in (plain, real, meshes):
        box = bubblewrap.Sandbox(bubblewrap.LAB_DIR, tmp_path / found.id, hide=notebook.hidden_modules(found))
        if not box.bwrap:
            pytest.skip("bubblewrap cannot run here")
        with box.workspace() as work:
            box.hand_over()
            (work / "run.py").write_text(f"import sys\nsys.stdout = open('seen.json', 'w')\n{script}\n")
            box.hand_over()
            code, _timed_out, stderr = box.run([sys.executable, "run.py"], 120)
            assert code == 0, stderr
            seen[found.id] = json.loads((work / "seen.json").read_text())
    assert seen[plain.id] == {"OCP": False, "rhino3dm": False, "numpy": True, "igl": True, "trimesh": True}
    assert seen[real.id] == {"OCP": True, "rhino3dm": True, "numpy": True, "igl": True, "trimesh": True}
    assert seen[meshes.id] == {"OCP": False, "rhino3dm": False, "numpy": True, "igl": False, "trimesh": False}


def test_the_module_path_of_every_road_imports():
    for road in roads():
        module, _, qual = road.partition(":")
        obj = importlib.import_module(module)
        for part in qual.split("."):
            obj = getattr(obj, part)
        assert callable(obj) or isinstance(obj, property), road
    assert protocol.MARKER  # the verdicts above look for this text
