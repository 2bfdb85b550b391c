"""The German a student reads: one form of address ("Sie", README "Form of address"), German outputs (issue 20)."""

import re
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent

#: forms of "du": pronouns, possessives, and the imperatives the notebooks' tasks used ("Vervollständige …")
DU = re.compile(r"\b(du|dich|dir|dein|deine|deinen|deinem|deiner|deines|Du|Dein|Deine|Deinen|Deinem|Deiner|"
                r"hast|bist|kannst|musst|darfst|siehst|"
                r"Vervollständige|Vergleiche|Schreibe|Schreib|Gib|Nimm|Ändere|Wähle|Setze|Führe|Öffne|Verwende|"
                r"Ersetze|Berechne|Prüfe|Probiere|Wechsle|Verschiebe|Zeichne|Bewege|Geh|Entwirf|Skaliere)\b")


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
    assert not DU.search("Vervollständigen Sie `h(x)`; geben Sie ein Tupel zurück; Ihre Werte")
