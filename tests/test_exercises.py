"""Bilingual source notebooks and what is generated from them (lab.notebooks): exercises and solutions in English and German."""

import copy
import shutil
from pathlib import Path

import nbformat
import pytest

from lab import notebooks

ROOT = Path(__file__).resolve().parent.parent
SOURCES = sorted((ROOT / "solutions").glob("[0-9][0-9]_*.ipynb"))
LANGS = notebooks.LANGUAGES


def read(path):
    return nbformat.read(path, as_version=4)


def test_committed_notebooks_are_freshly_generated():
    assert len(SOURCES) == 14
    result = notebooks.generate(ROOT / "solutions", ROOT / "exercises", check_only=True)
    assert len(result) == 4 * len(SOURCES)
    differs = [str(p) for p, action in result.items() if action != "unchanged"]
    assert not differs, f"generated notebooks differ from the sources in solutions/ (run `make exercises`): {differs}"
    names = sorted(p.name for p in SOURCES)
    for folder in ("exercises", "solutions"):
        for lang in LANGS:
            assert sorted(p.name for p in (ROOT / folder / lang).glob("*.ipynb")) == names, f"{folder}/{lang}"
    assert list((ROOT / "exercises").glob("*.ipynb")) == [], "exercises live in exercises/en and exercises/de"




