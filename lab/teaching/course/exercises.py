"""Exercise and solution notebooks in English and German, generated from one bilingual source each.

The source: ``solutions/NN_topic.ipynb``
----------------------------------------

One notebook holds both languages, so that an author sees them side by side:

* **Markdown cells** carry their language in ``cell.metadata["lang"]`` (``"en"`` or ``"de"``).  Every
  English cell is followed directly by its German twin, whose id is the English id plus ``-de``
  (``"1ad29206"`` → ``"1ad29206-de"``).  Both must be non-empty and different from each other, and a
  solution part (``<!-- BEGIN SOLUTION -->`` … ``<!-- END SOLUTION -->``) in one must be in the other.
* **Code cells** are shared.  What a German reader should read in German – comments, the task
  description after ``### BEGIN SOLUTION:`` (it becomes the exercise's ``NotImplementedError``
  message), picture titles and printed labels – is translated by a visible replacement table in the
  cell's metadata, applied in order to the cell's source for the German notebook::

      "metadata": {"de": {"# calculate curvatures at each corner point":
                          "# Krümmungen an jedem Eckpunkt berechnen", ...}}

  Every English text of the table must occur in the source (an edited comment makes its stale
  translation fail, see :func:`problems`); the replacements may change comments and string literals
  only, never code (checked token by token); and no English comment may be left untranslated (a
  language-neutral comment is listed with itself as its translation).
* **The notebook's metadata** ``lab`` holds the assignment id, the task list and the English ``title``;
  ``title_de`` is the German title.

What ``make exercises`` generates (:func:`generate`)
---------------------------------------------------

For each language ``L`` in ``en``, ``de``: ``solutions/L/NN_topic.ipynb`` (:func:`localize`: the
markdown cells of ``L`` with the English cell ids, the code translated for German, ``metadata.lab.lang
= L``; a German notebook calls ``lab.set_language("de")`` right after ``import lab`` in its first code
cell, so checks, hints and explorer labels speak German) and ``exercises/L/NN_topic.ipynb``
(:func:`make_exercise`):

* the first code cell calls ``lab.exercise_mode()`` after ``import lab``: Run All reaches the end with no
  task written, each cell that needs an unfinished task saying so in one line (:mod:`lab.teaching.kernel.exercise_mode`);
* in code cells, the lines from ``### BEGIN SOLUTION`` to ``### END SOLUTION`` (inclusive) become
  ``raise NotImplementedError("…")`` at the same indentation; the text after ``### BEGIN SOLUTION:`` is
  the message, so it says what to implement;
* in markdown cells, the text from ``<!-- BEGIN SOLUTION -->`` to ``<!-- END SOLUTION -->`` becomes
  ``*Your answer here.*`` (``*Ihre Antwort hier.*``).

The assignment id and the task list are the same in both languages.  Outputs and execution counts are
removed.  Each generated notebook records a digest of its cell sources in its metadata; regeneration
refuses to overwrite one whose sources no longer match that digest (a student changed an exercise, or
someone edited a generated solution instead of the source), and names the file, so nothing is lost.
"""

import argparse
import copy
import hashlib
import io
import json
import re
import string
import sys
import tokenize
from pathlib import Path

import nbformat

from ... import repository
from .files import NotACourseRepository, course_repository

__all__ = [
    "LANGUAGES",
    "SourceError",
    "StudentChangesError",
    "digest",
    "generate",
    "localize",
    "main",
    "make_exercise",
    "problems",
    "strip_code",
    "strip_markdown",
    "translate_code",
]

#: The languages generated; the first is the language of the source's code and of its first markdown twin.
LANGUAGES = ("en", "de")
TWIN_SUFFIX = {"de": "-de"}

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
MD_BEGIN = "<!-- BEGIN SOLUTION -->"
MD_END = "<!-- END SOLUTION -->"
DEFAULT_MESSAGE = {"en": "replace this line with your solution", "de": "ersetzen Sie diese Zeile durch Ihre Lösung"}
ANSWER_PLACEHOLDER = {"en": "*Your answer here.*", "de": "*Ihre Antwort hier.*"}
SET_LANGUAGE = {"de": 'lab.set_language("de")  # Prüfungen, Hinweise und Beschriftungen auf Deutsch'}
#: The line an exercise's first code cell gets after ``import lab`` (and ``set_language``): Run All goes on
#: past unfinished tasks (:mod:`lab.teaching.kernel.exercise_mode`).
EXERCISE_MODE = {"en": "lab.exercise_mode()  # a cell that needs an unfinished task says so, and Run All goes on",
                 "de": "lab.exercise_mode()  # eine Zelle, die eine unfertige Aufgabe braucht, sagt es, und "
                       "„Alle ausführen“ läuft weiter"}

_ROOT = Path(repository())


