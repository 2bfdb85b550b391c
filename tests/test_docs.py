"""The documentation site as a reader meets it: every page of both languages served on 127.0.0.1 in headless Chromium
with every other request refused, and the site's promises (no source links, no solution, offline MathJax, German
catalogues complete, the sources cited as papers, a short README).

``make site`` builds the site (``make test`` does it first); without a built site the browser tests are skipped.
"""

import contextlib
import functools
import html
import http.server
import re
import subprocess
import threading
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
SITE = ROOT / "docs" / "_build" / "html"
LOCALES = ROOT / "docs" / "locales" / "de" / "LC_MESSAGES"
#: The pages translated into German (the student- and instructor-facing ones); the others stay English there.
GERMAN = ("index", "start", "students", "theory", "instructors/index")

built = pytest.mark.skipif(not (SITE / "index.html").is_file() or not (SITE / "de" / "index.html").is_file(),
                           reason="the site is not built (make site)")
pytestmark = pytest.mark.xdist_group("browser")


def _pages(root):
    """The pages of one language's build (not its static files' own HTML, not the other language)."""
    return sorted(p for p in root.rglob("*.html") if p.relative_to(root).parts[0] not in ("_static", "_images")
                  and (p.relative_to(root).parts[0] != "de" or root.name == "de"))


@contextlib.contextmanager
def _serving(root):
    """The folder ``root`` over HTTP on 127.0.0.1 (a thread of this process); yields the base address."""
    handler = functools.partial(_Quiet, directory=str(root))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def visits():
    """``{language: {page: what the browser saw}}`` for every page of both builds."""
    from playwright.sync_api import sync_playwright

    from tests.browser_support import CHROMIUM, CHROMIUM_ARGS

    found = {}
    with _serving(SITE) as base, sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1200, "height": 900})
        outside, errors = [], []

        def route(r):
            if r.request.url.startswith(base) or r.request.url.startswith("data:"):
                r.continue_()
            else:
                outside.append(r.request.url)
                r.abort()

        page.route("**/*", route)
        page.on("console", lambda m: errors.append(m.text) if m.type == "error" else None)
        page.on("pageerror", lambda e: errors.append(str(e)))
        for lang, root in (("en", SITE), ("de", SITE / "de")):
            seen = found.setdefault(lang, {})
            for path in _pages(root):
                rel = path.relative_to(SITE).as_posix()
                outside.clear()
                errors.clear()
                page.goto(f"{base}/{rel}", wait_until="load")
                page.evaluate("() => window.MathJax && MathJax.startup ? MathJax.startup.promise : null")
                seen[rel] = page.evaluate("""() => ({
                    math: document.querySelectorAll('.math').length,
                    typeset: [...document.querySelectorAll('.math')].filter(m => m.querySelector('mjx-container')).length,
                    images: [...document.images].map(i => [i.getAttribute('src'), i.complete && i.naturalWidth > 0]),
                    lang: document.documentElement.lang,
                })""")
                seen[rel]["outside"], seen[rel]["errors"] = list(outside), [e for e in errors if "favicon" not in e]
        browser.close()
    return found


@built
@pytest.mark.parametrize("lang", ["en", "de"])
def test_every_page_is_complete_and_offline(visits, lang):
    pages = visits[lang]
    assert len(pages) > 60, len(pages)
    assert {p: v["outside"] for p, v in pages.items() if v["outside"]} == {}  # nothing left the machine
    assert {p: v["errors"] for p, v in pages.items() if v["errors"]} == {}  # no console error
    assert {p: (v["typeset"], v["math"]) for p, v in pages.items() if v["typeset"] != v["math"]} == {}
    assert sum(v["math"] for v in pages.values()) > 50  # the theory pages have formulas, all typeset by MathJax
    broken = {p: [src for src, ok in v["images"] if not ok] for p, v in pages.items()}
    assert {p: b for p, b in broken.items() if b} == {}
    assert sum(len(v["images"]) for v in pages.values()) > 15  # the gallery and the examples' pictures
    assert {v["lang"] for v in pages.values()} == {lang}


