# Two commands: `make lab` (set up, open JupyterLab on exercises/en or exercises/de) and `make test` (set up, run every test).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
STAMP  := $(VENV)/.installed
TEST_STAMP := $(VENV)/.installed-test
APT_PACKAGES := libegl1 libgl1-mesa-dri
TEST_APT_PACKAGES := chromium bubblewrap
PORT ?= 8888
# The lab's language: German with `make lab LANG=de` or a German system locale (LANG=de_DE.UTF-8 …), English otherwise.
# It selects exercises/<lang>, JupyterLab's interface language and LAB_LANG (checks, hints, labels) for the kernels.
LAB_LANGUAGE := $(if $(filter de%,$(LANG)),de,en)

.PHONY: lab test setup system-deps venv clean benchmarks exercises translations docs

# Debian packages that offscreen rendering (EGL) needs (and Chromium for the browser tests); installed only when missing.
system-deps:
	@missing=""; for p in $(APT_PACKAGES) $(EXTRA_APT); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO="sudo"; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

OVERRIDES := $(VENV)/share/jupyter/lab/settings/overrides.json

# A student's set-up installs what the lab needs; the test set-up adds the test tools (pytest, Playwright,
# JupyterHub, potpourri3d …) and configurable-http-proxy (npm) for the JupyterHub test.
$(STAMP): pyproject.toml jupyter/overrides.json jupyter/settings.py | $(PY)
	$(PIP) install -q -e .
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	@touch $(STAMP)

$(TEST_STAMP): $(STAMP)
	$(PIP) install -q -e ".[test]"
	@command -v npm >/dev/null && (mkdir -p $(VENV)/node && cd $(VENV)/node && \
	  npm install --silent --no-fund --no-audit configurable-http-proxy@5) || echo "npm missing: the JupyterHub test will be skipped"
	@touch $(TEST_STAMP)

setup: system-deps $(STAMP)

# JupyterLab's settings override (jupyter/overrides.json) with the interface language, then JupyterLab on exercises/<lang>.
lab: setup
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	LAB_LANG=$(LAB_LANGUAGE) $(PY) -m jupyter lab --notebook-dir=exercises/$(LAB_LANGUAGE) --port=$(PORT) \
	  $(if $(DISPLAY),,--no-browser) $(if $(filter 0,$(shell id -u)),--allow-root,)

test: EXTRA_APT = $(TEST_APT_PACKAGES)
test: system-deps $(TEST_STAMP)
	$(PY) jupyter/settings.py en $(OVERRIDES)
	$(PY) -m pytest -n 2 --dist loadgroup --durations=12

# Regenerate exercises/en, exercises/de, solutions/en and solutions/de from the bilingual sources solutions/NN_*.ipynb
# (refuses to overwrite notebooks edited since they were generated, e.g. a student's exercise).
exercises: setup
	$(PY) -m lab.teaching.notebooks

# Messages: extract the marked strings (Babel), merge them into the German catalogue, compile it.
# A test fails when a message has no German text or the compiled catalogue is stale.
CATALOGUE := lab/i18n/locale/de/LC_MESSAGES/lab.po
translations: $(TEST_STAMP)
	$(VENV)/bin/pybabel extract -k _ -k N_ --no-location --sort-output --project curvature-lab -o $(VENV)/lab.pot lab
	$(VENV)/bin/pybabel update -i $(VENV)/lab.pot -d lab/i18n/locale -l de -D lab --no-fuzzy-matching --ignore-obsolete
	$(VENV)/bin/pybabel compile -d lab/i18n/locale -l de -D lab --statistics

# Redraw every picture in docs/ (README pictures and docs/gallery/), deterministically.
docs: setup
	$(PY) -m lab.view.gallery

benchmarks: system-deps $(TEST_STAMP)
	$(PY) benchmarks/curvature.py

clean:
	rm -rf $(VENV) .pytest_cache
