"""The language of the lab's messages (English or German) through gettext; catalogues in ``locale/<lang>``.
The lowest layer: imports nothing of lab.  ``_("text")`` translates, ``set_language("de")`` chooses
(default: ``LAB_LANG``, else English); ``lab.po`` files are extracted with Babel (the site, Instructors → "Authoring notebooks and translations").
"""

import contextlib
import contextvars
import gettext
import os
import re
from pathlib import Path

__all__ = ["DOMAIN", "LANGUAGES", "LOCALE_DIR", "N_", "_", "decimal", "language", "number_list", "parse_number",
           "set_language", "translation", "using"]

#: The languages the lab speaks.
LANGUAGES = ("en", "de")
DOMAIN = "lab"
LOCALE_DIR = Path(__file__).resolve().parent / "locale"

_chosen = None
_context = contextvars.ContextVar("lab_language", default=None)  # per thread: the grader grades in parallel


def _normalise(lang):
    code = str(lang).strip().lower().replace("-", "_").split("_")[0].split(".")[0]
    if code not in LANGUAGES:
        raise ValueError(f"language must be one of {', '.join(LANGUAGES)}; got {lang!r}")
    return code


def language():
    """The current language: :func:`using`'s, else :func:`set_language`'s, else ``LAB_LANG``, else English."""
    if _context.get() is not None:
        return _context.get()
    if _chosen is not None:
        return _chosen
    env = os.environ.get("LAB_LANG", "")
    try:
        return _normalise(env) if env else "en"
    except ValueError:
        return "en"


def set_language(lang):
    """Choose the language of checks, hints, reports and explorer labels in this process ("en" or "de")."""
    global _chosen
    _chosen = _normalise(lang)
    os.environ["LAB_LANG"] = _chosen  # kernels and processes started from here speak it too
    return _chosen


@contextlib.contextmanager
def using(lang):
    """Speak ``lang`` inside the block, in this thread only (the grader reports each submission in its language)."""
    token = _context.set(_normalise(lang))
    try:
        yield
    finally:
        _context.reset(token)


_catalogues = {}


def translation(lang=None):
    """The gettext translation of ``lang`` (default: the current language); English is the identity."""
    lang = language() if lang is None else _normalise(lang)
    if lang not in _catalogues:
        _catalogues[lang] = (gettext.NullTranslations() if lang == "en" else
                             gettext.translation(DOMAIN, LOCALE_DIR, languages=[lang], fallback=True))
    return _catalogues[lang]


def _(message):
    """``message`` in the current language (the English text itself where no translation exists)."""
    return translation().gettext(message)


def N_(message):
    """Mark ``message`` for extraction without translating it now (translate it with ``_`` where it is shown)."""
    return message


_POINT = re.compile(r"(?<=\d)\.(?=\d)")


def decimal(text):
    """``text`` with its numbers' decimal points as the current language writes them ("0.5" → "0,5" in German)."""
    return _POINT.sub(",", text) if language() == "de" else text


def number_list(values, spec="g"):
    """``values`` as the current language lists numbers: "0.5, 0.25" in English, "0,5; 0,25" in German (the comma is
    the decimal sign there, so a semicolon separates).  Each number is formatted with ``spec``; a string (a symbol
    such as ``"x"``) is kept as it is.  For arguments and points: ``f"f2({number_list(['x', 0.5, 1])})"``."""
    sep = "; " if language() == "de" else ", "
    return sep.join(x if isinstance(x, str) else decimal(format(float(x), spec)) for x in values)


def parse_number(text):
    """A number a person typed: a decimal point or comma, a minus sign or hyphen (``ValueError`` otherwise)."""
    return float(str(text).strip().replace("−", "-").replace(",", "."))
