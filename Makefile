# Two commands: `make lab` (set up, open JupyterLab on exercises/en or exercises/de) and `make test` (set up, run every test).
# The set-up and `make lab` are in jupyter/setup.mk, which the students' hand-out (`curvature-lab release`) uses too.
# The tests run the versions the hub image pins (deploy/constraints.txt; tests/test_deploy.py checks that they are
# all pinned): a package released on PyPI since does not change what CI tests.
PIP_CONSTRAINTS := -c deploy/constraints.txt
include jupyter/setup.mk

TEST_STAMP := $(VENV)/.installed-test
# Chromium for the browser tests, bubblewrap and libseccomp for the grader's sandbox (its syscall filter), geomview
# and Xvfb for the test that Debian's geomview shows the practical's CBEZ333 export (tests/test_geomview.py).
TEST_APT_PACKAGES := chromium bubblewrap libseccomp2 geomview xvfb

.PHONY: test benchmarks exercises translations docs site site-po

# The test set-up adds the test tools (pytest, Playwright, JupyterHub, potpourri3d …) and configurable-http-proxy
# (npm) for the JupyterHub test.
$(TEST_STAMP): $(STAMP)
	$(PIP) install -q $(PIP_CONSTRAINTS) -e ".[test]"
	@command -v npm >/dev/null && (mkdir -p $(VENV)/node && cd $(VENV)/node && \
	  npm install --silent --no-fund --no-audit configurable-http-proxy@5) || echo "npm missing: the JupyterHub test will be skipped"
	@touch $(TEST_STAMP)

test: EXTRA_APT = $(TEST_APT_PACKAGES)
test: system-deps $(TEST_STAMP) site
	$(VENV)/bin/ruff check .
	$(PY) jupyter/settings.py en $(OVERRIDES)
	$(PY) -m pytest -n 2 --dist loadgroup --durations=12

# Regenerate exercises/en, exercises/de, solutions/en and solutions/de from the bilingual sources solutions/NN_*.ipynb
# (refuses to overwrite notebooks edited since they were generated, e.g. a student's exercise).
exercises: setup
	$(PY) -m lab.teaching.course.exercises

# Messages: extract the marked strings (Babel), merge them into the German catalogue, compile it.
# A test fails when a message has no German text or the compiled catalogue is stale.
CATALOGUE := lab/i18n/locale/de/LC_MESSAGES/lab.po
translations: $(TEST_STAMP)
	$(VENV)/bin/pybabel extract -k _ -k N_ --no-location --sort-output --project curvature-lab -o $(VENV)/lab.pot lab
	$(VENV)/bin/pybabel update -i $(VENV)/lab.pot -d lab/i18n/locale -l de -D lab --no-fuzzy-matching --ignore-obsolete -w 120
	$(VENV)/bin/pybabel compile -d lab/i18n/locale -l de -D lab --statistics

# Redraw every picture in docs/ (README pictures and docs/gallery/), deterministically.
docs: setup
	$(PY) -m lab.view.gallery

# The documentation site, both languages, offline (MathJax from npm), warnings are errors: docs/_build/html and
# docs/_build/html/de.  The German catalogues are docs/locales/de (make site-po after changing an English page).
DOCS_STAMP := $(VENV)/.installed-docs
MATHJAX := $(VENV)/node/node_modules/mathjax/es5/tex-chtml.js
SPHINX := $(VENV)/bin/sphinx-build -W --keep-going -q
$(DOCS_STAMP): $(STAMP)
	$(PIP) install -q $(PIP_CONSTRAINTS) -e ".[docs]"
	@touch $(DOCS_STAMP)
$(MATHJAX):
	mkdir -p $(VENV)/node && cd $(VENV)/node && npm install --silent --no-fund --no-audit mathjax@3
site: $(DOCS_STAMP) $(MATHJAX)
	rm -rf docs/_build/html docs/_build/doctrees
	$(SPHINX) -b html -d docs/_build/doctrees docs docs/_build/html
	$(SPHINX) -b html -d docs/_build/doctrees-de -D language=de -t de docs docs/_build/html/de
site-po: $(DOCS_STAMP) $(MATHJAX)
	$(VENV)/bin/sphinx-build -q -b gettext docs docs/_build/gettext
	$(VENV)/bin/sphinx-intl update -p docs/_build/gettext -l de -d docs/locales

benchmarks: system-deps $(TEST_STAMP)
	$(PY) benchmarks/curvature.py
