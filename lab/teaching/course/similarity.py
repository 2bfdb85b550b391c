"""Similarity of submissions: ``curvature-lab similarity SUBS -o similarity.html [--csv pairs.csv]``.

Which submissions of one assignment are copies of each other?  ``SUBS`` is a folder of submissions as ``collect``
writes it (``SUBS/<student>/<ID>.ipynb``; a flat ``SUBS/<student>.ipynb`` is read too).  Every pair of students is
compared in two parts, each on its own:

* **code**: the student's code cells that differ from every code cell of the hand-out (the exercise of the assignment
  in English and German, ``--exercises``), joined;
* **written**: the answers to the assignment's written questions (:mod:`lab.teaching.course.written`), joined.

Both are compared by token fingerprints (k-grams of normalised text, as MOSS does) with the library copydetect:
the code is tokenised by pygments and every name becomes ``V``, every string ``S``, comments and layout are dropped,
so renamed variables, reordered functions, changed comments and reformatting change nothing but the few k-grams at
the edges; written answers are compared in lower case with every run of spaces and punctuation one space.  What the
hand-out already holds (its code; the questions' text) and what the reference solution holds (``--solutions``,
default: the repository's ``solutions/`` when the lab runs from a checkout) is copydetect's *boilerplate*: its
k-grams count for nobody.  So that short pieces that are necessarily alike are not counted (``f1`` of notebook 04 is
one line, a value clipped to [0, 1], written one of two natural ways), a stretch of matching k-grams
counts only when it spans at least :data:`MIN_REGION` characters of normalised text in both submissions.

A part's score is the larger of the two shares of matched text (of each submission's text that can count: not
boilerplate, in stretches of at least :data:`MIN_REGION`, so that an identical copy scores 100 %); a pair's score is
the larger of its parts' scores, and ``part`` says which parts have a matching stretch at all: ``code``,
``written`` or ``both``.  Pairs without any are not listed.  Because the reference solution's k-grams count
for nobody, two students who both copied the reference solution would score low against each other: the report
therefore shows each student's share of code found in the reference solution as well.

The report is an HTML page without scripts or anything from the network (the student's text escaped), in the
instructor's language (``LAB_LANG``); ``--csv`` writes the ranked pairs (``student_a, student_b, score, part``).  It
is evidence for a person to weigh, not a verdict, and says so.  A notebook that cannot be read (invalid JSON, over
the size limit, a link) is noted and left out; a student's code beyond :data:`MAX_CODE` characters is cut there.
"""

import argparse
import copy
import csv
import io
import re
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import nbformat
import numpy as np

from ... import repository
from ...i18n import LANGUAGES, _, language
from ..grader.assignments import DEFAULT_FOLDER
from ..grader.notebook import read_submission
from ..untrusted import clean, csv_cell
from . import similarity_page, written
from .files import read_collected, write_atomic
from .grade import find_submissions

__all__ = ["CSV_COLUMNS", "GUARANTEE", "MAX_CODE", "MIN_REGION", "NOISE", "Pair", "Result", "SimilarityError",
           "compare", "main", "write_csv", "write_page"]

#: copydetect's noise threshold: the length k of a fingerprint's k-gram, in characters of normalised text (a name is
#: one character, ``V``); about one and a half lines of code (copydetect's default).
NOISE = 25
#: copydetect's guarantee threshold: a match this long is always found.  Equal to :data:`NOISE` (copydetect's
#: default), the winnowing window is 1: every k-gram is a fingerprint.  A notebook's code is a few thousand
#: characters, so nothing needs thinning, and the scores are the same in every run (copydetect hashes with Python's
#: per-process salted ``hash``: with a larger window the chosen fingerprints, and so the scores, change from run to
#: run).
GUARANTEE = 25
#: A stretch of matching k-grams counts only when it spans at least this many characters of normalised text in both
#: submissions (code: about four lines; written answers: about twelve words).
MIN_REGION = {"code": 80, "written": 80}
#: Most characters of a student's code (or written answers) compared; the rest is cut, with a note.
MAX_CODE = 50_000
#: The columns of ``--csv``.
CSV_COLUMNS = ("student_a", "student_b", "score", "part")
PARTS = ("code", "written")


