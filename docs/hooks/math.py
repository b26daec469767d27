"""mkdocs hook: the pages' TeX becomes MathML at build time, so no script typesets it.

``pymdownx.arithmatex`` (generic mode) wraps each formula of the pages and of the docstrings in
``<span class="arithmatex">\\(...\\)</span>`` or ``<div class="arithmatex">\\[...\\]</div>``.
This hook replaces each wrapper's TeX by MathML from ``latex2mathml`` (a pure-Python package of
the ``docs`` extra), which browsers display natively: the site needs no MathJax and no network.
Formulas in headings are converted in the table of contents too.

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


def _to_mathml(tex: str, display: bool, page) -> str | None:
    """MathML for ``tex``; ``None`` (and a warning: strict builds fail) if it does not convert."""
    source = tex
    for pattern, repl in REWRITES:
        tex = pattern.sub(repl, tex)
    try:
        mathml = convert(tex.strip(), display="block" if display else "inline")
    except Exception as exc:  # latex2mathml raises many types on bad input
        _logger.warning("%s: cannot convert %r to MathML: %s", page.file.src_uri, source, exc)
        return None
    leftover = LEFTOVER.search(mathml)
    if leftover:
        _logger.warning("%s: TeX command not understood in %r: %s",
                        page.file.src_uri, source, leftover.group(0))
    return mathml


def _replace(match: re.Match, page) -> str:
    raw = html.unescape(match.group("tex")).strip()
    inline = INLINE.match(raw)
    display = DISPLAY.match(raw)
    if not (inline or display):
        _logger.warning("%s: unexpected math wrapper content %r", page.file.src_uri, raw[:80])
        return match.group(0)
    mathml = _to_mathml((inline or display).group("tex"), display is not None, page)
    if mathml is None:
        return match.group(0)
    cls = "arithmatex arithmatex--display" if display else "arithmatex"
    return f'<{match.group("tag")} class="{cls}">{mathml}</{match.group("tag")}>'


# a heading's formula reaches the table of contents as bare text, delimiters included
TOC_INLINE = re.compile(r"\\\((?P<tex>.+?)\\\)")


def _toc(items, page) -> None:
    for item in items:
        item.title = TOC_INLINE.sub(
            lambda m: _to_mathml(html.unescape(m.group("tex")), False, page) or m.group(0),
            item.title,
        )
        _toc(item.children, page)


def on_page_content(html_text: str, page, config, files) -> str:
    _toc(page.toc.items, page)
    return WRAPPER.sub(lambda m: _replace(m, page), html_text)
