"""The fuzzer's command lines (issue 35): ``curvature-lab render`` with every option, and each course verb's
``main(argv)`` with the options its own parser declares (read from the parser, so a new option is fuzzed without
a change here).  Every file a command reads or writes is in the fuzzer's scratch folder, which is also the working
directory during the call; ``start`` does not start JupyterLab (``subprocess.call`` is replaced)."""

import argparse
import contextlib
import os
import shutil
import subprocess
from unittest import mock

from hypothesis import strategies as st

import lab.cli

from .fuzz_targets import Target, scratch

#: Values tried for any option: numbers as text at the edges, junk, paths.
VALUES = ["0", "1", "2", "-1", "-5", "0.5", "nan", "inf", "-inf", "1e308", "1e999", "half", "", "9" * 400, "2.5",
          "1,2", "a,b", "x" * 300, "64x48", "0x0", "-60,35", "2026-12-15T23:59", "not-a-date", "\u00e4\u00f6\u00fc"]
PATHS = ["empty", "junk.step", "empty.igs", "list.ipynb", "junk.ipynb", "roster.csv", "missing/x", "new", "deadline.txt"]

RENDER = {
    "--surface": ["torus", "plane", "sphere", "practical", "cone", "nope", ""],
    "--curvature": ["gaussian", "mean", "k1", "strain-energy", "K"],
    "--color-map": ["linear", "cut", "classification", "dill", "symmetric", "signed-log-vik", "nope"],
    "--depth": ["0", "1", "2", "3", "8", "9", "-1", "1000", "9" * 30, "half", "2.5"],
    "--resolution": ["1", "2", "0", "-3", "200", "100000", "half"],
    "--window-size": ["64x48", "1x1", "100000x100000", "axb", "64x", "-64x48"],
    "--vmin": ["-1", "0", "1", "-5", "nan", "inf", "-inf", "1e308", "-1e308", "half"],
    "--vmax": ["-1", "0", "1", "-5", "nan", "inf", "1e308", "half", "1e999"],
    "--camera": ["-60,35", "inf,30", "0,100", "a,b", "30"],
    "--simulate": ["deuteranopia", "x"],
    "--title": ["T", ""],
    "--draft": ["0,0,1", "0,0,0", "nan,0,1", "a", "1e308,1e308,0", "1e-320,0,0"],
    "--min-radius": ["0.5", "-1", "0", "nan", "inf", "1e-320", "half", "1e308"],
    "--combs": ["0", "1", "3", "-1", "1000000", "half"],
    "--comb-scale": ["0.05", "-1", "nan", "inf", "1e308", "0"],
    "--comb-density": ["8", "0", "-1", "1000000000", "half"],
    "--file": [os.path.join("{scratch}", p) for p in ("junk.step", "empty.igs", "missing/x.step", "junk.bez", "text.3dm")],
    "--model": ["teapot", "nope"],
}
FLAGS = ["--edges", "--band-lines", "--legend", "--no-legend", "--quiet", "--no-title"]
OUTPUTS = ["out.vtp", "out.off", "out.bez", "out.vtk", "out.txt", "out", "missing/out.vtp", "out.png", "out.html"]


@st.composite
def render_argv(draw):
    root = scratch()
    argv = ["render"]
    for option in draw(st.lists(st.sampled_from(sorted(RENDER)), max_size=4, unique=True)):
        value = draw(st.sampled_from(RENDER[option]))
        argv += [option, value.replace("{scratch}", root)]
    argv += draw(st.lists(st.sampled_from(FLAGS), max_size=2, unique=True))
    # a picture costs a rendering: rarely, and small
    out = draw(st.sampled_from(OUTPUTS[:6] * 4 + OUTPUTS[6:]))
    if out.endswith(".png") and "--window-size" not in argv:
        argv += ["--window-size", "64x48"]
    if draw(st.integers(0, 19)):
        argv += ["-o", os.path.join(root, out)]
    if "--depth" not in argv and "--file" not in argv and "--model" not in argv:
        argv += ["--depth", "0"]
    return {"argv": argv}


def _parser_of(main):
    """The ``argparse`` parser a verb's ``main`` builds (caught when it parses)."""
    found = {}

    class Caught(Exception):
        pass

    def catch(self, args=None, namespace=None):
        found["parser"] = self
        raise Caught

    with mock.patch.object(argparse.ArgumentParser, "parse_args", catch), contextlib.suppress(Caught):
        main([])
    return found["parser"]


#: Options whose default points into the repository: always given, in the scratch folder.
SAFE = {"exercises": {"--solutions": "sol", "--exercises": "ex"}}


@st.composite
def verb_argv(draw, verb):
    import importlib

    root = scratch()
    parser = _parser_of(importlib.import_module(f"lab.teaching.course.{verb}").main)
    argv, given = [], set()
    value = st.one_of(st.sampled_from(VALUES), st.sampled_from(PATHS).map(lambda p: os.path.join(root, p)))
    for action in parser._actions:
        if isinstance(action, argparse._HelpAction):
            continue
        positional = not action.option_strings
        if not positional and not action.required and not draw(st.integers(0, 2)):
            continue
        values = st.sampled_from(list(action.choices)) if action.choices else value
        if action.choices:
            values = st.one_of(values, st.sampled_from(VALUES))
        if positional:
            n = {"?": draw(st.integers(0, 1)), "+": draw(st.integers(1, 2)), "*": draw(st.integers(0, 2))}.get(
                action.nargs, 1)
            argv += [os.path.join(root, draw(st.sampled_from(PATHS))) for _ in range(n)]
            continue
        option = action.option_strings[-1]
        given.add(option)
        if action.nargs == 0:
            argv.append(option)
        else:
            argv += [option, draw(values)]
    for option, folder in SAFE.get(verb, {}).items():
        if option not in given:
            argv += [option, os.path.join(root, folder)]
    return {"argv": argv}


def _listing(root):
    return {os.path.join(folder, name) for folder, dirs, files in os.walk(root) for name in dirs + files}


def _in_scratch(main):
    """``main`` run in the scratch folder, which is left as it was found: what a call wrote is removed, so that
    no call sees another's output (a release written into the empty folder would make grading it slow)."""

    def call(argv):
        here, root = os.getcwd(), scratch()
        before = _listing(root)
        os.chdir(root)
        try:
            with mock.patch.object(subprocess, "call", lambda *a, **k: 0):  # curvature-lab start: no JupyterLab
                return main(argv)
        finally:
            os.chdir(here)
            for path in sorted(_listing(root) - before, key=len):
                if os.path.isdir(path) and not os.path.islink(path):
                    shutil.rmtree(path, ignore_errors=True)
                elif os.path.lexists(path):
                    os.remove(path)

    return call


def cli_targets():
    import importlib

    found = [Target("cli render", _in_scratch(lab.cli.main), [], strategy=render_argv(), cli=True, examples=60)]
    for verb in lab.cli.VERBS:
        main = importlib.import_module(f"lab.teaching.course.{verb}").main
        found.append(Target(f"cli {verb}", _in_scratch(main), [], strategy=verb_argv(verb), cli=True,
                            examples=4 if verb in ("release", "exercises", "gradescope") else 12))
    return found
