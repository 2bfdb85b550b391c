"""Exercise mode: Run All reaches the end of an exercise whose tasks are not written yet.

An exercise's first cell calls ``lab.exercise_mode()`` (``make exercises`` puts it there).  From then on,
in an IPython kernel, every cell is compiled with one guard around it (an AST transformer):

* a cell **stopped by an unfinished task** – a ``NotImplementedError`` raised by code written in the
  notebook (the stub of a task, also when the library calls it), or, in the graded run, a library function
  whose reference implementation is withheld – prints one line in the notebook's language that names the
  function and its task text, instead of a traceback, and the cell counts as run, so Run All goes on;
* the names that cell assigns are marked unfinished; a later cell that needs one of them (it uses the name
  at its top level before assigning it) is not run and says so in one line; the names it would have
  assigned are marked as well;
* a cell that runs to its end clears the marks of the names it assigns (re-running a cell after finishing
  the task brings everything back).

Every other error is shown as usual, with its traceback.  A ``NotImplementedError`` raised inside the
library (an unsupported case, not a task) is such an error.  Outside IPython, ``exercise_mode`` does
nothing.
"""

import ast
import sys

from ... import library
from ...i18n import _
from .protocol import MARKER

__all__ = ["exercise_mode", "is_unfinished"]

_LAB_DIR = library()
_MODULE = __name__


class _State:
    """What the guard knows in this kernel: the unfinished names (name -> the reason) and a cell's result."""

    def __init__(self):
        self.unfinished = {}
        self.result = None


_state = _State()


def _library_file(filename):
    return filename.startswith((_LAB_DIR, sys.prefix, sys.base_prefix)) or "site-packages" in filename


def _last_frame(exc):
    tb = exc.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    return tb.tb_frame if tb is not None else None


def _withheld(exc):
    return type(exc) is RuntimeError and MARKER in str(exc)


def is_unfinished(exc):
    """Whether ``exc`` stopped a cell at an unfinished task: a NotImplementedError raised by code written in
    the notebook, or the error of a withheld reference implementation (graded run)."""
    if _withheld(exc):
        return True
    if not isinstance(exc, NotImplementedError):
        return False
    frame = _last_frame(exc)
    return frame is not None and not _library_file(frame.f_code.co_filename)


def _reason(exc):
    """One line on what is unfinished: the function whose stub raised and its task text."""
    if _withheld(exc):
        name = str(exc).split(MARKER, 1)[1].lstrip(": ") or "?"
        return _("the library's {name} is withheld in the graded run (no points depend on this cell)").format(
            name=name)
    frame = _last_frame(exc)
    qualname = getattr(frame.f_code, "co_qualname", frame.f_code.co_name) if frame is not None else "<module>"
    text = " ".join(str(exc).split())
    if qualname == "<module>":
        return _("a task of this cell is not written yet ({task})").format(task=text) if text else _(
            "a task of this cell is not written yet")
    if text:
        return _("{name} is not written yet ({task})").format(name=qualname, task=text)
    return _("{name} is not written yet").format(name=qualname)


class _Line:
    """The one line a guarded cell shows (plain text and HTML, styled like a check's "not implemented")."""

    def __init__(self, text):
        self.text = text

    def __repr__(self):
        return self.text

    def _repr_html_(self):
        import html

        return ('<div style="border-left:4px solid #9a6700;padding:0.2em 0.8em;white-space:pre-wrap;'
                'word-break:normal;overflow-wrap:break-word">'
                f"{html.escape(self.text)}</div>")


def _show(text):
    try:
        from IPython.display import display
    except ImportError:  # pragma: no cover - exercise mode runs in IPython only
        print(text)
        return
    display(_Line(text))


# -- what the guarded cell calls ------------------------------------------------------------------------


