"""mkdocs hook: the pages' TeX becomes MathML at build time, so no script typesets it.

``pymdownx.arithmatex`` (generic mode) wraps each formula of the pages and of the docstrings in
``<span class="arithmatex">\\(...\\)</span>`` or ``<div class="arithmatex">\\[...\\]</div>``.
This hook replaces each wrapper's TeX by MathML from ``latex2mathml`` (a pure-Python package of
the ``docs`` extra), which browsers display natively: the site needs no MathJax and no network.
The TeX stays in the page as the MathML ``annotation``, so copying and search still see it.

A formula ``latex2mathml`` cannot convert, or converts with a TeX command left in the output,
is a warning, so it fails the strict build.
"""

from __future__ import annotations

import html
import logging
import re

from latex2mathml.converter import convert

_logger = logging.getLogger("mkdocs.hooks.math")

WRAPPER = re.compile(
    r'<(?P<tag>span|div) class="arithmatex">(?P<tex>.*?)</(?P=tag)>', re.DOTALL
)
INLINE = re.compile(r"^\\\((?P<tex>.*)\\\)$", re.DOTALL)
DISPLAY = re.compile(r"^\\\[(?P<tex>.*)\\\]$", re.DOTALL)
# a TeX control word left in the MathML's visible elements means it was not understood
LEFTOVER = re.compile(r"<m(?:i|o|n|text)[^>]*>[^<]*\\[A-Za-z]+[^<]*</m(?:i|o|n|text)>")

# TeX that latex2mathml (3.81) does not know, rewritten into what it does (meaning unchanged).
REWRITES = [
    (re.compile(r"\\arg\b"), r"\\operatorname{arg}"),
]


def _to_mathml(tex: str, display: bool) -> str:
    for pattern, repl in REWRITES:
        tex = pattern.sub(repl, tex)
    return convert(tex.strip(), display="block" if display else "inline")


def _replace(match: re.Match, page) -> str:
    raw = html.unescape(match.group("tex")).strip()
    inline = INLINE.match(raw)
    display = DISPLAY.match(raw)
    if not (inline or display):
        _logger.warning("%s: unexpected math wrapper content %r", page.file.src_uri, raw[:80])
        return match.group(0)
    tex = (inline or display).group("tex")
    try:
        mathml = _to_mathml(tex, display=display is not None)
    except Exception as exc:  # latex2mathml raises many types on bad input
        _logger.warning("%s: cannot convert %r to MathML: %s", page.file.src_uri, tex, exc)
        return match.group(0)
    if LEFTOVER.search(mathml):
        _logger.warning(
            "%s: TeX command not understood in %r: %s",
            page.file.src_uri, tex, LEFTOVER.search(mathml).group(0),
        )
    # keep the source as an annotation (copy/paste, search); MathML Core ignores it visually
    annotation = f'<annotation encoding="application/x-tex">{html.escape(tex.strip())}</annotation>'
    mathml = re.sub(r"(<math[^>]*>)(.*)(</math>)",
                    lambda m: f"{m.group(1)}<semantics><mrow>{m.group(2)}</mrow>{annotation}</semantics>{m.group(3)}",
                    mathml, count=1, flags=re.DOTALL)
    cls = "arithmatex arithmatex--display" if display else "arithmatex"
    return f'<{match.group("tag")} class="{cls}">{mathml}</{match.group("tag")}>'


def on_page_content(html_text: str, page, config, files) -> str:
    return WRAPPER.sub(lambda m: _replace(m, page), html_text)
