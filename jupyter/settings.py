"""Write JupyterLab's settings override: the settings the lab needs plus the interface language.

    python jupyter/settings.py de .venv/share/jupyter/lab/settings/overrides.json

``de`` selects the German language pack (jupyterlab-language-pack-de-de), ``en`` JupyterLab's own English
(the ``@jupyterlab/translation-extension:plugin`` setting ``locale``).  ``make lab``, ``make test`` and the hub's
image call it; ``curvature-lab start`` writes the same settings (``lab.teaching.course.start.jupyterlab_settings``,
the one place they are defined).
"""

import json
import sys
from pathlib import Path

from lab.teaching.course.start import jupyterlab_settings


def main(lang, out):
    try:
        settings = jupyterlab_settings(lang)
    except ValueError as exc:
        raise SystemExit(str(exc)) from None
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(json.dumps(settings, indent=2) + "\n")


if __name__ == "__main__":
    main(*sys.argv[1:])