@pytest.mark.parametrize("path", SOURCES, ids=lambda p: p.stem)
def test_every_source_has_both_languages(path):
    """Each markdown cell has its twin, each comment and task text its German version, no translation is stale."""
    nb = read(path)
    assert notebooks.problems(nb, path.name) == []
    md = [c for c in nb.cells if c.cell_type == "markdown"]
    assert [c.metadata["lang"] for c in md] == ["en", "de"] * (len(md) // 2)


def _source():
    nb = nbformat.v4.new_notebook()
    nb.metadata["lab"] = {"assignment": "99_demo", "title": "Demo", "title_de": "Demo (deutsch)", "tasks": []}
    cells = [nbformat.v4.new_markdown_cell("# Curvature"), nbformat.v4.new_markdown_cell("# Krümmung"),
             nbformat.v4.new_code_cell("import numpy as np\n\nimport lab"),
             nbformat.v4.new_code_cell("x = 1  # the answer\nprint(f'value {x:.2f}')"),
             nbformat.v4.new_markdown_cell("Q?\n<!-- BEGIN SOLUTION -->\nA.\n<!-- END SOLUTION -->"),
             nbformat.v4.new_markdown_cell("F?\n<!-- BEGIN SOLUTION -->\nA (de).\n<!-- END SOLUTION -->")]
    for cell, lang, cid in zip([cells[i] for i in (0, 1, 4, 5)], ["en", "de"] * 2, ["m1", "m1-de", "m2", "m2-de"]):
        cell.metadata["lang"], cell.id = lang, cid
    cells[3].metadata["de"] = {"# the answer": "# die Antwort", "value": "Wert"}
    nb.cells = cells
    return nb


def test_a_complete_source_has_no_problems():
    assert notebooks.problems(_source()) == []


@pytest.mark.parametrize("damage, message", [
    (lambda nb: nb.cells.pop(1), "has no German twin"),
    (lambda nb: nb.cells.pop(0), "a markdown cell with lang 'de' where an English cell"),
    (lambda nb: setattr(nb.cells[1], "source", "  "), "German text of the pair is empty"),
    (lambda nb: setattr(nb.cells[0], "source", ""), "English text of the pair is empty"),
    (lambda nb: setattr(nb.cells[1], "source", "# Curvature"), "identical to the English cell"),
    (lambda nb: nb.cells[1].metadata.pop("lang"), "has no German twin"),
    (lambda nb: setattr(nb.cells[5], "source", "F? A (de)."), "<!-- BEGIN SOLUTION --> appears 1 times in English, 0"),
    (lambda nb: setattr(nb.cells[1], "id", "other"), "twin's id should be m1-de"),
    (lambda nb: setattr(nb.cells[3], "source", "x = 1  # the right answer\nprint(f'value {x:.2f}')"),
     "the translation of '# the answer' is stale"),
    (lambda nb: setattr(nb.cells[3], "source", "x = 1  # the answer\nprint(f'value {x:.2f}')  # shown"),
     "comments without a German translation (metadata 'de'): ['# shown']"),
    (lambda nb: nb.cells[3].metadata["de"].update({"x = 1": "x = 2"}), "change code, not only comments and strings"),
    (lambda nb: nb.cells[3].metadata["de"].update({"{x:.2f}": "{x:.3f}"}), "change code, not only comments and strings"),
    (lambda nb: nb.metadata["lab"].pop("title_de"), "no German title"),
])
def test_problems_name_what_is_missing_or_stale(damage, message):
    nb = _source()
    damage(nb)
    found = notebooks.problems(nb, "demo")
    assert any(message in p for p in found), found


def test_a_neutral_comment_is_listed_with_itself():
    nb = _source()
    nb.cells[3].source += "  # c00, c01"
    assert any("# c00, c01" in p for p in notebooks.problems(nb))
    nb.cells[3].metadata["de"]["# c00, c01"] = "# c00, c01"
    assert notebooks.problems(nb) == []


def test_generation_refuses_an_incomplete_source(tmp_path):
    nb = _source()
    nb.cells.pop(1)
    nbformat.write(nb, tmp_path / "99_demo.ipynb")
    with pytest.raises(notebooks.SourceError, match="99_demo.ipynb, cell 0 .*has no German twin"):
        notebooks.generate(tmp_path, tmp_path / "exercises")
    assert not (tmp_path / "exercises").exists() and not (tmp_path / "en").exists()
    assert notebooks.main(["--solutions", str(tmp_path), "--exercises", str(tmp_path / "exercises")]) == 1


def test_localize_picks_the_language_and_keeps_the_code():
    src = _source()
    before = copy.deepcopy(src)
    en, de = notebooks.localize(src, "en"), notebooks.localize(src, "de")
    assert src == before  # the source is unchanged
    assert next(c.source for c in en.cells if c.cell_type == "markdown") == "# Curvature"
    assert next(c.source for c in de.cells if c.cell_type == "markdown") == "# Krümmung"
    assert [c.id for c in en.cells] == [c.id for c in de.cells]  # the English ids in both languages
    assert de.cells[1].source == 'import numpy as np\n\nimport lab\n' + notebooks.SET_LANGUAGE["de"]
    assert en.cells[1].source == "import numpy as np\n\nimport lab"
    assert de.cells[2].source == "x = 1  # die Antwort\nprint(f'Wert {x:.2f}')"
    assert en.cells[2].source == "x = 1  # the answer\nprint(f'value {x:.2f}')"
    assert (en.metadata.lab.lang, de.metadata.lab.lang) == ("en", "de")
    assert (en.metadata.lab.title, de.metadata.lab.title) == ("Demo", "Demo (deutsch)")
    assert all("lang" not in c.metadata and "de" not in c.metadata for nb in (en, de) for c in nb.cells)
    exercise = notebooks.make_exercise(de)
    assert exercise.cells[-1].source == "F?\n*Ihre Antwort hier.*"
    assert notebooks.make_exercise(en).cells[-1].source == "Q?\n*Your answer here.*"


@pytest.mark.parametrize("name", [p.name for p in SOURCES], ids=lambda n: n[:-6])
def test_both_languages_have_the_same_assignment_tasks_and_code(name):
    en, de = (read(ROOT / "solutions" / lang / name) for lang in LANGS)
    assert en.metadata.lab.assignment == de.metadata.lab.assignment == name[:-6]
    assert en.metadata.lab.tasks == de.metadata.lab.tasks
    assert en.metadata.lab.title != de.metadata.lab.title
    assert (en.metadata.lab.lang, de.metadata.lab.lang) == ("en", "de")
    assert [(c.cell_type, c.id) for c in en.cells] == [(c.cell_type, c.id) for c in de.cells]
    first_en, first_de = (next(c for c in nb.cells if c.cell_type == "code") for nb in (en, de))
    assert "import lab\n" + notebooks.SET_LANGUAGE["de"] + "\n" in first_de.source + "\n"
    assert "set_language" not in first_en.source
    # every German code cell is the English one with comments and strings changed, nothing else
    for a, b in zip(en.cells, de.cells):
        if a.cell_type == "code":
            assert notebooks._tokens(a.source) == notebooks._tokens(b.source.replace(notebooks.SET_LANGUAGE["de"], ""))
        else:
            assert a.source != b.source


@pytest.mark.parametrize("lang", LANGS)
def test_exercises_have_stubs_no_solutions_and_no_outputs(lang):
    for path in sorted((ROOT / "exercises" / lang).glob("*.ipynb")):
        nb = read(path)
        text = "\n".join(c.source for c in nb.cells)
        assert "BEGIN SOLUTION" not in text and "END SOLUTION" not in text, path
        if nb.metadata["lab"]["tasks"]:  # the gallery has questions (answers stripped) but no code task
            assert "raise NotImplementedError(" in text, path
        else:
            assert notebooks.ANSWER_PLACEHOLDER[lang] in text, path
        for cell in nb.cells:
            if cell.cell_type == "code":
                assert cell.outputs == [] and cell.execution_count is None, path
        assert nb.metadata["lab"]["role"] == "exercise" and nb.metadata["lab"]["lang"] == lang, path
        assert "tasks" in nb.metadata["lab"], path


def test_german_task_texts_are_german():
    """The NotImplementedError messages (what to implement) differ between the languages, task by task."""
    for name in (p.name for p in SOURCES):
        en, de = ("\n".join(c.source for c in read(ROOT / "exercises" / lang / name).cells) for lang in LANGS)
        stubs_en = [line.strip() for line in en.splitlines() if "raise NotImplementedError(" in line]
        stubs_de = [line.strip() for line in de.splitlines() if "raise NotImplementedError(" in line]
        assert len(stubs_en) == len(stubs_de), name
        assert all(a != b for a, b in zip(stubs_en, stubs_de)), name
    text = "\n".join(c.source for c in read(ROOT / "exercises" / "de" / "00_start.ipynb").cells)
    assert "raise NotImplementedError('die mittlere Krümmung der Hauptkrümmungen k1 und k2 zurückgeben')" in text


def test_visualize_stub_keeps_the_practicals_comments():
    for lang, first, second in [("en", "# calculate curvatures at each corner point", "# set colors according to color map"),
                                ("de", "# Krümmungen an jedem Eckpunkt berechnen", "# Farben entsprechend der Farbabbildung setzen")]:
        nb = read(ROOT / "exercises" / lang / "05_visualize_curvature.ipynb")
        cell = next(c for c in nb.cells if "class MyBezierPatches" in c.source)
        lines = cell.source.splitlines()
        i = lines.index("        " + first)
        assert lines[i + 1].startswith("        raise NotImplementedError(")
        assert "        " + second in lines


def test_strip_code_keeps_indentation_and_message():
    src = "def f(x):\n    y = 1\n    ### BEGIN SOLUTION: return twice x\n    return 2 * x\n    ### END SOLUTION\n"
    assert notebooks.strip_code(src) == "def f(x):\n    y = 1\n    raise NotImplementedError('return twice x')\n"
    assert "replace this line with your solution" in notebooks.strip_code("### BEGIN SOLUTION\nx\n### END SOLUTION")
    assert "ersetzen Sie diese Zeile durch Ihre Lösung" in notebooks.strip_code("### BEGIN SOLUTION\nx\n### END SOLUTION", "de")
    with pytest.raises(ValueError, match="without '### END SOLUTION'"):
        notebooks.strip_code("### BEGIN SOLUTION\nx = 1\n")
    with pytest.raises(ValueError, match="'### END SOLUTION' without '### BEGIN SOLUTION'"):
        notebooks.strip_code("x = 1\n### END SOLUTION\n")
    md = "Q?\n<!-- BEGIN SOLUTION -->\nsecret\n<!-- END SOLUTION -->\nmore"
    assert notebooks.strip_markdown(md) == "Q?\n*Your answer here.*\nmore"
    assert notebooks.strip_markdown(md, "de") == "Q?\n*Ihre Antwort hier.*\nmore"


def test_regeneration_refuses_to_overwrite_student_work(tmp_path):
    sol, ex = tmp_path / "solutions", tmp_path / "exercises"
    sol.mkdir()
    for path in SOURCES:
        shutil.copy(path, sol / path.name)
    first = notebooks.generate(sol, ex)
    assert set(first.values()) == {"written"} and len(first) == 4 * len(SOURCES)
    assert set(notebooks.generate(sol, ex).values()) == {"unchanged"}
    # a student works on the German exercise 02
    target = ex / "de" / "02_fundamental_forms.ipynb"
    nb = read(target)
    nb.cells[3].source += "\n# meine Arbeit"
    nbformat.write(nb, target)
    before = target.read_bytes()
    # the instructor changes a solution and regenerates
    src = read(sol / "02_fundamental_forms.ipynb")
    src.cells[1].source += "\n\nEin neuer Satz."
    nbformat.write(src, sol / "02_fundamental_forms.ipynb")
    with pytest.raises(notebooks.StudentChangesError, match="de/02_fundamental_forms.ipynb"):
        notebooks.generate(sol, ex)
    assert target.read_bytes() == before  # nothing lost
    assert notebooks.main(["--solutions", str(sol), "--exercises", str(ex)]) == 1
    # an untouched exercise is regenerated once the edited one is moved away
    target.rename(tmp_path / "mine.ipynb")
    result = notebooks.generate(sol, ex)
    assert result[target] == "written" and result[sol / "de" / "02_fundamental_forms.ipynb"] == "written"
    assert result[ex / "en" / "02_fundamental_forms.ipynb"] == "unchanged"  # only the German text changed
    assert "Ein neuer Satz." in read(target).cells[0].source


def test_a_hand_edited_generated_solution_is_not_overwritten(tmp_path):
    sol, ex = tmp_path / "solutions", tmp_path / "exercises"
    sol.mkdir()
    shutil.copy(ROOT / "solutions" / "00_start.ipynb", sol / "00_start.ipynb")
    notebooks.generate(sol, ex)
    target = sol / "en" / "00_start.ipynb"
    nb = read(target)
    nb.cells[0].source += "\nedited here instead of in the source"
    nbformat.write(nb, target)
    with pytest.raises(notebooks.StudentChangesError, match="bilingual source"):
        notebooks.generate(sol, ex)
    assert notebooks.main(["--solutions", str(sol), "--exercises", str(ex), "--check"]) == 1