def stopped(exc, statements):
    """The cell stopped at an unfinished task: one line, and the names it did not finish are marked.

    ``statements``: per top-level statement of the cell, (first line, last line, names it assigns, names it
    may change in place).  Marked are the names assigned by the statement that stopped and the ones after it,
    and names the cell assigned before that the stopped statement may have changed in place and left half
    done (as ``patches.visualize_curvature(…)`` leaves ``patches`` without colours).
    """
    reason = _reason(exc)
    _state.result = None
    tb = exc.__traceback__
    line = tb.tb_lineno if tb is not None else 0
    k = next((i for i, (first, last, _s, _l) in enumerate(statements) if first <= line <= last), 0)
    names = {n for _f, _e, stored, _l in statements[k:] for n in stored}
    names |= {n for _f, _e, stored, _l in statements[:k] for n in stored} & set(statements[k][3]) if statements else set()
    for name in names:
        _state.unfinished[name] = reason
    _show("… " + _("Stopped here: {reason}. The next cells still run.").format(reason=reason))


def skipped(needed, names):
    """The cell was not run because it needs the unfinished names ``needed``; its ``names`` are marked too."""
    reason = _state.unfinished[needed[0]]
    for name in names:
        _state.unfinished[name] = reason
    _show("… " + _("Not run: this cell needs {names}, which an earlier cell could not finish: {reason}.").format(
        names=", ".join(needed), reason=reason))


def name_error(exc):
    """Whether the NameError ``exc`` is about a name marked unfinished (then it is shown as such)."""
    name = getattr(exc, "name", None)
    if name not in _state.unfinished:
        return False
    skipped([name], [])
    return True


def finished(names):
    """The cell ran to its end: the names it assigns are no longer unfinished."""
    for name in names:
        _state.unfinished.pop(name, None)


def keep(value):
    """The value of the cell's last expression (shown by IPython after the guard)."""
    _state.result = value


def result():
    """The kept value, once (the guard shows it as the cell's result)."""
    value, _state.result = _state.result, None
    return value


# -- the guard --------------------------------------------------------------------------------------------


class _Names(ast.NodeVisitor):
    """Names a cell assigns and names it uses at its top level (function and class bodies aside)."""

    def __init__(self):
        self.stored, self.loaded = {}, {}  # name -> when it is first stored / loaded (in the order of execution)
        self.receivers = set()  # names the code may change in place (``patches.refine(1)``, ``x.colors[…] = …``)
        self._clock = 0

    def _note(self, where, name, node):
        self._clock += 1
        where.setdefault(name, self._clock)

    def _changed(self, node):
        """``x.attr = …``, ``x[i] = …`` and ``x.method(…)`` as a statement may change ``x`` in place."""
        while isinstance(node, (ast.Attribute, ast.Subscript, ast.Call)):
            node = node.func if isinstance(node, ast.Call) else node.value
            if isinstance(node, ast.Name):
                self.receivers.add(node.id)

    def visit_Expr(self, node):
        if isinstance(node.value, ast.Call) and isinstance(node.value.func, ast.Attribute):
            self._changed(node.value.func)
        self.generic_visit(node)

    def visit_Name(self, node):
        self._note(self.stored if isinstance(node.ctx, (ast.Store, ast.Del)) else self.loaded, node.id, node)

    def _definition(self, node):
        for child in node.decorator_list + getattr(node, "bases", []) + [k.value for k in getattr(node, "keywords", [])]:
            self.visit(child)
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for default in node.args.defaults + [d for d in node.args.kw_defaults if d is not None]:
                self.visit(default)
        self._note(self.stored, node.name, node)

    visit_FunctionDef = visit_AsyncFunctionDef = visit_ClassDef = _definition

    def visit_Lambda(self, node):
        for default in node.args.defaults:
            self.visit(default)

    def _comprehension(self, node):
        """A comprehension has a scope of its own: its loop variables are neither assigned nor needed at the
        cell's top level (``[f.index for f in model.faces]`` needs ``model`` only); its first iterable is
        evaluated in the cell's scope."""
        self.visit(node.generators[0].iter)
        inner = _Names()
        for part in [g.target for g in node.generators] + [g.iter for g in node.generators[1:]]:
            inner.visit(part)
        for g in node.generators:
            for condition in g.ifs:
                inner.visit(condition)
        for part in ("elt", "key", "value"):
            if getattr(node, part, None) is not None:
                inner.visit(getattr(node, part))
        for name in sorted(set(inner.loaded) - set(inner.stored), key=inner.loaded.get):
            self._note(self.loaded, name, node)

    visit_ListComp = visit_SetComp = visit_DictComp = visit_GeneratorExp = _comprehension

    def visit_alias(self, node):
        name = node.asname or node.name.split(".")[0]
        if name != "*":
            self._note(self.stored, name, node)

    def visit_ExceptHandler(self, node):
        if node.type is not None:
            self.visit(node.type)
        for stmt in node.body:
            self.visit(stmt)

    def visit_AugAssign(self, node):  # x += 1 needs x
        if isinstance(node.target, ast.Name):
            self._note(self.loaded, node.target.id, node)
        self._changed(node.target)
        self.generic_visit(node)

    def visit_Assign(self, node):  # the value is computed before the targets are bound
        self.visit(node.value)
        for target in node.targets:
            self._changed(target)
            self.visit(target)


