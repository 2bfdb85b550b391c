"""Self-contained HTML pages for students and instructors (feedback, written answers): escaped text, no scripts.

JupyterLab opens such a file in its HTML viewer (a sandboxed frame); a page needs nothing from the network.
"""

import html

__all__ = ["STATUS_COLOURS", "e", "page"]

e = html.escape

STYLE = ("body{font-family:system-ui,sans-serif;max-width:62em;margin:2em auto;padding:0 1em;line-height:1.45}"
         "h1{font-size:1.5em}h2{font-size:1.2em;margin-top:2em}section{margin-bottom:2.5em}"
         "pre,.q,.a{white-space:pre-wrap}.q{background:#f4f4f4;padding:.6em}"
         ".a{border-left:4px solid #0969da;padding:.2em .8em;margin:.8em 0}.none{color:#777}"
         "table{border-collapse:collapse;margin:.6em 0}td,th{border:1px solid #ccc;padding:.25em .6em;"
         "text-align:left;vertical-align:top}.passed{color:#1a7f37}.failed,.error,.timeout,.delegated{color:#cf222e}"
         ".not-implemented,.not-run,.late{color:#9a6700}.score{font-size:1.3em;font-weight:bold}")

#: CSS class per case status (the statuses of lab.teaching.report).
STATUS_COLOURS = {"passed": "passed", "failed": "failed", "error": "error", "timeout": "timeout",
                  "delegated": "delegated", "not implemented": "not-implemented", "not run": "not-run"}


def page(title, body, lang="en"):
    """A whole HTML document around ``body`` (HTML the caller escaped)."""
    return (f"<!DOCTYPE html>\n<html lang='{e(lang)}'><head><meta charset='utf-8'>"
            f"<meta name='viewport' content='width=device-width'><title>{e(title)}</title>"
            f"<style>{STYLE}</style></head><body>\n{body}\n</body></html>\n")
