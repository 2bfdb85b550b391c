# The set-up and `make lab`: included by the course repository's Makefile and by the students' hand-out
# (`curvature-lab release`), so both set up the same way.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip
STAMP  := $(VENV)/.installed
APT_PACKAGES := libegl1 libgl1-mesa-dri occt-misc
PORT ?= 8888
# The lab's language: German with `make lab LANG=de` or a German system locale (LANG=de_DE.UTF-8 …), English otherwise.
# It selects exercises/<lang>, JupyterLab's interface language and LAB_LANG (checks, hints, labels) for the kernels.
LAB_LANGUAGE := $(if $(filter de%,$(LANG)),de,en)

.PHONY: lab setup system-deps python-check clean

# Python 3.10 or newer (pyproject.toml's requires-python), checked first: pip's own message comes late and a .venv
# made with an older Python keeps failing until it is removed.
python-check:
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 10))' 2>/dev/null || { \
	  echo "curvature-lab needs Python 3.10 or newer; $(PYTHON) is $$($(PYTHON) --version 2>/dev/null || echo "not found")."; \
	  echo "Install a newer Python, then: make clean; make lab PYTHON=python3.12 (or whichever you installed)"; \
	  exit 1; }
	@if [ -x $(PY) ] && ! $(PY) -c 'import sys; sys.exit(sys.version_info < (3, 10))'; then \
	  echo "the .venv was made with $$($(PY) --version 2>&1), older than 3.10: run make clean, then make lab again"; \
	  exit 1; fi

# Debian packages that offscreen rendering (EGL) needs, OpenCASCADE's sample parts (occt-misc, for lab.models) and
# Chromium for the browser tests; installed only when missing.  Without apt-get it says what to get instead.
system-deps:
	@if ! command -v dpkg >/dev/null || ! command -v apt-get >/dev/null; then \
	  if [ "$$(uname)" = Darwin ]; then \
	    echo "macOS: pictures use VTK's own window (no EGL needed)."; \
	  else \
	    echo "no apt-get: offscreen pictures need EGL (libEGL and Mesa from your distribution) or a desktop session"; \
	  fi; \
	  echo "OpenCASCADE's sample parts (lab.models.wing() ...) are in OCCT's source tree (data/occ, data/iges,"; \
	  echo "data/step): set LAB_OCC_DATA to that data folder (lab.models.teapot() needs none)"; \
	  exit 0; fi; \
	missing=""; for p in $(APT_PACKAGES) $(EXTRA_APT); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO="sudo"; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(PY): | python-check
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

OVERRIDES := $(VENV)/share/jupyter/lab/settings/overrides.json

# What the lab needs, with the extra "cad" (OpenCASCADE, rhino3dm, pyiges: lab.read of STEP/IGES/BREP/3dm files and
# lab.models); the course repository's test set-up adds the test tools.  PIP_CONSTRAINTS: the course repository
# installs the versions deploy/constraints.txt pins (those the tests ran and the hub image installs), not whatever
# PyPI released since; the students' hand-out leaves it empty.
PIP_CONSTRAINTS ?=
$(STAMP): pyproject.toml jupyter/settings.py | $(PY)
	$(PIP) install -q $(PIP_CONSTRAINTS) -e ".[cad]"
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	@touch $(STAMP)

setup: python-check system-deps $(STAMP)

# JupyterLab's settings override (jupyter/settings.py) with the interface language, then JupyterLab on exercises/<lang>.
lab: setup
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	LAB_LANG=$(LAB_LANGUAGE) $(PY) -m jupyter lab --notebook-dir=exercises/$(LAB_LANGUAGE) --port=$(PORT) \
	  $(if $(DISPLAY),,--no-browser) $(if $(filter 0,$(shell id -u)),--allow-root,)

clean:
	rm -rf $(VENV) .pytest_cache
