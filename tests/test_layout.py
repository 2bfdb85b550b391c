"""The package layout: folders are layers, imports point down, no cycles, small modules, a cheap ``import lab``."""

import ast
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import lab

ROOT = Path(lab.__file__).resolve().parent
MAX_LINES = 600

#: Third-party packages a layer must not import (directly, at any depth of the module).
FORBIDDEN = {
    "geometry": {"pyvista", "vtk", "ipywidgets", "trame", "matplotlib", "nbformat", "nbclient", "IPython"},
    "mesh": {"ipywidgets", "trame", "matplotlib", "nbformat", "nbclient", "IPython", "sympy"},
    "model": {"pyvista", "ipywidgets", "trame", "matplotlib", "nbformat", "nbclient", "IPython"},
    "interrogation": {"ipywidgets", "trame", "matplotlib", "nbformat", "nbclient", "IPython", "sympy"},
    "view": {"nbformat", "nbclient"},
}


def module_name(path):
    parts = path.relative_to(ROOT.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def modules():
    return {module_name(p): p for p in sorted(ROOT.rglob("*.py"))}


def imports_of(name, path):
    """Every module imported anywhere in the file (module level and inside functions), as absolute names."""
    tree = ast.parse(path.read_text(), str(path))
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out += [(a.name, node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")
                base = base[: len(base) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module
            out.append((target, node.lineno))
            # "from . import bezier" imports a module too
            out += [(f"{target}.{a.name}", node.lineno) for a in node.names]
    return out


def layer_of(name):
    """Index of the module's layer; the package root (``lab``, ``lab.cli``) sits above all layers."""
    parts = name.split(".")
    if len(parts) > 1 and parts[1] in lab.LAYERS:
        return lab.LAYERS.index(parts[1])
    return len(lab.LAYERS)


def lab_imports(name, path, known):
    """The lab modules ``name`` imports (resolved to real modules; aliases such as lab.curvature are refused)."""
    found = set()
    for target, line in imports_of(name, path):
        if not target.startswith("lab.") or target == name:
            continue
        short = target.partition(".")[2]
        if name != "lab" and short in lab.MODULES:
            pytest.fail(f"{name} (line {line}) imports the alias {target}; inside the package use "
                        f"{lab.MODULES[short]}")
        if target in known:
            found.add(target)
    return found


def test_the_layers_are_the_folders():
    folders = sorted(p.name for p in ROOT.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    assert folders == sorted(lab.LAYERS)
    for layer in lab.LAYERS:
        doc = ast.get_docstring(ast.parse((ROOT / layer / "__init__.py").read_text()))
        summary = (doc or "").strip().split("\n\n")[0]  # a map of the layer's folders may follow (teaching)
        assert summary and len(summary.splitlines()) <= 3, f"lab/{layer}/__init__.py needs a summary of at most three lines"
        assert "import" in doc, f"lab/{layer}/__init__.py must say what the layer may import"


def test_imports_point_down_the_layers():
    known = modules()
    upward = []
    for name, path in known.items():
        for target in lab_imports(name, path, known):
            if layer_of(target) > layer_of(name):
                upward.append(f"{name} -> {target}")
    assert not upward, "imports pointing up the layers:\n" + "\n".join(upward)


@pytest.mark.parametrize("layer", sorted(FORBIDDEN))
def test_lower_layers_do_not_import_user_interface_libraries(layer):
    known = modules()
    bad = []
    for name, path in known.items():
        if layer_of(name) < len(lab.LAYERS) and lab.LAYERS[layer_of(name)] == layer:
            for target, line in imports_of(name, path):
                if target.split(".")[0] in FORBIDDEN[layer]:
                    bad.append(f"{name}:{line} imports {target}")
    assert not bad, "\n".join(bad)


def test_no_import_cycles():
    known = modules()
    graph = {name: lab_imports(name, path, known) for name, path in known.items()}
    state, stack, cycles = {}, [], []

    def visit(node):
        state[node] = "active"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "active":
                cycles.append(" -> ".join(stack[stack.index(nxt):] + [nxt]))
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = "done"

    for node in sorted(graph):
        if node not in state:
            visit(node)
    assert not cycles, "import cycles:\n" + "\n".join(cycles)


def test_modules_are_small():
    long = {name: len(path.read_text().splitlines()) for name, path in modules().items()}
    assert {k: v for k, v in long.items() if v > MAX_LINES} == {}


def test_import_lab_loads_no_heavy_library():
    code = (
        "import sys, lab\n"
        "heavy = ('pyvista', 'vtk', 'ipywidgets', 'trame', 'scipy.integrate', 'scipy.optimize', 'sympy', 'scipy')\n"
        "print(sorted(m for m in heavy if m in sys.modules))\n"
        "lab.surfaces.practical().curvature(1.0, 1.0)\n"
        "print(sorted(m for m in heavy if m in sys.modules))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split("\n")
    assert out[0] == "[]"  # import lab alone: nothing at all
    assert out[1] == "[]"  # exact curvature of the practical's surface needs numpy only


def test_public_api_and_aliases_resolve():
    for short, target in lab.MODULES.items():
        assert getattr(lab, short).__name__ == target
    for name in lab.__all__:
        assert getattr(lab, name) is not None
    import lab.curvature as c  # the aliases work with import too
    from lab.colormaps import f2

    assert c is sys.modules["lab.geometry.curvature"]
    assert f2 is sys.modules["lab.geometry.colormaps"].f2
    with pytest.raises(AttributeError, match="has no attribute 'nonsense'"):
        lab.nonsense  # noqa: B018


# -- inside lab/teaching: rooms by role, the trust boundaries are folders ------------------------------------------

#: What a module of each room of ``lab/teaching`` may import of ``lab.teaching`` (besides its own room).  The rooms
#: are the sub-packages and the modules at the root (``lab.teaching.task`` is "task").
TEACHING_RULES = {
    "kernel": set(),  # runs beside the student's code: the only teaching code the sandbox keeps
    "report": set(),
    "untrusted": set(),
    "task": {"report", "kernel"},  # the task model (results come back in the kernel protocol's plain numbers)
    "tasks": {"task", "report", "kernel"},  # cases, answers, hints, mutants
    "sandbox": {"kernel", "tasks"},  # the withheld names of the tasks; never the self-check
    "self_check": {"kernel", "task", "report", "untrusted"},
    "check": {"self_check", "task", "report", "tasks"},
    "grader": {"kernel", "task", "report", "tasks", "sandbox", "untrusted"},
    "course": {"kernel", "task", "report", "tasks", "sandbox", "untrusted", "grader"},  # the verbs sit on top
}


def teaching_room(name):
    parts = name.split(".")
    return parts[2] if len(parts) > 2 and parts[:2] == ["lab", "teaching"] else None


def test_teaching_is_folders_by_role():
    """Every module of lab/teaching is in a room of :data:`TEACHING_RULES`, and the package's docstring maps them."""
    teaching = ROOT / "teaching"
    rooms = {p.stem for p in teaching.iterdir() if p.suffix == ".py" and p.stem != "__init__"} | {
        p.name for p in teaching.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    assert rooms == set(TEACHING_RULES)
    doc = ast.get_docstring(ast.parse((teaching / "__init__.py").read_text()))
    for room in TEACHING_RULES:
        assert f"``{room}" in doc, f"lab/teaching/__init__.py does not map {room}"


def test_imports_inside_teaching_follow_the_rooms():
    known = modules()
    bad = []
    for name, path in known.items():
        room = teaching_room(name)
        if room is None:
            continue
        for target in lab_imports(name, path, known):
            other = teaching_room(target)
            if other is not None and other != room and other not in TEACHING_RULES[room]:
                bad.append(f"{name} ({room}) -> {target} ({other})")
    assert not bad, "imports across the rooms of lab/teaching that the rules do not allow:\n" + "\n".join(bad)


def test_only_tasks_holds_cases_answers_and_hints():
    """Outside ``tasks/`` a module may import the registry (``lab.teaching.tasks``: the task names, ``TASKS``) but no
    module inside it: whatever imports the cases, answers, hints or mutants must itself be withheld, and only
    ``tasks/`` is (the hand-out ships everything else as source)."""
    known = modules()
    bad = []
    for name, path in known.items():
        if teaching_room(name) == "tasks":
            continue
        for target in lab_imports(name, path, known):
            if target.startswith("lab.teaching.tasks."):
                bad.append(f"{name} -> {target}")
    assert not bad, "modules outside lab/teaching/tasks that import its answers:\n" + "\n".join(bad)


def test_the_trust_boundaries_are_the_folders(tmp_path):
    """The sandbox's copy of the library keeps of lab/teaching exactly ``kernel/`` (and a stub of ``check``); the
    hand-out's copy ships every module of ``tasks/`` as a stub whose code is compiled only, whatever its name."""
    from lab.teaching.sandbox import withhold

    package = withhold.prepare_package([], ["warmup"], tmp_path / "sandbox")
    kept = sorted(str(p.relative_to(package / "teaching")) for p in (package / "teaching").rglob("*.py"))
    assert kept == ["__init__.py", "check.py"] + sorted(
        f"kernel/{p.name}" for p in (ROOT / "teaching" / "kernel").glob("*.py"))
    assert "checked by the grader" in (package / "teaching" / "check.py").read_text()
    original, copy = tmp_path / "course" / "lab", tmp_path / "handout" / "lab"
    shutil.copytree(ROOT, original, ignore=shutil.ignore_patterns("__pycache__"))
    (original / "teaching" / "tasks" / "new_notebook.py").write_text("ANSWER = 42\n")  # a module no list names
    shutil.copytree(original, copy)
    pairs = withhold.hand_out(copy, original)
    stubs = {file.relative_to(copy) for _source, file in pairs}
    tasks = {p.relative_to(copy) for p in (copy / "teaching" / "tasks").glob("*.py")}
    assert tasks <= stubs and Path("teaching/tasks/new_notebook.py") in tasks
    for path in tasks:
        text = (copy / path).read_text()
        assert "withheld in this hand-out" in text and "ANSWER = 42" not in text and "\ndef " not in text, path