class SimilarityError(ValueError):
    """A comparison that cannot be made (no submissions, an unknown assignment, too few notebooks)."""


@dataclass
class Match:
    """What two submissions share in one part: the shares of each one's text, and the matching stretches (start,
    end) in each one's text as shown."""

    share_a: float
    share_b: float
    slices_a: list
    slices_b: list

    @property
    def score(self):
        return max(self.share_a, self.share_b)


@dataclass
class Pair:
    a: str
    b: str
    matches: dict  # part -> Match

    @property
    def score(self):
        return max((m.score for m in self.matches.values()), default=0.0)

    @property
    def part(self):
        """``code``, ``written`` or ``both``: the parts with a matching stretch."""
        found = [p for p in PARTS if p in self.matches]
        return "both" if len(found) == 2 else found[0] if found else ""


@dataclass
class Submission:
    student: str
    path: Path
    texts: dict = field(default_factory=dict)  # part -> the text compared, as shown
    notes: list = field(default_factory=list)
    reference_share: float | None = None


@dataclass
class Result:
    assignment: str
    submissions: list
    pairs: list  # ranked, only those with a matching stretch
    skipped: list  # (name, reason)
    reference: bool  # whether a reference solution was found
    questions: int
    seconds: float = 0.0


# -- the instructor's notebooks ------------------------------------------------------------------------------------

def _notebooks(folder, assignment_id):
    """The instructor's notebooks ``folder/ID.ipynb`` and ``folder/<lang>/ID.ipynb`` that exist."""
    where = Path(folder)
    paths = [p / f"{assignment_id}.ipynb" for p in (where, *(where / lang for lang in LANGUAGES))]
    return [nbformat.read(str(p), as_version=4) for p in paths if p.is_file()]


def _known_assignments(folder):
    where = Path(folder)
    return sorted({p.stem for d in (where, *(where / lang for lang in LANGUAGES)) if d.is_dir()
                   for p in d.glob("*.ipynb")})


def _lines(source):
    """A cell's source without trailing spaces and blank lines at either end (so an unchanged cell is recognised
    after a save that stripped them)."""
    return "\n".join(line.rstrip() for line in str(source).strip().splitlines())


def _code_cells(nb):
    return [c.source for c in nb.cells if c.cell_type == "code" and str(c.source).strip()]


# -- normalising and fingerprints (copydetect) ---------------------------------------------------------------------

_WORD = re.compile(r"\w+")


def _prose(text):
    """``(normalised, where)``: ``text`` in lower case with every run of anything but letters and digits (spaces,
    punctuation, Markdown and TeX marks) one space, and for each character of it the index in ``text`` it comes from."""
    out, where = [], []
    for m in _WORD.finditer(text):
        if out:
            out.append(" ")
            where.append(m.start())
        for i in range(m.start(), m.end()):
            low = text[i].lower()
            out.append(low if len(low) == 1 else text[i])
            where.append(i)
    return "".join(out), where


