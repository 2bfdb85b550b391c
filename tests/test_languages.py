"""English or German: how `make lab` chooses the language, and JupyterLab's German interface (issue 14)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def make_lab(**env):
    """The commands `make lab` would run (make -n) under the environment variables ``env``."""
    environ = {k: v for k, v in os.environ.items() if k not in ("LANG", "LC_ALL", "MAKEFLAGS", "MFLAGS")}
    environ.update(env)
    out = subprocess.run(["make", "-n", "lab"], cwd=ROOT, env=environ, capture_output=True, text=True, check=True)
    return out.stdout


@pytest.mark.parametrize("lang, expected", [("de", "de"), ("de_DE.UTF-8", "de"), ("de_AT", "de"), ("C.UTF-8", "en"),
                                            ("en_GB.UTF-8", "en"), ("fr_FR.UTF-8", "en"), ("", "en")])
def test_make_lab_follows_the_system_locale(lang, expected):
    out = make_lab(LANG=lang)
    assert f"jupyter/settings.py {expected} .venv/share/jupyter/lab/settings/overrides.json" in out
    assert f"LAB_LANG={expected} " in out and f"--notebook-dir=exercises/{expected} " in out


def test_make_lab_lang_on_the_command_line_wins():
    environ = {k: v for k, v in os.environ.items() if k not in ("MAKEFLAGS", "MFLAGS")}
    environ["LANG"] = "C.UTF-8"
    out = subprocess.run(["make", "-n", "lab", "LANG=de"], cwd=ROOT, env=environ, capture_output=True, text=True,
                         check=True).stdout
    assert "--notebook-dir=exercises/de " in out and "LAB_LANG=de " in out


@pytest.mark.parametrize("lang, locale", [("de", "de_DE"), ("en", "en")])
def test_the_settings_override_keeps_the_project_settings_and_adds_the_language(tmp_path, lang, locale):
    out = tmp_path / "share" / "overrides.json"
    subprocess.run([sys.executable, str(ROOT / "jupyter" / "settings.py"), lang, str(out)], check=True)
    settings = json.loads(out.read_text())
    from lab.teaching.course.start import OVERRIDES

    assert settings == {**OVERRIDES, "@jupyterlab/translation-extension:plugin": {"locale": locale}}
    assert settings["@jupyterlab/apputils-extension:kernels-settings"] == {"commsOverSubshells": "disabled"}


def test_the_settings_script_refuses_other_languages(tmp_path):
    result = subprocess.run([sys.executable, str(ROOT / "jupyter" / "settings.py"), "fr", str(tmp_path / "o.json")],
                            capture_output=True, text=True, check=False)
    assert result.returncode != 0 and "language must be one of de, en; got 'fr'" in result.stderr


def test_jupyterlab_has_the_german_language_pack():
    from jupyterlab_server.translation_utils import get_language_pack, get_language_packs

    packs, _ = get_language_packs("de_DE")
    assert packs["de_DE"]["nativeName"].startswith("Deutsch")
    strings, _ = get_language_pack("de_DE")
    assert strings["jupyterlab"]["Help"] == ["Hilfe"]  # the Help menu in JupyterLab's own catalogue
