# Two commands: `make lab` (set up, open JupyterLab on exercises/) and `make test` (set up, run every test).
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
STAMP  := $(VENV)/.installed
APT_PACKAGES := libegl1 libgl1-mesa-dri
TEST_APT_PACKAGES := chromium
PORT ?= 8888

.PHONY: lab test setup system-deps venv clean benchmarks exercises docs

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

$(STAMP): pyproject.toml jupyter/overrides.json | $(PY)
	$(PIP) install -q -e ".[test]"
	mkdir -p $(dir $(OVERRIDES)) && cp jupyter/overrides.json $(OVERRIDES)
	@touch $(STAMP)

setup: system-deps $(STAMP)

lab: setup
	$(PY) -m jupyter lab --notebook-dir=exercises --port=$(PORT) $(if $(DISPLAY),,--no-browser) \
	  $(if $(filter 0,$(shell id -u)),--allow-root,)

test: EXTRA_APT = $(TEST_APT_PACKAGES)
test: setup
	$(PY) -m pytest -n 2

# Regenerate exercises/ from solutions/ (refuses to overwrite exercises a student has edited).
exercises: setup
	$(PY) -m lab.notebooks

# Redraw every picture in docs/ (README pictures and docs/gallery/), deterministically.
docs: setup
	$(PY) -m lab.view.gallery

benchmarks: setup
	$(PY) benchmarks/curvature.py

clean:
	rm -rf $(VENV) .pytest_cache
