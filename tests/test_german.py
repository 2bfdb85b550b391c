"""The German a student reads: one form of address ("Sie", README "Form of address"), German outputs (issue 20)."""

import re
from pathlib import Path

import nbformat
import pytest

ROOT = Path(__file__).resolve().parent.parent

#: forms of "du": pronouns, possessives, and the imperatives the notebooks' tasks used ("Vervollständige …")
DU = re.compile(r"\b(du|dich|dir|dein|deine|deinen|deinem|deiner|deines|Du|Dein|Deine|Deinen|Deinem|Deiner|"
                r"hast|bist|kannst|musst|darfst|siehst|"
                r"Vervollständige|Vergleiche|Schreibe|Schreib|Gib|Nimm|Ändere|Wähle|Setze|Führe|Öffne|Verwende|"
                r"Ersetze|Berechne|Prüfe|Probiere|Wechsle|Verschiebe|Zeichne|Bewege|Geh|Entwirf|Skaliere|"
                r"gib|nimm|verwende|prüfe|vergleiche|teile|wähle|schreib|schreibe)\b")


def _german_texts():
    for folder in ("solutions/de", "exercises/de"):
        for path in sorted((ROOT / folder).glob("*.ipynb")):
            nb = nbformat.read(path, as_version=4)
            for i, cell in enumerate(nb.cells):
                source = cell.source
                if cell.cell_type == "code":  # comments and strings only: code identifiers are English
                    source = "\n".join(re.findall(r"#.*|\"[^\"\n]*\"|'[^'\n]*'", source))
                yield f"{folder}/{path.name} cell {i}", source


def test_german_notebooks_say_sie():
    found = [f"{where}: {line.strip()}" for where, text in _german_texts() for line in text.splitlines()
             if DU.search(line)]
    assert not found, "du forms in German notebooks:\n" + "\n".join(found[:20])


def test_german_messages_say_sie():
    from babel.messages.pofile import read_po

    with open(ROOT / "lab" / "i18n" / "locale" / "de" / "LC_MESSAGES" / "lab.po", "rb") as fh:
        catalogue = read_po(fh)
    found = [m.string for m in catalogue if m.id and isinstance(m.string, str) and DU.search(m.string)]
    assert not found, "du forms in the German messages:\n" + "\n".join(found[:20])


def test_the_du_check_finds_du_forms():
    assert DU.search("Vervollständige `h(x)`; gib ein Tupel zurück") and DU.search("deine Werte")
    assert DU.search("NaN: nimm √(max(H² − K, 0))") and DU.search("verwende tol, keine feste Zahl")
    assert not DU.search("Vervollständigen Sie `h(x)`; geben Sie ein Tupel zurück; Ihre Werte")


# -- the outputs of the German notebooks ----------------------------------------------------------------------------

#: English words that German text never uses (short function words and the lab's English terms)
ENGLISH = {"the", "of", "and", "is", "are", "with", "from", "your", "you", "not", "yet", "which", "this", "that",
           "at", "on", "by", "for", "to", "points", "values", "curves", "curve", "patch", "closed", "open", "pieces",
           "largest", "smallest", "differ", "corner", "cylinder", "tilted", "depth", "mean", "curvature",
           "gaussian", "surface", "implemented", "expected", "got", "passed", "failed", "case", "cases", "holes",
           "outer", "loop", "region", "triangles", "nodes", "angle", "vertices", "lines", "line", "warning",
           "removed", "distance", "axis", "length", "end", "start", "sections", "geodesics", "area", "areas",
           "explorer", "picture", "notebook", "interactive", "view", "control", "degree", "rational",
           # Dill's colours (lab.colormaps.dill_names), the point classes (PointClass.label), the meshes' diagonals
           # (estimators.diagonals_name), the colour-vision deficiencies (lab.vision.name)
           "blue", "turquoise", "green", "yellow", "red", "hyperbolic", "parabolic", "elliptic", "flat", "regular",
           "alternating", "random", "protanopia", "deuteranopia", "tritanopia"}
#: words that are English and allowed: code identifiers and names a German text uses as they are
#: ("Patch" and "Start" are German words too)
ALLOWED = {"lab", "signed", "log", "signed-log", "off", "coff", "cbez333", "jupyterlab", "explorer", "patch", "start"}
#: the kinds of a model's faces as code names them (``face.kind == "Cylinder"``, OpenCASCADE's type names)
KINDS = {"Plane", "Cylinder", "Cone", "Sphere", "Torus"}


def english_words(text):
    """The English words of ``text`` outside code: identifiers (snake_case, CamelCase, dotted, calls) are skipped."""
    text = re.sub(r"`[^`]*`|'[^'\n]*'|\"[^\"\n]*\"", " ", text)  # quoted code and values
    words = []
    for token in re.findall(r"[A-Za-zÄÖÜäöüß_.()\[\]-]+", text):
        if "_" in token or "." in token.strip(".") or "(" in token or re.search(r"[a-z][A-Z]", token) or token in KINDS:
            continue
        word = token.strip(".()[]-").lower()
        if word in ENGLISH and word not in ALLOWED:
            words.append(word)
    return words