class _Print:
    """The fingerprint of one part of one submission: copydetect's :class:`CodeFingerprint` of the normalised text,
    its k-grams in the order of the text (``positions``, ``hashes``), and how a stretch maps back to the text as
    shown."""

    def __init__(self, part, text, boilerplate):
        from copydetect import CodeFingerprint

        self.part, self.text = part, text
        if part == "code":
            self.fp = CodeFingerprint("cells.py", NOISE, GUARANTEE - NOISE + 1, language="python",
                                      fp=io.StringIO(text))
            self._where = None
        else:
            normalised, self._where = _prose(text)
            self.fp = CodeFingerprint("answers.txt", NOISE, GUARANTEE - NOISE + 1, filter=False,
                                      fp=io.StringIO(normalised))
        pairs = sorted((int(i), int(h)) for h, where in self.fp.hash_idx.items() for i in where)
        positions = np.array([i for i, _h in pairs], dtype=np.int64)
        hashes = np.array([h for _i, h in pairs], dtype=np.int64)
        # the boilerplate is left out here, not by CodeFingerprint: copydetect 0.5.0 removes it with
        # np.intersect1d(..., assume_unique=True) from hashes that repeat, which also drops repeated k-grams that are
        # no boilerplate
        keep = ~np.isin(hashes, boilerplate)
        self._index(positions[keep], hashes[keep])

    def _index(self, positions, hashes):
        self.positions, self.hashes = positions, hashes
        self.unique = np.unique(hashes)
        self.coverage = _covered(positions, self.fp.k, MIN_REGION[self.part])

    def without(self, hashes):
        """This fingerprint less the k-grams ``hashes`` (more boilerplate, without tokenising the text again)."""
        other = copy.copy(self)
        keep = ~np.isin(self.hashes, hashes)
        other._index(self.positions[keep], self.hashes[keep])
        return other

    def long(self, hashes, min_region):
        """The k-grams of ``hashes`` (sorted) that lie here in a stretch of them spanning at least ``min_region``
        characters."""
        mask = np.isin(self.hashes, hashes, assume_unique=False)
        positions, found = self.positions[mask], self.hashes[mask]
        return np.unique(found[_in_long_runs(positions, self.fp.k, min_region)])

    def shown(self, slices):
        """The stretches ``slices`` (2 × N, in normalised text) as ``[(start, end)]`` in the text as shown."""
        if slices.shape[1] == 0:
            return []
        if self._where is not None:
            where = self._where
            return [(where[s], where[t - 1] + 1) for s, t in zip(slices[0], slices[1])]
        offsets = self.fp.offsets  # copydetect's: characters removed before each position of the normalised code
        moved = slices.copy()
        if len(offsets):  # as copydetect.compare_files maps them
            moved += offsets[:, 1][np.clip(np.searchsorted(offsets[:, 0], slices), 0, offsets.shape[0] - 1)]
        n = len(self.text)
        return [(int(min(s, n)), int(min(t, n))) for s, t in zip(moved[0], moved[1]) if s < t]


def _boilerplate(part, texts):
    """The k-gram hashes of ``texts`` (copydetect's boilerplate: every k-gram, window 1), sorted."""
    from copydetect import CodeFingerprint

    hashes = set()
    for text in texts:  # each on its own: a k-gram across two cells is in no submission
        if part == "code":
            fp = CodeFingerprint("boilerplate.py", NOISE, 1, language="python", fp=io.StringIO(text))
        else:
            fp = CodeFingerprint("boilerplate.txt", NOISE, 1, filter=False, fp=io.StringIO(_prose(text)[0]))
        hashes |= {int(h) for h in fp.hashes}
    return np.array(sorted(hashes), dtype=np.int64)


def _runs(positions, k):
    """``(starts, ends)``: the stretches of the sorted k-gram ``positions`` as copydetect joins them (at most k − 1
    apart), as index ranges into ``positions``."""
    breaks = np.flatnonzero(np.diff(positions) > k - 1) + 1
    return np.r_[0, breaks], np.r_[breaks, len(positions)]


def _in_long_runs(positions, k, min_region):
    """For each of the sorted k-gram ``positions``: whether its stretch spans at least ``min_region`` characters."""
    if not len(positions):
        return np.zeros(0, dtype=bool)
    starts, ends = _runs(positions, k)
    return np.repeat(positions[ends - 1] - positions[starts] + k >= min_region, ends - starts)


def _covered(positions, k, min_region):
    """How many characters of the normalised text lie in stretches of its k-grams (what is not boilerplate) that span
    at least ``min_region`` characters: what a match can count, the denominator of a share (a shorter stretch never
    counts, so it is not counted against a copy either)."""
    if not len(positions):
        return 0.0
    starts, ends = _runs(positions, k)
    spans = positions[ends - 1] - positions[starts] + k
    return float(spans[spans >= min_region].sum())