@built
def test_each_landing_page_links_the_other_language():
    english = (SITE / "index.html").read_text()
    german = (SITE / "de" / "index.html").read_text()
    assert 'href="de/index.html"' in english and 'href="../index.html"' in german
    assert "Studierende" in german and "Theorie" in german  # the German landing page is German
    menu = re.compile(r'class="btn dropdown-toggle nav-item"[^>]*>\s*([^<\s]+)')  # the header's overflow menu
    assert menu.findall(english) == ["More"] and menu.findall(german) == ["Mehr"]  # the theme does not translate it


@built
def test_every_page_links_the_same_page_in_the_other_language():
    """The navigation bar's "Deutsch" / "English" leads to the same page in the other build, on every page."""
    link = re.compile(r'class="nav-link lab-language" href="([^"]+)"')
    for root, other in ((SITE, "Deutsch"), (SITE / "de", "English")):
        for page in _pages(root):
            text = page.read_text()
            found = link.findall(text)
            assert found and f">{other}</a>" in text, page
            target = (page.parent / found[0]).resolve()
            twin = SITE / page.relative_to(root) if root.name == "de" else SITE / "de" / page.relative_to(root)
            assert target == twin.resolve() and target.is_file(), (page, found[0])


@built
def test_no_source_link_and_no_line_of_a_solution():
    """Five documented functions are the withheld reference answers of graded tasks: no page links their source, and
    no text of the site holds a line of a solution (their docstrings show only their first paragraph)."""
    from lab.teaching.course import release

    assert not list(SITE.rglob("_modules")) and not [p for p in SITE.rglob("_sources/**/*") if p.is_file()]
    lines = release.solution_lines()
    assert len(lines) > 100
    hits = []
    for path in SITE.rglob("*.html"):
        text = html.unescape(re.sub(r"<[^>]+>", "", path.read_text()))
        squeezed = re.sub(r"\s+", "", text)
        hits += [(path.relative_to(SITE).as_posix(), nb, line) for key, (nb, line) in lines.items() if key in squeezed]
    assert hits == []


def test_every_command_has_its_help_on_the_cli_page():
    from lab.cli import VERBS

    page = (ROOT / "docs" / "library" / "cli.md").read_text()
    assert [v for v in ["render", *VERBS] if f"../_build/help/{v}.txt" not in page] == []


@built
def test_mathjax_is_the_sites_own():
    page = (SITE / "theory" / "curvature.html").read_text()
    assert re.search(r'<script[^>]+src="\.\./_static/mathjax/tex-chtml\.js', page)
    assert (SITE / "_static" / "mathjax" / "tex-chtml.js").is_file()
    assert "cdn.jsdelivr" not in page and "https://" not in re.sub(r'href="https://[^"]*"', "", page).split("<body")[0]


def test_the_german_catalogues_are_complete():
    """An untranslated paragraph would appear in English in the German build without a warning."""
    from babel.messages.pofile import read_po

    catalogues = [p for p in LOCALES.rglob("*.po")
                  if any(p.relative_to(LOCALES).with_suffix("").as_posix().startswith(g) for g in GERMAN)]
    assert len(catalogues) >= 15
    missing = {}
    for path in catalogues:
        with open(path, "rb") as fh:
            bad = [m.id[:60] for m in read_po(fh) if m.id and (not m.string or m.fuzzy)]
        if bad:
            missing[path.relative_to(LOCALES).as_posix()] = bad
    assert missing == {}


def test_the_sources_are_cited_as_papers_everywhere():
    """No file of the repository cites the developers' private copies of the papers or their design notes."""
    found = subprocess.run(["git", "grep", "-n", "-I", "-e", "seeds" + "/", "-e", "DESIGN" + ".md"], cwd=ROOT,
                           capture_output=True, text=True, check=False).stdout
    assert found == ""
    bibliography = (ROOT / "docs" / "bibliography.md").read_text()
    for source in ("Versuch 6: Krümmungsvisualisierung", "Dill", "Choi", "Puig-Pey", "The NURBS Book", "Klass",
                   "Hagen", "Meyer et al. 2003", "Borrelli"):
        assert source in bibliography


def test_the_readme_is_a_front_door():
    readme = (ROOT / "README.md").read_text()
    assert len(readme.splitlines()) <= 150
    from lab.view.gallery import PICTURES

    captions = {name: caption for name, _options, caption in PICTURES}
    for name in ("practical_gaussian_linear.png", "practical_gaussian_signed_log.png"):
        assert f'src="docs/{name}"' in readme
        assert " ".join(captions[name].split()) in " ".join(readme.split())  # one caption, the gallery's
