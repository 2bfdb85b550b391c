"""Marking written answers in JupyterLab: ``curvature-lab mark SUBS`` and ``lab.mark(SUBS)``.

``SUBS`` is a folder of collected submissions of one assignment (``curvature-lab collect``), with its
``written-<id>.csv``.  The command writes ``SUBS/marking-<id>.ipynb`` (one cell: ``lab.mark(...)``; a notebook
already there is kept, never overwritten) and prints its path: open it in JupyterLab, on the hub, as the instructor
or a teaching assistant.  The panel shows one question at a time across the whole class:

* the question, **the sample answer and the points it is worth** (from the solution notebook), always visible;
* each answer as the student wrote it (Markdown with math, escaped: a student's HTML is shown as text), with the
  pictures of the student's notebook before the question; equal answers grouped, one mark for all (and split again);
* points (0 … max in steps of ½; anything else is refused with the reason) and a comment; **Enter** in the points
  saves and goes to the next unmarked answer, **Tab** moves to the comment and the buttons (previous, next, next
  unmarked, split, names);
* a progress line and the distribution of the points given so far;
* names hidden behind pseudonyms until the marker shows them (blind marking, the default).

Every change is saved at once into ``written-<id>.csv`` (:func:`lab.teaching.course.marking.save`): a mark that
another marker changed since the panel read it is shown and kept, never overwritten.  Reopening resumes where the
marker stopped.  The data and its rules are in :mod:`lab.teaching.course.marking`; this module is the view.
"""

import argparse
import html
import sys
from pathlib import Path

import mistune

from ... import i18n
from ...i18n import _
from . import marking
from .files import read_roster

__all__ = ["MarkingPanel", "main", "mark"]

_MARKDOWN = mistune.create_markdown(escape=True, plugins=["math", "strikethrough", "table"])


def markdown(text):
    """HTML of a student's Markdown: raw HTML escaped, math left to MathJax (``\\(…\\)``, ``$$…$$``)."""
    return _MARKDOWN(str(text))


def _bars(counter, top):
    """A small text histogram of the points given (HTML)."""
    if not counter:
        return "<span style='color:#666'>" + html.escape(_("no points given yet")) + "</span>"
    most = max(counter.values())
    rows = []
    for value in sorted(counter):
        width = max(4, round(120 * counter[value] / most))
        label = i18n.decimal(f"{value:g}")
        rows.append(f"<div style='display:flex;align-items:center;gap:6px;line-height:1.3'>"
                    f"<span style='width:3em;text-align:right'>{html.escape(label)}</span>"
                    f"<span style='display:inline-block;height:0.8em;width:{width}px;background:#4a6fa5'></span>"
                    f"<span>{counter[value]}</span></div>")
    return "".join(rows)