def _match(pa, pb, min_region):
    """The :class:`Match` of two fingerprints of one part, or None: copydetect's comparison
    (:func:`copydetect.compare_files`) of only those common k-grams that lie in stretches of at least ``min_region``
    characters in both texts."""
    from copydetect.utils import get_copied_slices

    if not pa.coverage or not pb.coverage:
        return None
    common = np.intersect1d(pa.unique, pb.unique, assume_unique=True)
    while len(common):  # a stretch shortened in one text shortens it in the other: until nothing changes
        keep = np.intersect1d(pa.long(common, min_region), pb.long(common, min_region), assume_unique=True)
        if len(keep) == len(common):
            break
        common = keep
    if not len(common):
        return None
    k = pa.fp.k
    slices_a = get_copied_slices(pa.positions[np.isin(pa.hashes, common)], k)
    slices_b = get_copied_slices(pb.positions[np.isin(pb.hashes, common)], k)
    share_a = min(1.0, float(np.sum(slices_a[1] - slices_a[0])) / pa.coverage)
    share_b = min(1.0, float(np.sum(slices_b[1] - slices_b[0])) / pb.coverage)
    return Match(share_a, share_b, pa.shown(slices_a), pb.shown(slices_b))


# -- reading the submissions ---------------------------------------------------------------------------------------

def _candidates(folder):
    """``({student: [path, …]}, skipped)``: the notebooks ``SUBS/<student>/*.ipynb`` and ``SUBS/<student>.ipynb``
    (read as ``grade`` reads a folder: no links, no names that are no user names)."""
    folder = Path(folder)
    notebooks, refused = find_submissions(folder)
    found, skipped = {}, []
    for path in notebooks:
        rel = path.relative_to(folder)
        if len(rel.parts) == 1:
            found.setdefault(rel.stem, []).append(path)
        elif len(rel.parts) == 2:
            found.setdefault(rel.parts[0], []).append(path)
    for path, why in refused:
        rel = path.relative_to(folder)
        if len(rel.parts) <= 2:
            skipped.append((str(rel), why))
    return found, skipped


def _assignment_of(folder, found, assignment):
    """The assignment compared: ``assignment``, else the one ``collected.csv`` names, else the one of the notebooks'
    names ``SUBS/<student>/<ID>.ipynb``."""
    if assignment:
        return assignment
    ids = {row.get("assignment") for row in read_collected(folder).values()
           if row.get("status") == "collected" and row.get("assignment")}
    if len(ids) != 1:
        ids |= {p.stem for paths in found.values() for p in paths if p.parent != Path(folder)}
    if len(ids) == 1:
        return ids.pop()
    if not ids:
        raise SimilarityError(f"{folder}: cannot tell which assignment these notebooks are (no collected.csv, no "
                              "SUBS/<student>/<ID>.ipynb); name it with --assignment ID")
    raise SimilarityError(f"{folder} holds notebooks of several assignments ({', '.join(sorted(ids))}); choose one "
                          "with --assignment ID")


def _assignment_id(nb):
    meta = nb.metadata.get("lab") if isinstance(nb.metadata.get("lab"), dict) else {}
    return str(meta.get("assignment", ""))


def _read(folder, found, assignment_id, handed_out, questions, known, skipped):
    """The :class:`Submission` of each student with a readable notebook of the assignment."""
    subs = []
    for student, paths in sorted(found.items()):
        own = [p for p in paths if p.parent != Path(folder) and p.stem == assignment_id]
        flat = [p for p in paths if p.parent == Path(folder)]
        chosen, nb, notes = None, None, []
        for path in own + flat:
            try:
                _raw, candidate = read_submission(path)
            except ValueError as exc:
                skipped.append((str(path.relative_to(folder)), clean(exc, 300)))
                continue
            if path in flat and _assignment_id(candidate) != assignment_id:
                continue  # a flat notebook of another assignment (or of none)
            if chosen is None:
                chosen, nb = path, candidate
            else:
                notes.append(_("also found, not compared: {file}").format(file=path.relative_to(folder)))
        if chosen is None:
            continue
        sub = Submission(student, chosen, notes=notes)
        cells = [(k, _lines(c.source)) for k, c in enumerate(nb.cells, 1) if c.cell_type == "code"]
        kept = [(k, src) for k, src in cells if src and src not in handed_out]
        sub.texts["code"] = _cut(sub, "\n\n".join(f"# ── {k} ──\n{src}" for k, src in kept), _("code"))
        if questions:
            answers = written.answers_of(nb, questions, known)
            sub.texts["written"] = _cut(sub, "\n\n".join(f"[{k}] {answers.get(q.cell, '')}"
                                                         for k, q in enumerate(questions, 1)
                                                         if answers.get(q.cell, "").strip()), _("written answers"))
        if not sub.texts["code"]:
            sub.notes.append(_("no code beyond the hand-out"))
        subs.append(sub)
    return subs


