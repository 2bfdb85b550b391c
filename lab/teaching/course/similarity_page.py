"""The page of ``curvature-lab similarity`` (:mod:`lab.teaching.course.similarity`): the ranking, the matching
stretches side by side and every submission's notes, escaped, without scripts or anything from the network, in the
instructor's language; it says that it is evidence for a person to weigh, not a verdict."""

from ...i18n import _, decimal, language, using
from ..untrusted import clean
from .files import write_atomic
from .pages import e, page

__all__ = ["MAX_LISTED", "MAX_SHOWN", "write_page"]

#: Most pairs shown side by side, and listed in the page's ranking (the CSV lists all).
MAX_SHOWN = 30
MAX_LISTED = 500

STYLE = (".notice{border:2px solid #9a6700;background:#fff8c5;padding:.6em 1em;margin:1em 0}"
         ".sbs{display:grid;grid-template-columns:1fr 1fr;gap:1em}.sbs pre{margin:0;background:#f6f8fa;padding:.5em;"
         "font-size:.85em;overflow-wrap:anywhere;max-height:40em;overflow:auto}mark{background:#ffd8b5}"
         "td.n{text-align:right}")


def _percent(x):
    return f"{100 * x:.0f} %"


def _marked(text, slices):
    """``text`` escaped, its stretches ``slices`` in ``<mark>``."""
    out, at = [], 0
    for s, t in sorted(slices):
        s = max(s, at)
        if t <= s:
            continue
        out.append(e(text[at:s]))
        out.append(f"<mark>{e(text[s:t])}</mark>")
        at = t
    out.append(e(text[at:]))
    return "".join(out)


def _name(student):
    return e(clean(student, 100, keep_newlines=False))


def _part_name(part):
    return {"code": _("code"), "written": _("written answers"), "both": _("both")}.get(part, part)


def _page(result, MIN_REGION, PARTS):
    title = _("Similarity of submissions: {id}").format(id=result.assignment)
    by_name = {s.student: s for s in result.submissions}
    out = [f"<style>{STYLE}</style><h1>{e(title)}</h1>"]
    out.append("<div class='notice'><strong>" + e(_("Evidence, not a verdict.")) + "</strong> " + e(_(
        "A high score says that two submissions share long stretches of code or text once names, comments and "
        "layout are set aside. It does not say who copied from whom, or that anyone did: students may have worked "
        "together as allowed, or followed the same source. Read the matching stretches side by side and talk with "
        "the students before you decide anything.")) + "</div>")
    out.append("<p>" + e(_("{n} submissions compared, {pairs} pairs with matching stretches, in {seconds} s.").format(
        n=len(result.submissions), pairs=len(result.pairs), seconds=decimal(f"{result.seconds:.1f}"))) + "</p>")
    out.append("<p>" + e(_(
        "Compared: the code cells that differ from the hand-out and, separately, the written answers. Names become "
        "one token, comments and layout are dropped, so renaming, reordering, new comments and reformatting do not "
        "hide a copy. What the hand-out already holds counts for nobody, nor does what the reference solution holds "
        "(the natural way to write it); a stretch counts only when it spans at least {code} characters of "
        "normalised code (every name one character) or {text} of written text, so short pieces that are necessarily "
        "alike are not counted. The score is the larger of the two shares of matching text.").format(
        code=MIN_REGION["code"], text=MIN_REGION["written"])) + "</p>")
    if not result.reference:
        out.append("<p>" + e(_("No reference solution was found: what it would explain is counted.")) + "</p>")

    out.append("<h2>" + e(_("Ranking")) + "</h2>")
    if result.pairs:
        parts = PARTS if result.questions else ("code",)
        head = [_("rank"), _("student A"), _("student B"), _("score"), *map(_part_name, parts), _("part")]
        out.append("<table><tr>" + "".join(f"<th>{e(h)}</th>" for h in head) + "</tr>")
        for k, p in enumerate(result.pairs[:MAX_LISTED], 1):
            cells = [f"<a href='#pair-{k}'>{k}</a>" if k <= MAX_SHOWN else str(k), _name(p.a), _name(p.b),
                     _percent(p.score)] + [_percent(p.matches[part].score) if part in p.matches else "–"
                                           for part in parts] + [e(_part_name(p.part))]
            out.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
        out.append("</table>")
        if len(result.pairs) > MAX_LISTED:
            out.append("<p>" + e(_("{n} more pairs in the CSV file (--csv).").format(
                n=len(result.pairs) - MAX_LISTED)) + "</p>")
    else:
        out.append("<p>" + e(_("No pair shares a stretch long enough to count.")) + "</p>")

    if result.pairs:
        out.append("<h2>" + e(_("Side by side")) + "</h2><p>" + e(_(
            "Matching stretches are marked. Each code cell is headed by its number in the notebook (# ── 7 ──)."))
            + "</p>")
    for k, p in enumerate(result.pairs[:MAX_SHOWN], 1):
        out.append(f"<section id='pair-{k}'><h3>{k}. {_name(p.a)} – {_name(p.b)}: {e(_percent(p.score))}</h3>")
        for part in PARTS:
            if part not in p.matches:
                continue
            m = p.matches[part]
            out.append(f"<h4>{e(_part_name(part))}: {_name(p.a)} {e(_percent(m.share_a))}, {_name(p.b)} "
                       f"{e(_percent(m.share_b))}</h4><div class='sbs'>")
            for student, slices in ((p.a, m.slices_a), (p.b, m.slices_b)):
                text = by_name[student].texts[part]
                out.append(f"<div><strong>{_name(student)}</strong><pre>{_marked(text, slices)}</pre></div>")
            out.append("</div>")
        out.append("</section>")

    out.append("<h2>" + e(_("Submissions")) + "</h2><table><tr>" + "".join(
        f"<th>{e(h)}</th>" for h in (_("student"), _("code (characters)"), _("like the reference solution"),
                                     _("notes"))) + "</tr>")
    for s in result.submissions:
        share = "–" if s.reference_share is None else _percent(s.reference_share)
        out.append(f"<tr><td>{_name(s.student)}</td><td class='n'>{len(s.texts.get('code', ''))}</td>"
                   f"<td class='n'>{e(share)}</td><td>{e(clean('; '.join(s.notes), 600))}</td></tr>")
    out.append("</table>")
    if result.reference:
        out.append("<p>" + e(_("Like the reference solution: the share of a student's code (less the hand-out) also "
                                "found in the reference solution. Between students it counts for nobody, so two "
                                "students who both copied it would score low together: a high share here is a reason "
                                "to look, not proof (part of it is the natural way to write the task).")) + "</p>")
    if result.skipped:
        out.append("<h2>" + e(_("Not compared")) + "</h2><ul>" + "".join(
            f"<li>{e(clean(name, 300, keep_newlines=False))}: {e(clean(why, 600))}</li>"
            for name, why in result.skipped) + "</ul>")
    return page(title, "".join(out), language())


def write_page(result, path, lang=None, *, min_region, parts):
    """The report (:class:`lab.teaching.course.similarity.Result`) as a self-contained HTML page, in ``lang``
    (default: the current language); ``min_region``, ``parts``: the comparison's, as the page explains them."""
    with using(lang or language()):
        write_atomic(path, _page(result, min_region, parts))