class MarkingPanel:
    """The marking panel of one :class:`~lab.teaching.course.marking.Sheet`: ``panel.widget`` is what a notebook
    shows.  ``marker``: whose position is kept (default: the hub's user); ``blind``: pseudonyms until shown."""

    def __init__(self, sheet, *, marker=None, blind=True):
        import ipywidgets as w

        self.sheet, self.marker = sheet, marker or marking.the_marker()
        state = marking.read_state(sheet, self.marker)
        self.split = {q: set(keys) for q, keys in state.get("split", {}).items()}
        self.names = bool(state.get("names", not blind))
        cells = [q.cell for q in sheet.questions]
        self.question = state.get("question") if state.get("question") in cells else (cells[0] if cells else None)
        self.position = int(state.get("position", 0)) if isinstance(state.get("position", 0), int) else 0
        self.message = ""
        layout = w.Layout(width="100%")
        self.w_question = w.Dropdown(options=[(self._question_label(k, q), q.cell)
                                              for k, q in enumerate(sheet.questions, 1)], layout=layout)
        self.w_text = w.HTMLMath(layout=layout)
        self.w_sample = w.HTMLMath(layout=w.Layout(width="100%", border="1px solid #9ab", padding="0 8px"))
        self.w_progress = w.HTML()
        self.w_bars = w.HTML()
        self.w_who = w.HTML()
        self.w_answer = w.HTMLMath(layout=w.Layout(width="100%", border="1px solid #ccc", padding="0 8px",
                                                   min_height="4em"))
        self.w_figures = w.HBox(layout=w.Layout(flex_flow="row wrap"))
        self.w_message = w.HTML()
        self.w_points = w.Text(description=_("Points"), continuous_update=False, layout=w.Layout(width="16em"))
        self.w_comment = w.Textarea(description=_("Comment"), continuous_update=False,
                                    layout=w.Layout(width="100%", height="4em"))
        self.w_prev = w.Button(description=_("Previous"), icon="arrow-left")
        self.w_next = w.Button(description=_("Next"), icon="arrow-right")
        self.w_unmarked = w.Button(description=_("Next unmarked"), icon="forward")
        self.w_split = w.Button(description=_("Split group"), icon="scissors")
        self.w_names = w.ToggleButton(value=self.names, description=_("Show names"), icon="eye")
        self.w_points.add_class("lab-mark-points")
        self.w_comment.add_class("lab-mark-comment")
        self.w_who.add_class("lab-mark-who")
        self.w_question.observe(self._on_question, "value")
        self.w_points.observe(self._on_points, "value")
        self.w_comment.observe(self._on_comment, "value")
        self.w_prev.on_click(lambda _b: self._go(self.position - 1))
        self.w_next.on_click(lambda _b: self._go(self.position + 1))
        self.w_unmarked.on_click(lambda _b: self._next_unmarked())
        self.w_split.on_click(lambda _b: self._split())
        self.w_names.observe(self._on_names, "value")
        title = _("Written answers: {id}").format(id=sheet.assignment)
        who = _("marker: {name}").format(name=self.marker)
        keys = _("Enter in the points saves and goes to the next unmarked answer; Tab moves to the comment and "
                 "the buttons.")
        self.widget = w.VBox([
            w.HTML(f"<h3 style='margin:4px 0'>{html.escape(title)}</h3>"
                   f"<div style='color:#555'>{html.escape(who)} · "
                   f"{html.escape(keys)}</div>"),
            self.w_question, self.w_text,
            w.HTML("<b>" + html.escape(_("Sample answer")) + "</b>"), self.w_sample,
            w.HBox([self.w_progress, self.w_bars], layout=w.Layout(justify_content="space-between")),
            self.w_who, self.w_answer, self.w_figures, self.w_message,
            w.HBox([self.w_points, self.w_prev, self.w_next, self.w_unmarked, self.w_split, self.w_names],
                   layout=w.Layout(flex_flow="row wrap")),
            self.w_comment,
        ], layout=w.Layout(width="100%"))
        self.widget.add_class("lab-mark")
        self._loading = False
        if self.question is not None:
            self._loading = True
            self.w_question.value = self.question
            self._loading = False
        self._show()

    # -- what is shown ------------------------------------------------------------------------------------------
    def _question_label(self, k, q):
        top = self.sheet.max_points.get(q.cell, q.points)
        return i18n.decimal(_("Question {k}: {title} ({points:g} points)").format(k=k, title=q.title, points=top))

    def groups(self):
        if self.question is None:
            return []
        return marking.groups(self.sheet.answers[self.question], self.split.get(self.question, ()))

    def _name(self, student):
        return student if self.names else marking.pseudonym(self.sheet.assignment, student)

    def _ordered(self):
        """The groups in the marker's order: by the first member's name when names are shown, else by pseudonym
        (an order that has nothing to do with the names)."""
        return sorted(self.groups(), key=lambda g: self._name(g[0].student))

    def current(self):
        order = self._ordered()
        if not order:
            return []
        self.position = min(max(self.position, 0), len(order) - 1)
        return order[self.position]

    def _show(self):
        self._loading = True
        try:
            q = next((q for q in self.sheet.questions if q.cell == self.question), None)
            if q is None:
                self.w_text.value = html.escape(_("This sheet has no questions."))
                return
            top = self.sheet.max_points.get(q.cell, q.points)
            self.w_text.value = markdown(q.text)
            sample = self.sheet.samples.get(q.cell)
            worth = i18n.decimal(_("{points} points").format(points=f"{top:g}"))
            self.w_sample.value = (markdown(sample) + f"<p><i>{html.escape(worth)}</i></p>" if sample
                                   else html.escape(_("(no sample answer: the solution notebook is not at hand)")))
            marked, total = self.sheet.progress(q.cell)
            every, all_total = self.sheet.progress()
            self.w_progress.value = html.escape(_("this question: {marked} of {total} marked · all questions: {every} "
                                                  "of {all} marked").format(marked=marked, total=total, every=every,
                                                                           all=all_total))
            self.w_bars.value = _bars(self.sheet.distribution(q.cell), top)
            group = self.current()
            order = self._ordered()
            if not group:
                self.w_who.value, self.w_answer.value = "", ""
                return
            first = group[0]
            who = ", ".join(self._name(a.student) for a in group[:8]) + (" …" if len(group) > 8 else "")
            where = _("answer {k} of {n}").format(k=self.position + 1, n=len(order))
            same = (" · " + _("the same answer from {n} students: one mark for all").format(n=len(group))
                    if len(group) > 1 else "")
            self.w_answer.value = (markdown(first.text) if first.text.strip()
                                   else "<i>" + html.escape(_("(no answer)")) + "</i>")
            self._figures(first.student, q.cell)
            self.w_points.value = first.points.replace(".", ",") if i18n.language() == "de" else first.points
            self.w_points.placeholder = i18n.decimal(f"0 … {top:g}")
            self.w_comment.value = first.comment
            self.w_split.disabled = len(group) < 2
            self.w_message.value = self.message
            # the name last: the browser applies the updates in order, so a marker (or a test) who sees the next name
            # finds its points box already emptied and cannot type into it before the empty value arrives
            self.w_who.value = f"<b>{html.escape(who)}</b> <span style='color:#555'>({html.escape(where + same)})</span>"
        finally:
            self._loading = False

    def _figures(self, student, question):
        import ipywidgets as w

        pictures = marking.figures(self.sheet.notebooks.get(student), question)
        self.w_figures.children = [w.Image(value=png, format="png", layout=w.Layout(max_width="32%", margin="2px"))
                                   for png in pictures]

    # -- what the marker does -----------------------------------------------------------------------------------
    def _keep(self):
        marking.write_state(self.sheet, self.marker, {
            "question": self.question, "position": self.position, "names": self.names,
            "split": {q: sorted(k) for q, k in self.split.items() if k}})

    def _go(self, position):
        self.message = ""
        self.position = position
        self.current()
        self._keep()
        self._show()

    def _next_unmarked(self):
        order = self._ordered()
        n = len(order)
        for step in range(1, n + 1):
            k = (self.position + step) % n
            if not order[k][0].points.strip():
                self._go(k)
                return True
        self.message = "<span style='color:#2a7'>" + html.escape(_("every answer of this question is marked")) + "</span>"
        self._show()
        return False

    def _on_question(self, change):
        if self._loading:
            return
        self.question, self.position, self.message = change["new"], 0, ""
        self._keep()
        self._show()

    def _on_names(self, change):
        first = self.current()[0].student if self.current() else None
        self.names = bool(change["new"])
        order = self._ordered()
        self.position = next((k for k, g in enumerate(order) if g[0].student == first), 0)
        self._keep()
        self._show()

    def _split(self):
        group = self.current()
        if len(group) > 1:
            self.split.setdefault(self.question, set()).add(marking._key(group[0].text))
            self._keep()
            self.position = next(k for k, g in enumerate(self._ordered()) if g[0].student == group[0].student)
            self._show()

    def _save(self, points_text, comment):
        group = self.current()
        if not group:
            return False
        top = self.sheet.max_points.get(self.question, 0.0)
        try:
            points = marking.check_points(points_text, top)
        except ValueError as exc:
            self.message = "<span style='color:#b00'>" + html.escape(str(exc)) + "</span>"
            self.w_message.value = self.message
            return False
        conflicts = marking.save(self.sheet, [a.student for a in group], self.question, points, comment)
        if conflicts:
            names = ", ".join(self._name(s) for s in conflicts)
            now = [self.sheet.marks.get((s, self.question), ("", "")) for s in conflicts]
            shown = "; ".join(f"{self._name(s)}: {p or '—'}" + (f" ({c})" if c else "") for s, (p, c) in zip(conflicts, now))
            self.message = ("<span style='color:#b00'>" + html.escape(
                _("changed by another marker since you read it, and kept: {names}. Now: {marks}").format(
                    names=names, marks=shown)) + "</span>")
            self._show()
            return False
        self.message = ""
        return True

    def _on_points(self, change):
        if self._loading:
            return
        if self._save(change["new"], self.w_comment.value) and str(change["new"]).strip():
            self._next_unmarked() or self._show()
        else:
            self._show()

    def _on_comment(self, change):
        if self._loading:
            return
        self._save(self.w_points.value, change["new"])
        self._show()

    def _ipython_display_(self):
        from IPython.display import display

        display(self.widget)


