"""Sphinx configuration of curvature-lab's documentation site: ``make site`` builds it into ``docs/_build/html`` (English)
and ``docs/_build/html/de`` (German), offline: MathJax from npm (``mathjax@3``'s ``es5/``), nothing from a CDN."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path.insert(0, str(ROOT))
os.environ.setdefault("PYVISTA_OFF_SCREEN", "true")
os.environ.setdefault("LAB_STATIC", "1")  # executed examples draw static pictures

project = "curvature-lab"
author = "the curvature-lab developers"
copyright = "2026, the curvature-lab developers"
release = version = "0.1.0"

extensions = ["myst_nb", "numpydoc", "sphinx.ext.autosummary", "sphinx.ext.autodoc", "sphinx.ext.mathjax",
              "sphinx_design", "sphinx_copybutton"]
# No sphinx.ext.viewcode or linkcode: five documented functions are the withheld reference answers of graded tasks,
# and a link to their source would publish their bodies (tests/test_docs.py checks that no _modules/ is built).

exclude_patterns = ["_build", "_templates", "**.ipynb_checkpoints", "locales"]
source_suffix = {".md": "myst-nb", ".rst": "restructuredtext"}
myst_enable_extensions = ["dollarmath", "amsmath", "colon_fence", "deflist"]
myst_heading_anchors = 3
myst_dmath_double_inline = True
nb_execution_mode = "force"  # the examples run at every build; a failing cell fails the build
nb_execution_raise_on_error = True
nb_execution_show_tb = True
nb_execution_timeout = 300
nb_execution_excludepatterns = ["students/*", "instructors/*", "library/*", "developers/*", "start/*", "theory/*",
                                "index.md", "bibliography.md", "gallery/*", "api/*"]

autosummary_generate = True
autodoc_default_options = {"members": False}
numpydoc_show_class_members = False
numpydoc_validation_checks = set()
numpydoc_xref_param_type = False

language = "en"
locale_dirs = ["locales/"]
gettext_compact = False
gettext_uuid = False

html_theme = "pydata_sphinx_theme"
html_title = "curvature-lab"
html_static_path = ["_build/mathjax"]
html_theme_options = {
    "navigation_with_keys": False,
    "show_toc_level": 2,
    "footer_start": ["copyright"],
    "footer_end": [],
    "secondary_sidebar_items": ["page-toc"],
    "navbar_end": ["language-switch", "theme-switcher"],  # every page links the same page in the other language
}
templates_path = ["_templates"]
html_last_updated_fmt = None
html_context = {"default_mode": "light"}
html_show_sourcelink = False
html_copy_source = False
# MathJax from the lab's own copy (npm's mathjax@3, es5/): a student's offline laptop or a hub without internet
mathjax_path = "mathjax/tex-chtml.js"
mathjax3_config = {"tex": {"tags": "ams"}}
suppress_warnings = ["mystnb.unknown_mime_type"]


def _mathjax():
    """Copy MathJax 3's es5/ (npm) to _build/mathjax/mathjax, the one place the pages load it from."""
    source = Path(os.environ.get("LAB_MATHJAX", ROOT / ".venv" / "node" / "node_modules" / "mathjax" / "es5"))
    target = HERE / "_build" / "mathjax" / "mathjax"
    if not (source / "tex-chtml.js").is_file():
        raise RuntimeError(f"MathJax 3 is missing at {source}: run make site (it installs npm's mathjax@3), or set "
                           "LAB_MATHJAX to a folder with tex-chtml.js")
    if not (target / "tex-chtml.js").is_file():
        shutil.copytree(source, target, dirs_exist_ok=True)


def _withheld_docstrings(app, what, name, obj, options, lines):
    """A withheld reference implementation shows only the first paragraph of its docstring (as the hand-out does):
    the rest may discuss what the student writes."""
    from lab.teaching.sandbox.withhold import withheld

    if name in _WITHHELD.setdefault("names", set(withheld())) and "" in lines:
        del lines[lines.index(""):]