class StudentChangesError(RuntimeError):
    """A generated notebook was edited after it was generated."""


class SourceError(ValueError):
    """A bilingual source notebook is incomplete (a missing twin, a stale translation, …)."""


def _lang(lang):
    if lang not in LANGUAGES:
        raise ValueError(f"language must be one of {', '.join(LANGUAGES)}; got {lang!r}")
    return lang


def strip_code(source, lang="en"):
    """Replace every solution block of a code cell by a ``NotImplementedError`` stub."""
    out, inside = [], False
    for line in source.split("\n"):
        stripped = line.strip()
        if stripped.startswith(BEGIN):
            if inside:
                raise ValueError(f"nested {BEGIN!r} in:\n{source}")
            inside = True
            indent = line[: len(line) - len(line.lstrip())]
            message = stripped[len(BEGIN):].lstrip(" :").strip() or DEFAULT_MESSAGE[_lang(lang)]
            out.append(f"{indent}raise NotImplementedError({message!r})")
        elif stripped.startswith(END):
            if not inside:
                raise ValueError(f"{END!r} without {BEGIN!r} in:\n{source}")
            inside = False
        elif not inside:
            out.append(line)
    if inside:
        raise ValueError(f"{BEGIN!r} without {END!r} in:\n{source}")
    return "\n".join(out)


def strip_markdown(source, lang="en"):
    """Replace the solution parts of a markdown cell by a placeholder."""
    pattern = re.compile(re.escape(MD_BEGIN) + r".*?" + re.escape(MD_END), re.DOTALL)
    return pattern.sub(lambda _: ANSWER_PLACEHOLDER[_lang(lang)], source)


def translate_code(source, table):
    """``source`` with the replacements of ``table`` (English → German, applied in order).

    Raises
    ------
    SourceError
        If an English text of the table does not occur in the source (a stale translation).
    """
    for en, de in table.items():
        if en not in source:
            raise SourceError(f"the translation of {en!r} is stale: the text is not in the cell any more")
        source = source.replace(en, de)
    return source


def _after_import(source, line):
    """``source`` with ``line`` after its line ``import lab`` (and after the lines that follow it directly and
    call ``lab.``, as ``set_language``)."""
    lines = source.split("\n")
    if "import lab" not in lines:
        raise SourceError(f"the first code cell must contain the line 'import lab' ({line.split('(')[0]} follows it)")
    i = lines.index("import lab") + 1
    while i < len(lines) and lines[i].startswith("lab."):
        i += 1
    return "\n".join(lines[:i] + [line] + lines[i:])


def _set_language(source, lang):
    """The first code cell of a notebook in ``lang``: ``lab.set_language(...)`` right after ``import lab``."""
    return _after_import(source, SET_LANGUAGE[lang]) if lang in SET_LANGUAGE else source


#: The kernel JupyterLab starts for a generated notebook, as it writes it into the notebook's metadata on opening:
#: ipykernel's own spec.  A notebook whose metadata differ is marked modified as soon as it is opened (issue 36).
KERNELSPEC = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}


def kernel_metadata():
    """``kernelspec`` and ``language_info`` as JupyterLab writes them on opening a notebook with this Python's
    ipykernel (its ``language_info`` names the Python version, so only a kernel of the same version finds them
    unchanged)."""
    from ipykernel.ipkernel import IPythonKernel

    return {"kernelspec": dict(KERNELSPEC), "language_info": copy.deepcopy(IPythonKernel.language_info)}


def localize(source, lang):
    """The solution notebook in ``lang`` for a bilingual source notebook (a new object; the input is unchanged)."""
    _lang(lang)
    nb = copy.deepcopy(source)
    cells, first_code = [], True
    for cell in nb.cells:
        cell.metadata.pop("execution", None)
        if cell.cell_type == "markdown":
            if cell.metadata.pop("lang", LANGUAGES[0]) != lang:
                continue
            suffix = TWIN_SUFFIX.get(lang)
            if suffix and cell.get("id", "").endswith(suffix):
                cell.id = cell.id[: -len(suffix)]
        elif cell.cell_type == "code":
            table = cell.metadata.pop("de", None)
            if lang == "de" and table:
                cell.source = translate_code(cell.source, table)
            if first_code:
                cell.source, first_code = _set_language(cell.source, lang), False
        cells.append(cell)
    nb.cells = cells
    nb.metadata.update(kernel_metadata())
    meta = nb.metadata.setdefault("lab", {})
    title_de = meta.pop("title_de", None)
    if lang == "de" and title_de:
        meta["title"] = title_de
    meta["lang"] = lang
    meta["role"] = "solution"
    return nb


