"""Write JupyterLab's settings override: jupyter/overrides.json plus the interface language.

    python jupyter/settings.py de .venv/share/jupyter/lab/settings/overrides.json

``de`` selects the German language pack (jupyterlab-language-pack-de-de), ``en`` JupyterLab's own English
(the ``@jupyterlab/translation-extension:plugin`` setting ``locale``).  ``make lab`` and ``make test`` call it.
"""

import json
import sys
from pathlib import Path

LOCALES = {"de": "de_DE", "en": "en"}


def main(lang, out):
    if lang not in LOCALES:
        raise SystemExit(f"language must be one of {', '.join(LOCALES)}; got {lang!r}")
    settings = json.loads(Path(__file__).with_name("overrides.json").read_text())
    settings["@jupyterlab/translation-extension:plugin"] = {"locale": LOCALES[lang]}
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(settings, indent=2) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
