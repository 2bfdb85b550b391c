"""What the student's code may not see: one place for the grading sandbox's copy of the library and for the
hand-out's.

**The withheld set**, computed once (:func:`withheld`): every function a graded task blocks (its reference
implementation and the helpers that compute its answer, ``Task.blocked``) and the sympy-exact references
(:data:`lab.teaching.tasks.ANALYTIC_BLOCK`).  The grader withholds the set of an assignment's tasks, the hand-out the
set of all tasks, and the tests prove each of them raises.

**The trust boundary is a folder**, not a list of names:

* the sandbox keeps of ``lab/teaching/`` the folder ``kernel/`` (:data:`SANDBOX_KEEPS`: what runs beside the student's
  code, which holds no case, answer or hint) and a stub of ``check`` whose functions say the grader checks;
* the hand-out withholds ``tasks/`` whole (:data:`HAND_OUT_WITHHOLDS`: the cases, exact answers, hints and mutants):
  each module's source is a stub that says so, its code ships compiled.

Bodies are withheld in two ways: in the sandbox they raise the withheld marker (and record the call, so that a case
that used one is "delegated", :func:`lab.teaching.kernel.protocol.stub_source`); in the hand-out they say that they
are withheld, keeping every other line where it was.
"""

import ast
import compileall
import re
import shutil
from pathlib import Path

from ... import library
from ..kernel.protocol import stub_source
from ..tasks import ANALYTIC_BLOCK, TASKS

__all__ = ["HAND_OUT_WITHHOLDS", "SANDBOX_KEEPS", "by_module_file", "functions_named", "hand_out", "prepare_package",
           "withheld"]

#: The folder of ``lab/teaching/`` the sandbox keeps (with the package's ``__init__``).
SANDBOX_KEEPS = "kernel"
#: The folder of ``lab/teaching/`` the hand-out withholds whole.
HAND_OUT_WITHHOLDS = "tasks"


def withheld(task_names=None):
    """The qualified names of the functions withheld for the tasks ``task_names`` (default: every task), sorted."""
    names = TASKS if task_names is None else task_names
    return sorted({q for name in names for q in TASKS[name].blocked} | set(ANALYTIC_BLOCK))


def functions_named(tree, names, where):
    """``(qualified name within the module, node)`` of the functions and methods ``names`` in the module ``tree``;
    raises ``ValueError`` naming ``where`` when one is not there."""
    wanted, found = set(names), []

    def visit(body, prefix):
        for node in body:
            if isinstance(node, ast.ClassDef):
                visit(node.body, f"{prefix}{node.name}.")
            elif isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and f"{prefix}{node.name}" in wanted:
                found.append((f"{prefix}{node.name}", node))

    visit(tree.body, "")
    missing = wanted - {q for q, _ in found}
    if missing:
        raise ValueError(f"cannot withhold {sorted(missing)}: not found in {where}")
    return found


def strip_module(path, module, names):
    """Replace the bodies of the functions/methods ``names`` (dotted within ``module``) by the withheld stub,
    keeping their signatures and docstrings."""
    tree = ast.parse(path.read_text(), str(path))
    for qual, node in functions_named(tree, names, path):
        doc = [node.body[0]] if ast.get_docstring(node) else []
        node.body = doc + ast.parse(stub_source(f"{module}.{qual}")).body
    path.write_text(ast.unparse(tree) + "\n")


def _stub_check(task_names):
    lines = ['"""Checks are run by the grader, outside the notebook: in a graded run they do nothing."""', "",
             "TASKS = {}", "", "", "def _skip(name):", "    def check(*args, **kwargs):",
             "        print(f'check.{name}: checked by the grader')", "", "    return check", ""]
    lines += [f"{name} = TASKS[{name!r}] = _skip({name!r})" for name in task_names]
    return "\n".join(lines) + "\n"