def mark(folder, assignment=None, *, marker=None, blind=True, lang=None, exercises=None, solutions=None,
         students=None):
    """The marking panel of a folder of collected submissions (``SUBS`` of ``curvature-lab collect``): one written
    question at a time across the class, sample answer and points in view, every mark saved at once into
    ``written-<id>.csv``.

    Parameters
    ----------
    folder : str or Path
        The folder ``collect`` wrote (``SUBS/<student>/<id>.ipynb`` and ``written-<id>.csv``).
    assignment : str, optional
        The assignment id, when the folder holds sheets of several.
    marker : str, optional
        Whose place is kept (default: the hub's user, else the login name).
    blind : bool
        Show pseudonyms instead of names until "Show names" (default True).
    lang : {"en", "de"}, optional
        The language of the questions and sample answers (default: the lab's).
    exercises, solutions : str or Path, optional
        The course's ``exercises/`` and ``solutions/`` (default: the repository's).
    students : list of str, or str or Path, optional
        Only these students' answers: a marker's share of the class (a list of user names, or a roster file as
        ``collect --students`` reads it); default: all.

    Returns
    -------
    MarkingPanel
        Shown when it is the last value of a cell; ``.widget`` is the ipywidgets box.
    """
    if isinstance(students, (str, Path)):
        students = read_roster(students, marking.MarkingError)
    sheet = marking.load(folder, assignment, lang=lang, exercises=exercises, solutions=solutions, students=students)
    return MarkingPanel(sheet, marker=marker, blind=blind)


