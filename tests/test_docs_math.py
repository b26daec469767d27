"""docs/hooks/math.py: the pages' TeX becomes MathML at build time; what it cannot convert warns.

A warning fails the strict build; the whole site's formulas are converted by the strict build of
test_docs.py and checked in the browser by the browser tier.
"""

from __future__ import annotations

import importlib.util
import logging
from pathlib import Path
from types import SimpleNamespace

import pytest

HOOK = Path(__file__).resolve().parents[1] / "docs" / "hooks" / "math.py"


@pytest.fixture(scope="module")
def hook():
    pytest.importorskip("latex2mathml")
    spec = importlib.util.spec_from_file_location("docs_math_hook", HOOK)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _page(title: str = "Plain"):
    heading = SimpleNamespace(title=title, children=[])
    return SimpleNamespace(file=SimpleNamespace(src_uri="page.md"),
                           toc=SimpleNamespace(items=[heading]))


def test_inline_display_and_headings_become_mathml(hook, caplog):
    page = _page(r"Exact \(Z\) and marginals")
    html = (r'<p>A <span class="arithmatex">\(\gamma_n &lt; \hat n = \arg\max_n\)</span>.</p>'
            r'<div class="arithmatex">\[\pi(\gamma) \propto \sum_{j} w_j\]</div>')
    with caplog.at_level(logging.WARNING):
        out = hook.on_page_content(html, page, None, None)
    assert not caplog.records
    assert out.count("<math") == 2 and 'display="block"' in out and 'display="inline"' in out
    assert "\\(" not in out and "\\[" not in out and "\\gamma" not in out
    # the comparison stays an escaped operator of the MathML, not a tag opening
    assert "<mo>&#x0003C;</mo>" in out or "<mo>&lt;</mo>" in out
    assert page.toc.items[0].title.startswith("Exact <math")


def test_unknown_tex_warns(hook, caplog):
    with caplog.at_level(logging.WARNING):
        hook.on_page_content(r'<span class="arithmatex">\(\notacommand x\)</span>', _page(),
                             None, None)
    assert any("notacommand" in r.getMessage() for r in caplog.records)