def prepare_package(blocked, task_names, target):
    """A copy of the ``lab`` package at ``target/lab`` with ``blocked`` functions withheld; returns its path.

    ``blocked`` holds qualified names (``lab.geometry.curvature.from_derivatives``,
    ``lab.model.patches.BezierPatches.visualize_curvature``).  Of ``lab/teaching`` only the modules that
    call the student's code remain (no cases, answers or hints), and ``check`` is a stub whose functions
    print that the grader checks.
    """
    dest = Path(target) / "lab"
    shutil.copytree(library(), dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    for f in (dest / "teaching").iterdir():
        if f.name not in (SANDBOX_KEEPS, "__init__.py"):
            shutil.rmtree(f) if f.is_dir() else f.unlink()
    (dest / "teaching" / "check.py").write_text(_stub_check(task_names))
    for (file, module), names in by_module_file(blocked, dest).items():
        strip_module(file, module, names)
    compileall.compile_dir(str(dest), quiet=1, workers=1)
    return dest


def by_module_file(qualnames, package):
    """``{(file, module): [names within the module]}`` for qualified names of functions in the ``lab`` copy ``package``."""
    by_module = {}
    for qual in qualnames:
        parts = qual.split(".")
        for cut in range(len(parts) - 1, 1, -1):
            file = Path(package).joinpath(*parts[1:cut]).with_suffix(".py")
            if file.is_file():
                by_module.setdefault((file, ".".join(parts[:cut])), []).append(".".join(parts[cut:]))
                break
        else:
            raise ValueError(f"cannot withhold {qual!r}: no such module in lab")
    return by_module


def _withheld_stub(name, indent):
    message = (f"{name} is withheld in this hand-out (a reference implementation of a graded task); this Python "
               "has no compiled copy of it: ask for a hand-out built for ")
    return f"{indent}raise RuntimeError({message!r} + __import__('sys').implementation.cache_tag)"


def _docstring(text):
    """A one-line docstring literal of ``text`` (raw where the original has backslashes, as it was meant)."""
    text = " ".join(text.split()).replace('"', "'")
    return ("r" if "\\" in text else "") + '"""' + text + '"""'


def _strip_bodies(path, module, names):
    """Replace the bodies of ``names`` in the file ``path`` by the withheld line, keeping every other line."""
    text = path.read_text()
    lines = text.split("\n")
    for qual, node in functions_named(ast.parse(text), names, path):
        # the body and the docstring's discussion (the pros and cons of a map are a written answer) go;
        # the docstring's first paragraph stays; the line numbers of everything else stay too
        start, end = node.body[0].lineno - 1, node.end_lineno
        indent = re.match(r"\s*", lines[start]).group()
        doc = (ast.get_docstring(node, clean=True) or "").split("\n\n")[0]
        stub = ([f"{indent}{_docstring(doc)}"] if doc else []) + [_withheld_stub(f"{module}.{qual}", indent)]
        lines[start:end] = stub + [""] * max(0, end - start - len(stub))
    path.write_text("\n".join(lines))


def _whole_stub(module, original):
    doc = ast.get_docstring(ast.parse(original)) or ""
    return (f'"""{doc}\n\nWithheld in this hand-out: it holds the cases, answers and hints of the checks."""\n\n'
            f"raise ImportError({module + ' is withheld in this hand-out; this Python has no compiled copy of it: ask for a hand-out built for it'!r})\n")




def hand_out(dest, original):
    """Withhold the answers in the hand-out's copy ``dest`` of the library (``original``: the library it was copied
    from): the bodies of :func:`withheld` stripped, every module of ``tasks/`` a stub.  Returns ``(original file,
    file in dest)`` of each changed module, whose original code the hand-out ships compiled."""
    dest, original = Path(dest), Path(original)
    whole = dest / "teaching" / HAND_OUT_WITHHOLDS
    pairs = []
    for (file, module), names in by_module_file(withheld(), dest).items():
        if whole in file.parents:
            continue
        _strip_bodies(file, module, names)
        pairs.append((original / file.relative_to(dest), file))
    for file in sorted(whole.rglob("*.py")):
        source = original / file.relative_to(dest)
        module = ".".join(("lab",) + file.relative_to(dest).with_suffix("").parts).removesuffix(".__init__")
        file.write_text(_whole_stub(module, source.read_text()))
        pairs.append((source, file))
    return pairs