def _notebook(folder, assignment, lang, students=None):
    import nbformat

    share = f", students={str(Path(students).resolve())!r}" if students else ""
    code = (f"import lab\nlab.set_language({lang!r})\n"
            f"lab.mark({str(Path(folder).resolve())!r}, {assignment!r}{share})")
    from .exercises import kernel_metadata  # what JupyterLab writes on opening: the notebook opens unmodified

    nb = nbformat.v4.new_notebook(metadata={**kernel_metadata(),
                                            "lab": {"role": "marking", "assignment": assignment, "lang": lang}})
    nb.cells = [nbformat.v4.new_markdown_cell(_("# Marking: {id}\n\nRun the cell (Shift+Enter). Every mark is saved "
                                                "at once into written-{id}.csv.").format(id=assignment)),
                nbformat.v4.new_code_cell(code)]
    return nb


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab mark",
        description=_("Mark the written answers of a collected assignment in JupyterLab: writes SUBS/marking-ID.ipynb "
                      "(an existing one is kept) and prints its path. Open it in JupyterLab and run its cell."))
    parser.add_argument("folder", metavar="SUBS", help=_("a folder written by curvature-lab collect"))
    parser.add_argument("--assignment", help=_("the assignment, when SUBS has sheets of several"))
    parser.add_argument("--students", metavar="ROSTER",
                        help=_("only these students (one user name per line, or a CSV with 'username'): a marker's "
                               "share; the notebook is then marking-ID-ROSTER.ipynb"))
    args = parser.parse_args(argv)
    try:
        students = read_roster(args.students, marking.MarkingError) if args.students else None
        sheet = marking.load(args.folder, args.assignment, students=students)
    except (marking.MarkingError, ValueError, OSError) as exc:
        print(f"curvature-lab mark: error: {exc}", file=sys.stderr)
        return 2
    import nbformat

    share = f"-{Path(args.students).stem}" if args.students else ""
    path = Path(args.folder) / f"marking-{sheet.assignment}{share}.ipynb"
    if path.exists():
        print(_("{path} is there already (kept): open it in JupyterLab").format(path=path))
        return 0
    nbformat.write(_notebook(args.folder, sheet.assignment, i18n.language(), args.students), str(path))
    marked, total = sheet.progress()
    print(_("{path}: open it in JupyterLab and run its cell ({marked} of {total} answers marked)").format(
        path=path, marked=marked, total=total))
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

