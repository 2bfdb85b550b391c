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

.PHONY: lab setup system-deps clean

# Debian packages that offscreen rendering (EGL) needs, OpenCASCADE's sample parts (occt-misc, for lab.models) and
# Chromium for the browser tests; installed only when missing.  Without apt-get it says what to get instead.
system-deps:
	@if ! command -v dpkg >/dev/null || ! command -v apt-get >/dev/null; then \
	  echo "no apt-get: install EGL (libegl1, Mesa) yourself; OpenCASCADE's sample parts (lab.models.wing() ...) are"; \
	  echo "in Debian's occt-misc or OCCT's source tree (data/occ, data/iges, data/step): set LAB_OCC_DATA to that folder"; \
	  exit 0; fi; \
	missing=""; for p in $(APT_PACKAGES) $(EXTRA_APT); do dpkg -s $$p >/dev/null 2>&1 || missing="$$missing $$p"; done; \
	if [ -n "$$missing" ]; then \
	  echo "installing system packages:$$missing"; \
	  SUDO=""; [ "$$(id -u)" = 0 ] || SUDO="sudo"; \
	  $$SUDO apt-get update -qq && $$SUDO apt-get install -y -qq --no-install-recommends $$missing; \
	fi

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -q --upgrade pip

OVERRIDES := $(VENV)/share/jupyter/lab/settings/overrides.json

# What the lab needs, with the extra "cad" (OpenCASCADE, rhino3dm, pyiges: lab.read of STEP/IGES/BREP/3dm files and
# lab.models); the course repository's test set-up adds the test tools.  PIP_CONSTRAINTS: the course repository
# installs the versions deploy/constraints.txt pins (those the tests ran and the hub image installs), not whatever
# PyPI released since; the students' hand-out leaves it empty.
PIP_CONSTRAINTS ?=
$(STAMP): pyproject.toml jupyter/overrides.json jupyter/settings.py | $(PY)
	$(PIP) install -q $(PIP_CONSTRAINTS) -e ".[cad]"
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	@touch $(STAMP)

setup: system-deps $(STAMP)

# JupyterLab's settings override (jupyter/overrides.json) with the interface language, then JupyterLab on exercises/<lang>.
lab: setup
	$(PY) jupyter/settings.py $(LAB_LANGUAGE) $(OVERRIDES)
	LAB_LANG=$(LAB_LANGUAGE) $(PY) -m jupyter lab --notebook-dir=exercises/$(LAB_LANGUAGE) --port=$(PORT) \
	  $(if $(DISPLAY),,--no-browser) $(if $(filter 0,$(shell id -u)),--allow-root,)

clean:
	rm -rf $(VENV) .pytest_cache