def _cut(sub, text, what):
    if len(text) > MAX_CODE:
        sub.notes.append(_("{what} cut to the first {n} characters of {total}").format(
            what=what, n=MAX_CODE, total=len(text)))
        return text[:MAX_CODE]
    return text


# -- the comparison --------------------------------------------------------------------------------------------------

def default_solutions():
    """The repository's ``solutions/`` when the lab runs from a checkout, else None."""
    where = Path(repository()) / "solutions"
    return where if where.is_dir() else None


def compare(folder, *, assignment=None, exercises=DEFAULT_FOLDER, solutions="default"):
    """Compare every pair of submissions of one assignment in ``folder``; a :class:`Result`.

    ``exercises``: the instructor's exercises (``ID.ipynb`` or ``en/``, ``de/``); ``solutions``: the reference
    solutions, the same way (``"default"``: :func:`default_solutions`; None: none).
    Raises :class:`SimilarityError` saying what was expected and found.
    """
    start = time.perf_counter()
    folder = Path(folder)
    if not folder.is_dir():
        raise SimilarityError(f"{folder} is not a folder; expected a folder of submissions as curvature-lab collect "
                              "writes it (SUBS/<student>/<ID>.ipynb)")
    found, skipped = _candidates(folder)
    if not found:
        raise SimilarityError(f"{folder} holds no notebooks; expected SUBS/<student>/<ID>.ipynb as curvature-lab "
                              "collect writes it" + (f" (refused: {len(skipped)})" if skipped else ""))
    assignment_id = _assignment_of(folder, found, assignment)
    handouts = _notebooks(exercises, assignment_id)
    if not handouts:
        known = _known_assignments(exercises)
        raise SimilarityError(f"unknown assignment {assignment_id!r}: no exercise {assignment_id}.ipynb in {exercises} "
                              f"(or its {', '.join(LANGUAGES)} folders); the assignments there: "
                              f"{', '.join(known) or 'none'}")
    solutions = default_solutions() if solutions == "default" else solutions
    references = _notebooks(solutions, assignment_id) if solutions else []
    exercise_nb = next((nb for nb in handouts if nb.metadata.get("lab", {}).get("lang") == language()), handouts[0])
    questions = written.questions_of(exercise_nb)
    known = {c.get("id") for nb in handouts for c in nb.cells}
    handed_out = {_lines(src) for nb in handouts for src in _code_cells(nb)}

    subs = _read(folder, found, assignment_id, handed_out, questions, known, skipped)
    if len(subs) < 2:
        raise SimilarityError(f"{folder}: {len(subs)} readable notebook(s) of {assignment_id}; at least 2 are needed "
                              "to compare" + "".join(f"; {name}: {why}" for name, why in skipped))

    given = {"code": [src for nb in handouts for src in _code_cells(nb)],
             "written": [q.text for nb in handouts for q in written.questions_of(nb)]}
    answers = {"code": [src for nb in references for src in _code_cells(nb)],
               "written": [a for nb in references for a in written.answers_of(nb, questions, known).values()]}
    parts = ["code"] + (["written"] if questions else [])
    prints = {}
    for part in parts:
        handout, solution = _boilerplate(part, given[part]), _boilerplate(part, answers[part])
        mine = {s.student: _Print(part, s.texts[part], handout) for s in subs if s.texts.get(part)}
        if part == "code" and references:  # each student's share of code found in the reference solution
            reference = _Print(part, "\n\n".join(answers[part]), handout)
            for s in subs:
                m = _match(mine[s.student], reference, MIN_REGION[part]) if s.student in mine else None
                s.reference_share = m.share_a if m else 0.0
        prints[part] = {student: fp.without(solution) for student, fp in mine.items()}

    pairs = []
    for i, sa in enumerate(subs):
        for sb in subs[i + 1:]:
            matches = {}
            for part in parts:
                pa, pb = prints[part].get(sa.student), prints[part].get(sb.student)
                if pa is not None and pb is not None and (m := _match(pa, pb, MIN_REGION[part])):
                    matches[part] = m
            if matches:
                pairs.append(Pair(sa.student, sb.student, matches))
    pairs.sort(key=lambda p: (-p.score, p.a, p.b))
    return Result(assignment_id, subs, pairs, skipped, bool(references), len(questions),
                  time.perf_counter() - start)


