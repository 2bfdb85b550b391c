"""``curvature-lab start [DIR] [--lang de] [--no-browser] [--port N]``: the exercises on one's own laptop.

After ``pip install curvature-lab`` (no checkout, no make, no apt), ``start`` copies the exercise notebooks of the
chosen language into ``DIR`` (default ``./curvature-lab``) and opens JupyterLab there, with JupyterLab's interface in
that language and ``LAB_LANG`` set for the kernels (checks, hints, labels), and the settings the lab needs
(:data:`OVERRIDES`: widget callbacks on the kernel's main thread).  Run again, it brings new versions of the notebooks
but **never overwrites a notebook the student edited**: ``DIR/.curvature-lab.json`` records what it wrote; a notebook
that differs from that (the student's work) is kept and the new version goes beside it (``05_….2.ipynb``), as
``feedback`` does with a page a student edited.

The notebooks come from the installed package (the wheel carries ``exercises/en`` and ``exercises/de`` as
``lab/exercises``) or, in a checkout, from the repository's ``exercises/``.
"""

import argparse
import hashlib
import json
import os
import shutil
import sys
from pathlib import Path

from ... import library, repository
from ...i18n import LANGUAGES, _

__all__ = ["OVERRIDES", "StartError", "copy_exercises", "exercises_folder", "jupyterlab_settings", "main"]

#: JupyterLab settings the lab needs, whatever the language: comms on the kernel's main thread (a widget callback that
#: renders from a comm subshell kills the kernel: VTK's context belongs to the main thread), no news pop-ups.
OVERRIDES = {
    "@jupyterlab/apputils-extension:kernels-settings": {"commsOverSubshells": "disabled"},
    "@jupyterlab/apputils-extension:notification": {"checkForUpdates": False, "fetchNews": "false"},
}
#: JupyterLab's locale of each language of the lab.
LOCALES = {"de": "de_DE", "en": "en"}
#: What ``start`` records of the notebooks it wrote (their SHA-256), in the student's folder.
MANIFEST = ".curvature-lab.json"


class StartError(RuntimeError):
    """The exercises cannot be set up (none found, a folder in the way)."""


def jupyterlab_settings(lang):
    """JupyterLab's settings override for the lab in ``lang``: :data:`OVERRIDES` and the interface language."""
    if lang not in LOCALES:
        raise ValueError(f"language must be one of {', '.join(LOCALES)}; got {lang!r}")
    return {**OVERRIDES, "@jupyterlab/translation-extension:plugin": {"locale": LOCALES[lang]}}


def exercises_folder(lang):
    """The folder of the exercise notebooks in ``lang``: in the installed package, else in the course repository."""
    for base in (Path(library()) / "exercises", Path(repository()) / "exercises"):
        if (base / lang).is_dir() and any((base / lang).glob("[0-9][0-9]_*.ipynb")):
            return base / lang
    raise StartError(f"no exercise notebooks found (looked in {Path(library()) / 'exercises'} and "
                     f"{Path(repository()) / 'exercises'}): this installation of curvature-lab is incomplete; "
                     "reinstall it with pip install --force-reinstall curvature-lab")


def _sha(data):
    return hashlib.sha256(data).hexdigest()


def _beside(target):
    """A free name beside ``target``: ``name.2.ipynb``, ``name.3.ipynb`` …"""
    for k in range(2, 100):
        other = target.with_name(f"{target.stem}.{k}{target.suffix}")
        if not other.exists():
            return other
    raise StartError(f"{target}: {target.stem}.2{target.suffix} … .99{target.suffix} all exist; move some away")


def _write(path, data):
    tmp = path.with_name(f".{path.name}.tmp")
    tmp.write_bytes(data)
    os.replace(tmp, path)