def _content(nb):
    """What a generated notebook consists of, outputs and execution counts aside."""
    cells = [(c.cell_type, c.get("id"), c.source, dict(c.metadata)) for c in nb.cells]
    # the Python version in language_info is the generating machine's: another version is no reason to rewrite
    meta = {k: v for k, v in nb.metadata.items() if k != "language_info"}
    return json.dumps([cells, meta], ensure_ascii=False, sort_keys=True, default=str)


def digest(nb):
    """SHA-256 of the cell types and sources: what a student edits."""
    cells = [(c.cell_type, c.source) for c in nb.cells]
    return hashlib.sha256(json.dumps(cells, ensure_ascii=False).encode()).hexdigest()


def _stamp(nb):
    nb.metadata.setdefault("lab", {})["generated_digest"] = digest(nb)
    return nb


def make_exercise(solution):
    """The exercise notebook for a solution notebook (a new object; the input is unchanged).

    The placeholders are in the solution's language (``metadata.lab.lang``, default English).
    """
    nb = copy.deepcopy(solution)
    lang = nb.metadata.get("lab", {}).get("lang", LANGUAGES[0])
    first_code = True
    for cell in nb.cells:
        if cell.cell_type == "code":
            cell.source = strip_code(cell.source, lang)
            if first_code:
                cell.source, first_code = _after_import(cell.source, EXERCISE_MODE[_lang(lang)]), False
            cell.outputs = []
            cell.execution_count = None
        elif cell.cell_type == "markdown":
            cell.source = strip_markdown(cell.source, lang)
        cell.metadata.pop("execution", None)
    meta = nb.metadata.setdefault("lab", {})
    meta["role"] = "exercise"
    meta["generated_digest"] = digest(nb)
    return nb


# --- checking a bilingual source ------------------------------------------------------------------------

def _tokens(source):
    """Tokens of Python code; comments and blank lines dropped, string literals reduced to what is code in them."""
    out = []
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type in (tokenize.COMMENT, tokenize.NL):
            continue
        if tok.type == tokenize.STRING:
            prefix = re.match(r"[A-Za-z]*", tok.string).group().lower()
            fields = []
            if "f" in prefix:  # the replacement fields of an f-string are code
                body = tok.string[len(prefix):].strip("'\"")
                try:
                    fields = [tuple(f) for _, *f in string.Formatter().parse(body) if f[0] is not None]
                except ValueError:  # not a format string that str.format reads: compare the braces as text
                    fields = re.findall(r"\{[^{}]*\}", body)
            out.append(("STRING", prefix, tuple(fields)))
        else:
            out.append((tokenize.tok_name[tok.type], tok.string))
    return out


def _comments(source):
    return [tok.string.strip() for tok in tokenize.generate_tokens(io.StringIO(source).readline)
            if tok.type == tokenize.COMMENT and tok.string.strip() != END]


def problems(nb, name="notebook"):
    """What is missing or stale in a bilingual source notebook: a list of messages (empty when complete)."""
    found = []
    cells = nb.cells
    if not nb.metadata.get("lab", {}).get("title_de"):
        found.append(f"{name}: no German title (metadata lab.title_de)")
    i = 0
    while i < len(cells):
        cell = cells[i]
        where = f"{name}, cell {i} ({cell.get('id')})"
        if cell.cell_type == "markdown":
            lang = cell.metadata.get("lang")
            if lang != "en":
                found.append(f"{where}: a markdown cell with lang {lang!r} where an English cell (lang 'en') "
                             "followed by its German twin was expected")
                i += 1
                continue
            twin = cells[i + 1] if i + 1 < len(cells) else None
            if twin is None or twin.cell_type != "markdown" or twin.metadata.get("lang") != "de":
                found.append(f"{where}: the English markdown cell has no German twin (a markdown cell with "
                             "lang 'de') right after it")
                i += 1
                continue
            en, de = cell.source.strip(), twin.source.strip()
            if not en or not de:
                found.append(f"{where}: the {'English' if not en else 'German'} text of the pair is empty")
            elif en == de:
                found.append(f"{where}: the German twin is identical to the English cell")
            if twin.get("id") != f"{cell.get('id')}{TWIN_SUFFIX['de']}":
                found.append(f"{where}: the German twin's id should be {cell.get('id')}{TWIN_SUFFIX['de']}; "
                             f"it is {twin.get('id')}")
            for marker in (MD_BEGIN, MD_END):
                if en.count(marker) != de.count(marker):
                    found.append(f"{where}: {marker} appears {en.count(marker)} times in English, "
                                 f"{de.count(marker)} times in German")
            i += 2
            continue
        if cell.cell_type == "code":
            found += _code_problems(cell, where)
        i += 1
    return found