def _helper(name):
    """``__import__('lab.teaching.kernel.exercise_mode', fromlist=['_']).name`` as an expression."""
    module = ast.Call(ast.Name("__import__", ast.Load()), [ast.Constant(_MODULE)],
                      [ast.keyword("fromlist", ast.List([ast.Constant("_")], ast.Load()))])
    return ast.Attribute(module, name, ast.Load())


def _call(name, *args):
    return ast.Expr(ast.Call(_helper(name), list(args), []))


def _strings(names):
    return ast.List([ast.Constant(n) for n in names], ast.Load())


class Guard(ast.NodeTransformer):
    """The AST transformer of exercise mode (see the module docstring)."""

    def visit_Module(self, node):
        if not node.body:
            return node
        cell, statements = _Names(), []
        for stmt in node.body:
            cell.visit(stmt)
            one = _Names()
            one.visit(stmt)
            statements.append((stmt.lineno, stmt.end_lineno, tuple(sorted(one.stored)), tuple(sorted(one.receivers))))
        stored = sorted(cell.stored)
        needed = sorted(n for n, when in cell.loaded.items() if n in _state.unfinished
                        and not (n in cell.stored and cell.stored[n] < when))
        if needed:
            node.body = [_call("skipped", _strings(needed), _strings(stored))]
            return ast.fix_missing_locations(node)
        body = list(node.body)
        last_expr = isinstance(body[-1], ast.Expr)
        if last_expr:
            body[-1] = ast.copy_location(_call("keep", body[-1].value), body[-1])
        exc = ast.Name("_lab_unfinished_exc", ast.Load())
        reraise = ast.If(ast.UnaryOp(ast.Not(), ast.BoolOp(ast.And(), [
            ast.Call(ast.Name("isinstance", ast.Load()), [exc, ast.Name("NameError", ast.Load())], []),
            ast.Call(_helper("name_error"), [exc], [])])), [ast.Raise()], [])
        handler = ast.ExceptHandler(
            ast.Tuple([ast.Name(e, ast.Load()) for e in ("NotImplementedError", "RuntimeError", "NameError")],
                      ast.Load()), exc.id,
            [ast.If(ast.Call(_helper("is_unfinished"), [exc], []),
                    [_call("stopped", exc, ast.Constant(tuple(statements)))], [reraise])])
        guarded = ast.Try(body, [handler], [_call("finished", _strings(stored))], [])
        node.body = [guarded] + ([ast.Expr(ast.Call(_helper("result"), [], []))] if last_expr else [])
        return ast.fix_missing_locations(node)


def exercise_mode(on=True):
    """Let Run All reach the end of an exercise whose tasks are not written yet (see the module).

    Called in an exercise's first cell.  ``exercise_mode(False)`` switches it off.  Calling it again starts
    afresh (no name is marked unfinished).
    """
    if not isinstance(on, bool):
        raise TypeError(f"exercise_mode(on) takes True or False; got {on!r}")
    _state.unfinished.clear()
    try:
        from IPython import get_ipython
    except ImportError:  # pragma: no cover - IPython comes with the lab's Jupyter set-up
        return
    shell = get_ipython()
    if shell is None:
        return
    shell.ast_transformers[:] = [t for t in shell.ast_transformers if not isinstance(t, Guard)]
    if on:
        shell.ast_transformers.append(Guard())