def test_the_english_check_finds_english_and_skips_code():
    assert english_words("die Spitze: largest K at the corner") == ["largest", "at", "the", "corner"]
    assert english_words("TrimmedSurface(BSplineSurface(...)) mit set_curvature und lab.render.show") == []
    assert english_words("Ihr visualize_curvature auf 196 Patches; Werte −2,1 … 36,7") == []
    assert english_words("Äquator außen   u =  0,0: K = +0,1111 -> yellow") == ["yellow"]
    assert english_words("HYPERBOLIC     25,0 % der Abtastpunkte") == ["hyperbolic"]
    assert english_words("Torus  alternating: innen, Ordnung von K +2,00") == ["alternating"]
    assert english_words("deuteranopia  kleinster Schritt  10,6") == ["deuteranopia"]
    assert english_words("Äquator außen   u =  0,0: K = +0,1111 -> gelb; hyperbolisch; Torus abwechselnd") == []


def _outputs(nb):
    for i, cell in enumerate(nb.cells):
        for out in cell.get("outputs", []):
            if out.output_type == "stream":
                yield i, out.text
            elif out.output_type == "error":
                yield i, f"{out.ename}: {out.evalue}"
            elif "text/plain" in out.get("data", {}) and "image/png" not in out["data"]:
                yield i, out["data"]["text/plain"]


@pytest.mark.parametrize("path", sorted((ROOT / "solutions" / "de").glob("*.ipynb")), ids=lambda p: p.stem)
def test_german_notebooks_print_german(path, tmp_path):
    """Run All on a German solution (no frontend: the explorers show pictures); its printed outputs are German and free
    of leftovers (issue 36: every German solution, 00–13)."""
    from lab.teaching.kernel.notebook_client import NotebookRunner  # nbclient's own waits can stall a whole cell limit

    nb = nbformat.read(path, as_version=4)
    NotebookRunner(nb, timeout=900, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}},
                   allow_errors=True).execute()
    errors = [f"cell {i}: {text}" for i, cell in enumerate(nb.cells) for out in cell.get("outputs", [])
              if out.output_type == "error" for text in [f"{out.ename}: {out.evalue}"]]
    assert not errors, errors
    english = [f"cell {i}: {sorted(set(words))} in {text.strip()[:160]!r}" for i, text in _outputs(nb)
               for words in [english_words(text)] if words]
    assert not english, "English in the outputs of " + path.name + ":\n" + "\n".join(english)
    leftovers = [f"cell {i}: {found!r} in {text.strip()[:160]!r}" for i, text in _outputs(nb)
                 for found in [leftover(text)] if found]
    assert not leftovers, "leftovers in the outputs of " + path.name + ":\n" + "\n".join(leftovers)


#: What a German printout of any German solution must not show (issue 36): a decimal point in a number, the level
#: "none", "exact", a raw repr of the lab's records, a path of the machine, a negative zero.
LEFTOVERS = re.compile(r"(?<![\w.])[-+]?\d+\.\d+(?:e[-+]?\d+)?(?![\w.])|\bnone: \d|\bexact\b|\b(?:Umbilic|CurvatureDirections|Model)\("
                       r"|(?:^|[\s(\[])/(?:home|work|usr|tmp|opt)/|-0,0+\b")


#: A line of Python a notebook prints for the student to copy into a code cell (05's ``answer = (K_min, …)``): its
#: numbers keep Python's decimal point, as the values a student types into code do.
CODE_LINE = re.compile(r"^answer = \(.*$", re.MULTILINE)


def leftover(text):
    """The first leftover of English or of the machine in a German output, or None."""
    found = LEFTOVERS.search(CODE_LINE.sub("", text))
    return found.group() if found else None


def test_the_leftover_check_finds_each_leftover():
    for text in ("Winkel 1.95e-14 Grad", "99 Kanten (G2: 1, none: 0)", "|d1 . exact d1|", "Umbilic(lemon, index +0.5",
                 "CurvatureDirections(K=0.6", "Model(32 Flächenstücke", "aus /work/main/lab/teapot.bbp",
                 "k2 = -0,0000", "✔ h(0.25)", "Start (0.5, 0.4)", "Ende [5.  3.5]",
                 "answer = (1.5, 2)\nK = 0.5", "Antwort: answer = (1.5, 2)"):
        assert leftover(text), text
    for text in ("Winkel 1,95e-14 Grad", "99 Kanten (G2: 1, offen: 0)", "shell1.brep", "k2 = +0,0000  Radius 0,3953",
                 "Flächenstück 13 (B-Spline-Fläche)", "Nabelpunkt (Zitrone, Index +0,5) bei (2,37171; 0; 0,612372)",
                 "answer = (-1.102788646, 36.68493827, -0.5304956518, 6.082104899)"):
        assert not leftover(text), text
