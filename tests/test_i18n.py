"""Messages in German: every marked message has a German text, the compiled catalogue is current, and the
checks, hints and grader reports speak the language chosen (LAB_LANG, set_language, a notebook's language)."""

import re
import subprocess
import sys
from pathlib import Path

import pytest

from lab import check, i18n
from lab.teaching.task import fmt

babel = pytest.importorskip("babel")
from babel.messages import extract, mofile, pofile

ROOT = Path(__file__).resolve().parent.parent
PO = i18n.LOCALE_DIR / "de" / "LC_MESSAGES" / "lab.po"
MO = PO.with_suffix(".mo")
PLACEHOLDER = re.compile(r"(?<!\{)\{([a-z_0-9]*)\}(?!\})")


def extracted():
    """The messages marked in the sources (``_`` and ``N_``), as ``make translations`` extracts them."""
    out = set()
    for path in sorted((ROOT / "lab").rglob("*.py")):
        with open(path, "rb") as fh:
            for _line, message, _comments, _context in extract.extract("python", fh, keywords={"_": None, "N_": None}):
                out.add(message)
    return out


def catalogue():
    with open(PO, "rb") as fh:
        return pofile.read_po(fh)


def test_every_message_has_a_german_text():
    cat = catalogue()
    missing = sorted(m for m in extracted() if not (cat.get(m) and cat.get(m).string))
    assert missing == [], f"{len(missing)} messages without German text (make translations, then translate): {missing[:5]}"
    fuzzy = [m.id for m in cat if m.id and m.fuzzy]
    assert fuzzy == [], f"fuzzy (unchecked) translations: {fuzzy[:5]}"


def test_translations_keep_their_placeholders():
    for m in catalogue():
        if m.id and m.string:
            assert set(PLACEHOLDER.findall(m.id)) == set(PLACEHOLDER.findall(m.string)), (m.id, m.string)


def test_the_compiled_catalogue_is_current():
    with open(MO, "rb") as fh:
        compiled = {m.id: m.string for m in mofile.read_mo(fh) if m.id}
    assert compiled == {m.id: m.string for m in catalogue() if m.id and m.string}, "run make translations"


def test_language_follows_lab_lang_and_set_language(monkeypatch):
    monkeypatch.delenv("LAB_LANG", raising=False)
    monkeypatch.setattr(i18n, "_chosen", None)
    assert i18n.language() == "en"
    monkeypatch.setenv("LAB_LANG", "de_DE.UTF-8")
    assert i18n.language() == "de"
    with i18n.using("en"):
        assert i18n.language() == "en"
    with pytest.raises(ValueError, match="language must be one of en, de; got 'fr'"):
        i18n.set_language("fr")


def test_checks_and_hints_speak_german():
    def stub(k1, k2):
        raise NotImplementedError

    with i18n.using("de"):
        rep = check.warmup(stub)
        wrong = check.warmup(lambda k1, k2: k1 * k2)
    assert "noch nicht implementiert" in str(rep)
    assert "Gaußsche Krümmung" in str(wrong) and "Erster fehlgeschlagener Fall" in str(wrong)
    assert "not implemented yet" in str(check.warmup(stub))  # and English outside


def test_reports_write_numbers_as_the_language_does():
    """German case names, "expected" and "got" use decimal commas and a semicolon between numbers (issue 36)."""
    assert i18n.number_list([0.5, "x", 3]) == "0.5, x, 3" and i18n.number_list([-2.5, 0.25], "+.2f") == "-2.50, +0.25"
    with i18n.using("de"):
        assert i18n.number_list([0.5, "x", 3]) == "0,5; x; 3" and fmt([0.5, 1.25]) == "[0,5  1,25]"
        right = str(check.f2(lambda x, lo, hi: 0.5 if hi == lo else (x - lo) / (hi - lo)))
        wrong = str(check.f1(lambda x: x))  # f1(7.5) gives 7.5, not 1
    assert "f2(3; 1; 5)" in right and "f2(0,7; 0,7; 0,7)" in right and "f1(7,5)" in wrong
    assert not re.search(r"\d\.\d", right + wrong), right + wrong
    assert "f2(0.7, 0.7, 0.7)" in str(check.f2(lambda x, lo, hi: 0.5 if hi == lo else (x - lo) / (hi - lo)))


def test_kernel_started_with_lab_lang_speaks_german():
    code = "from lab import check\nprint(check.warmup(lambda a, b: a * b))"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={"LAB_LANG": "de", "PATH": "/usr/bin:/bin"}).stdout
    assert "Gaußsche Krümmung" in out


def test_explorer_labels_speak_german():
    """Controls, options, status texts and the colour bar of the explorers follow the language."""
    from lab import surfaces
    from lab.view.explorers import CurvatureExplorer, GeodesicExplorer

    with i18n.using("de"):
        e = CurvatureExplorer(surfaces.practical(), depth=1, live=False)
        g = GeodesicExplorer(surfaces.plane(4.0), start=(0.5, 0.5), n_angles=6, step=0.5, n_curves=2, live=False)
        labels = dict(e.measure.options)
        legend = e.legend()
        info = e.info.value
        title = e.picture_title()
        fan_legend = g.legend_html()
    # the labels the notebooks' text uses ("Krümmungsmaß", "Tiefe"), in the form of address "Sie"
    assert (e.measure.description, e.color_map.description, e.depth.description) == ("Krümmungsmaß", "Farbabbildung",
                                                                                       "Tiefe")
    assert e.range_mode.tooltips[1] == "−max|Wert| … +max|Wert|"
    assert labels["K  Gaußsche"] == "gaussian" and labels["H  mittlere"] == "mean", labels
    assert [label for label, _ in e.range_mode.options] == ["auto", "± max", "manuell"]
    assert legend.title == "Gaußsche Krümmung K  [1/Länge²]", legend.title
    assert re.search(r"\d+ Patches bei Tiefe 1; Werte ", info), info
    assert title.startswith("K, h∘f2 linear (min/max), Tiefe 1"), title
    assert (g.kind.description, g.step.description) == ("Pfade", "Schritt s_L")
    assert "Parametergebiet" in g.domain_view.value and "polare Isodistanzkurven" in fan_legend
    # the same explorer in English
    with i18n.using("en"):
        e2 = CurvatureExplorer(surfaces.practical(), depth=1, live=False)
    assert e2.measure.description == "measure" and e2.legend().title == "Gaussian curvature K  [1/length²]"
    for x in (e, g, e2):
        x.close()