_WITHHELD = {}


def _gallery():
    """docs/gallery/index.md from lab.view.gallery.PICTURES: one caption per picture, the command under it."""
    from lab.view.gallery import PICTURES, SIZE

    intro = ("Each picture is one `curvature-lab render` call, written under it; `make docs` redraws them all "
             "(`python -m lab.view.gallery`).")
    lines = ["# Gallery", "", intro, ""]
    for name, options, caption in PICTURES:
        rel = name[len("gallery/"):] if name.startswith("gallery/") else f"../{name}"
        lines += [f"```{{figure}} {rel}", f":alt: {caption}", "", caption, "```", "", "```bash",
                  f"curvature-lab render {options} --window-size {SIZE} -o docs/{name}", "```", ""]
    text = "\n".join(lines)
    path = HERE / "gallery" / "index.md"
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


def _cli_help(app):
    """Each command's --help, captured at build time (library/cli.md includes them)."""
    from lab.cli import VERBS

    out = HERE / "_build" / "help"
    out.mkdir(parents=True, exist_ok=True)
    for verb in ["render", *VERBS]:
        done = subprocess.run([sys.executable, "-m", "lab.cli", verb, "--help"], capture_output=True, text=True,
                              check=True, env={**os.environ, "LAB_LANG": app.config.language or "en", "COLUMNS": "100"})
        text = done.stdout
        path = out / f"{verb}.txt"
        if not path.is_file() or path.read_text() != text:
            path.write_text(text)


#: The API reference's sections: a layer, what it holds, and the modules whose public names it lists.
API = (("geometry", "Formulas on arrays: curvature, directions, colour maps, derivatives, validation."),
       ("model", "The objects a student handles: surfaces and the practical's patch collection."),
       ("interrogation", "Focal surfaces, reflection lines, geodesics, trimming, continuity, combs, umbilics, CAD parts."),
       ("view", "Pictures and the live explorers."),
       ("i18n", "The language of the lab's messages."),
       ("teaching", "Exercise mode, a student's own surface, and the marking panel."))


def _api():
    """docs/api/index.md: the public names of ``lab`` (``lab.__all__``), layer by layer, one autosummary each."""
    import lab

    by_layer = {}
    for module, names in lab._NAMES.items():
        by_layer.setdefault(module.split(".")[1], []).extend(f"{module}.{name}" for name in names)
    modules = ", ".join(f"`lab.{m}`" for m in sorted(lab.MODULES))
    intro = ("Every public function and class of `lab` (`import lab`; `lab.<name>`), by the layer that defines it. "
             f"The layers' modules are reached by short names too: {modules}; the formulas' modules are shown on "
             "the theory pages.")
    lines = ["# API reference", "", intro, ""]
    for layer, what in API:
        lines += [f"## {layer}", "", what, "", "```{eval-rst}", ".. autosummary::", "   :toctree: generated", ""]
        lines += [f"   {name}" for name in sorted(by_layer.get(layer, []), key=lambda q: q.rsplit('.', 1)[1].lower())]
        lines += ["```", ""]
    text = "\n".join(lines)
    path = HERE / "api" / "index.md"
    path.parent.mkdir(exist_ok=True)
    if not path.is_file() or path.read_text() != text:
        path.write_text(text)


# Generated pages and the static MathJax exist before Sphinx looks for sources (autosummary's stubs come from the
# pages found then) and checks html_static_path: here, when the configuration is read.
_api()
_gallery()
_mathjax()


def _theme_in_language(app, config):
    """The theme's own words that pydata-sphinx-theme does not translate: its header's "More" menu."""
    config.html_theme_options["header_dropdown_text"] = {"de": "Mehr"}.get(config.language, "More")


def setup(app):
    app.connect("config-inited", _theme_in_language)
    app.connect("builder-inited", _cli_help)
    app.connect("autodoc-process-docstring", _withheld_docstrings)