# -- writing ---------------------------------------------------------------------------------------------------------

def write_csv(result, path):
    """The ranked pairs: :data:`CSV_COLUMNS`, each cell through :func:`~lab.teaching.untrusted.csv_cell`."""
    buf = io.StringIO()
    writer = csv.writer(buf)
    writer.writerow(CSV_COLUMNS)
    for p in result.pairs:
        writer.writerow([csv_cell(p.a), csv_cell(p.b), csv_cell(round(p.score, 3)), csv_cell(p.part)])
    write_atomic(path, buf.getvalue())


def write_page(result, path, lang=None):
    """The report as a self-contained HTML page, in ``lang`` (default: the current language)."""
    similarity_page.write_page(result, path, lang, min_region=MIN_REGION, parts=PARTS)


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab similarity",
        description=_("Rank the pairs of submissions of one assignment by how much code and written text they share "
                      "(token fingerprints: robust to renaming, reordering, comments and reformatting), with the "
                      "matching stretches side by side. Evidence for a person to weigh, not a verdict."))
    parser.add_argument("subs", help=_("folder of submissions, as curvature-lab collect writes it (SUBS)"))
    parser.add_argument("-o", "--output", required=True, help=_("the HTML page to write"))
    parser.add_argument("--csv", help=_("also write the ranked pairs to this CSV file"))
    parser.add_argument("--assignment", help=_("assignment id (default: the one in SUBS)"))
    parser.add_argument("--exercises", default=str(DEFAULT_FOLDER),
                        help=_("the instructor's exercises, whose code and questions are left out (default: "
                               "exercises/)"))
    parser.add_argument("--solutions", help=_("the reference solutions, whose code and sample answers are left out "
                                              "(default: solutions/ of the repository, if there)"))
    args = parser.parse_args(argv)
    subs = Path(args.subs)
    if not subs.exists():
        parser.error(f"{subs} does not exist; expected a folder of submissions (SUBS/<student>/<ID>.ipynb)")
    if not subs.is_dir():
        parser.error(f"{subs} is a file; expected a folder of submissions (SUBS/<student>/<ID>.ipynb)")
    for option, value in (("-o", args.output), ("--csv", args.csv)):
        if value and not Path(value).parent.is_dir():
            parser.error(f"{option} {value}: the folder {Path(value).parent} does not exist")
    if args.solutions and not Path(args.solutions).is_dir():
        parser.error(f"--solutions {args.solutions} is not a folder")
    try:
        result = compare(subs, assignment=args.assignment, exercises=args.exercises,
                         solutions=args.solutions or "default")
        write_page(result, args.output)
        if args.csv:
            write_csv(result, args.csv)
    except (SimilarityError, OSError) as exc:
        print(f"curvature-lab similarity: error: {exc}", file=sys.stderr)
        return 2
    for name, why in result.skipped:
        print(f"curvature-lab similarity: {clean(name, 300, keep_newlines=False)} not compared: {clean(why, 300)}",
              file=sys.stderr)
    print(_("{n} submissions, {pairs} pairs with matching stretches -> {file}").format(
        n=len(result.submissions), pairs=len(result.pairs), file=args.output), file=sys.stderr)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