def copy_exercises(source, dest):
    """Copy the notebooks of ``source`` into ``dest``; returns ``{name: what happened}`` (see the module docstring):
    ``"new"``, ``"unchanged"``, ``"updated"`` (the student had not changed it) or ``"kept: new version in NAME"``."""
    dest = Path(dest)
    if dest.exists() and not dest.is_dir():
        raise StartError(f"{dest} is a file, not a folder for the exercises")
    dest.mkdir(parents=True, exist_ok=True)
    manifest_path = dest / MANIFEST
    try:
        manifest = json.loads(manifest_path.read_text()) if manifest_path.is_file() else {}
    except (OSError, ValueError):
        manifest = {}
    done = {}
    for src in sorted(Path(source).glob("[0-9][0-9]_*.ipynb")):
        new, target = src.read_bytes(), dest / src.name
        if not target.exists():
            _write(target, new)
            done[src.name] = "new"
        elif (old := target.read_bytes()) == new:
            done[src.name] = "unchanged"
        elif _sha(old) == manifest.get(src.name):  # ours, as we wrote it: the student did not change it
            _write(target, new)
            done[src.name] = "updated"
        else:  # the student's work: kept; the new version beside it, once
            if any(p.read_bytes() == new for p in dest.glob(f"{target.stem}.*{target.suffix}") if p.is_file()):
                done[src.name] = "kept"
                continue
            other = _beside(target)
            _write(other, new)
            done[src.name] = f"kept: new version in {other.name}"
            continue
        manifest[src.name] = _sha(new)
    manifest_path.write_text(json.dumps(manifest, indent=1, sort_keys=True) + "\n")
    return done


def _settings_folder(dest, lang):
    """A JupyterLab app-settings folder for this folder's session: the environment's own (page_config.json …) with
    :func:`jupyterlab_settings` merged into its overrides."""
    folder = Path(dest) / ".jupyter" / "settings"
    folder.mkdir(parents=True, exist_ok=True)
    settings = {}
    try:
        from jupyterlab.commands import get_app_dir

        default = Path(get_app_dir()) / "settings"
        for name in ("page_config.json",):
            if (default / name).is_file():
                shutil.copy(default / name, folder / name)
        if (default / "overrides.json").is_file():
            settings = json.loads((default / "overrides.json").read_text())
    except (ImportError, OSError, ValueError):
        pass
    settings.update(jupyterlab_settings(lang))
    (folder / "overrides.json").write_text(json.dumps(settings, indent=2) + "\n")
    return folder


def _default_language():
    """German where the system says so (``LANG=de_DE.UTF-8`` …, as ``make lab``), English otherwise."""
    for name in ("LC_ALL", "LC_MESSAGES", "LANG"):
        value = os.environ.get(name, "")
        if value:
            return "de" if value.lower().startswith("de") else "en"
    return "en"


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="curvature-lab start",
        description=_("Copy the exercise notebooks into a folder and open JupyterLab there (self-study, after "
                      "pip install curvature-lab). A notebook you edited is never overwritten: a new version goes "
                      "beside it."))
    parser.add_argument("folder", nargs="?", default="curvature-lab",
                        help=_("folder for the notebooks (default: ./curvature-lab)"))
    parser.add_argument("--lang", choices=LANGUAGES, default=None,
                        help=_("language of the notebooks and of JupyterLab (default: the system's, else en)"))
    parser.add_argument("--no-browser", action="store_true", help=_("do not open a browser; print the address"))
    parser.add_argument("--port", type=int, default=None, help=_("port of JupyterLab (default: 8888 or the next free)"))
    parser.add_argument("--copy-only", action="store_true", help=_("copy the notebooks, do not start JupyterLab"))
    args = parser.parse_args(argv)
    lang = args.lang or _default_language()
    dest = Path(args.folder).resolve()
    try:
        done = copy_exercises(exercises_folder(lang), dest)
    except (StartError, OSError) as exc:
        print(f"curvature-lab start: error: {exc}", file=sys.stderr)
        return 2
    for name, what in done.items():
        if what.startswith("kept: "):
            print(_("{name}: you changed it, so it is kept; the new version is {other}").format(
                name=name, other=what.rpartition(" ")[2]), file=sys.stderr)
    print(_("{n} notebooks in {folder}").format(n=len(done), folder=dest), file=sys.stderr)
    if args.copy_only:
        return 0
    command = [sys.executable, "-m", "jupyter", "lab", f"--notebook-dir={dest}",
               f"--LabApp.app_settings_dir={_settings_folder(dest, lang)}"]
    if args.no_browser:
        command.append("--no-browser")
    if args.port is not None:
        command.append(f"--port={args.port}")
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        command.append("--allow-root")
    env = {**os.environ, "LAB_LANG": lang}
    import subprocess

    try:
        return subprocess.call(command, env=env, cwd=dest)
    except KeyboardInterrupt:
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