def _code_problems(cell, where):
    table = cell.metadata.get("de") or {}
    if not isinstance(table, dict):
        return [f"{where}: metadata 'de' must map English texts to German ones"]
    try:
        german = translate_code(cell.source, table)
    except SourceError as exc:
        return [f"{where}: {exc}"]
    try:
        same_code = _tokens(german) == _tokens(cell.source)
        kept = set(_comments(german)) & set(_comments(cell.source))
    except (tokenize.TokenError, SyntaxError, IndentationError) as exc:
        return [f"{where}: cannot read the code ({exc})"]
    found = []
    if not same_code:
        found.append(f"{where}: the German replacements change code, not only comments and strings")
    neutral = [en for en, de in table.items() if en == de]
    untranslated = sorted(c for c in kept if not any(n in c for n in neutral))
    if untranslated:
        found.append(f"{where}: comments without a German translation (metadata 'de'): {untranslated}")
    return found


# --- generation ---------------------------------------------------------------------------------------

def _read(path):
    return nbformat.read(str(path), as_version=4)


def _write(nb, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    nbformat.write(nb, str(path))


def generate(sources=_ROOT / "solutions", exercises=_ROOT / "exercises", solutions=None, *,
             languages=LANGUAGES, check_only=False):
    """Generate ``exercises/<lang>/NN_*.ipynb`` and ``solutions/<lang>/NN_*.ipynb`` from ``solutions/NN_*.ipynb``.

    Parameters
    ----------
    sources : path
        The folder of bilingual source notebooks.
    exercises, solutions : path
        Where the exercises and the solutions go, one sub-folder per language (``solutions`` defaults
        to ``sources``).
    languages : sequence of str
        The languages to generate.
    check_only : bool
        Write nothing; report which notebooks differ from freshly generated ones.

    Returns
    -------
    dict of generated path -> "unchanged" | "written" | "differs"

    Raises
    ------
    SourceError
        If a source notebook is incomplete (:func:`problems`); nothing is written.
    StudentChangesError
        If an existing generated notebook was edited since it was generated; nothing is written in that
        case, and the message names the files.
    """
    sources, exercises = Path(sources), Path(exercises)
    solutions = sources if solutions is None else Path(solutions)
    if not any(sources.glob("[0-9][0-9]_*.ipynb")):  # nothing to generate is no success
        raise SourceError(f"no bilingual source notebooks (NN_*.ipynb) in {sources}")
    plan, edited, incomplete = {}, [], []
    for src in sorted(sources.glob("[0-9][0-9]_*.ipynb")):
        source = _read(src)
        incomplete += problems(source, str(src))
        if incomplete:
            continue
        for lang in languages:
            solution = _stamp(localize(source, lang))
            for target, new in ((solutions / lang / src.name, solution), (exercises / lang / src.name, make_exercise(solution))):
                if target.exists():
                    old = _read(target)
                    if old.metadata.get("lab", {}).get("generated_digest") != digest(old):
                        edited.append(target)
                        continue
                    if _content(old) == _content(new):
                        plan[target] = ("unchanged", new)
                        continue
                plan[target] = ("differs" if check_only else "written", new)
    if incomplete:
        raise SourceError("the bilingual source notebooks are incomplete:\n  " + "\n  ".join(incomplete))
    if edited:
        names = ", ".join(str(p) for p in edited)
        raise StudentChangesError(
            f"refusing to overwrite notebooks edited since they were generated: {names}. "
            "Move them away (or rename them) to keep the work, then generate again "
            "(a solution is changed in its bilingual source, solutions/NN_*.ipynb)."
        )
    if not check_only:
        for target, (action, nb) in plan.items():
            if action == "written":
                _write(nb, target)
    return {target: action for target, (action, _) in plan.items()}


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab exercises",
        description="Generate exercises/en, exercises/de, solutions/en and solutions/de from the bilingual "
                    "source notebooks solutions/NN_*.ipynb.")
    parser.add_argument("--solutions", default=str(_ROOT / "solutions"),
                        help="the folder of bilingual sources; solutions/<lang>/ are written into it")
    parser.add_argument("--exercises", default=str(_ROOT / "exercises"), help="exercises/<lang>/ are written into it")
    parser.add_argument("--lang", choices=LANGUAGES, action="append", help="only this language (repeatable)")
    parser.add_argument("--check", action="store_true", help="only report notebooks that differ; exit 1 if any")
    args = parser.parse_args(argv)
    try:
        if args.solutions == str(_ROOT / "solutions"):  # the default: the course repository's
            course_repository("exercises")
        result = generate(args.solutions, args.exercises, languages=tuple(args.lang or LANGUAGES),
                          check_only=args.check)
    except (StudentChangesError, SourceError, NotACourseRepository) as exc:
        print(f"curvature-lab exercises: error: {exc}", file=sys.stderr)
        return 2 if isinstance(exc, NotACourseRepository) else 1
    for path, action in result.items():
        print(f"{action:9s} {path}")
    return 1 if args.check and any(a == "differs" for a in result.values()) else 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
