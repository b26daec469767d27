"""docs/hooks/sphinx_roles.py: Sphinx roles become links, and an unresolvable one fails the build.

Each test builds a two-module site of its own (a few seconds), so the rule is checked on a
docstring written for the purpose; the real site's roles are checked by ``mkdocs build
--strict`` in test_docs.py and, in the rendered pages, by the browser tier.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXTENSION = ROOT / "docs" / "hooks" / "sphinx_roles.py"

PACKAGE = '''\
"""The package. Calls :func:`helper` (short name, this package's import), its module
:mod:`pkg.tools`, the record :class:`~pkg.tools.Record`, its field :attr:`Record.size`
(no docstring: links to the record) and :data:`LIMIT` (bound by ``A, LIMIT = 1, 2``: links to
the module), Python's :class:`ValueError` and NumPy's :func:`numpy.asarray` (no entry here:
code).{extra}
"""

from .tools import Record, helper

A, LIMIT = 1, 2
__all__ = ["Record", "helper"]
'''

TOOLS = '''\
"""Tools."""

from typing import NamedTuple


class Record(NamedTuple):
    """A record."""

    size: int


def helper():
    """Help. See :class:`Record`."""
'''


def _build(tmp_path: Path, extra: str = "") -> subprocess.CompletedProcess:
    (tmp_path / "pkg").mkdir(exist_ok=True)
    (tmp_path / "pkg" / "__init__.py").write_text(PACKAGE.format(extra=extra))
    (tmp_path / "pkg" / "tools.py").write_text(TOOLS)
    (tmp_path / "docs").mkdir(exist_ok=True)
    (tmp_path / "docs" / "index.md").write_text("# API\n\n::: pkg\n\n::: pkg.tools\n")
    (tmp_path / "mkdocs.yml").write_text(textwrap.dedent(f"""\
        site_name: roles
        strict: true
        plugins:
          - mkdocstrings:
              handlers:
                python:
                  paths: [.]
                  options:
                    docstring_style: numpy
                    show_root_heading: true
                    show_source: false
                    extensions:
                      - {EXTENSION}:SphinxRoles:
                          packages: [pkg]
                          external: [numpy]
                          api_pages: {tmp_path / "docs"}
        """))
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict"],  # no --quiet: it hides warnings
        cwd=tmp_path, capture_output=True, text=True,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )


def test_roles_become_links(tmp_path):
    proc = _build(tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    page = (tmp_path / "site" / "index.html").read_text()
    by_text = {text: href for href, text in re.findall(
        r'<a class="autorefs autorefs-internal"[^>]*href="([^"]+)"[^>]*><code>([^<]+)</code>', page)}
    assert by_text["helper"].endswith("#pkg.tools.helper") or by_text["helper"].endswith(
        "#pkg.helper")
    assert by_text["pkg.tools"].endswith("#pkg.tools")
    assert by_text["Record"].endswith("#pkg.tools.Record")
    assert by_text["Record.size"].endswith("#pkg.tools.Record")
    assert by_text["LIMIT"].endswith("#pkg")
    assert "<code>ValueError</code>" in page and "ValueError</a>" not in page
    assert "<code>numpy.asarray</code>" in page
    assert not re.search(r":(func|class|mod|attr|data):", page)


def test_an_unresolvable_role_fails_the_strict_build(tmp_path):
    proc = _build(tmp_path, extra=" A stale name: :func:`pkg.gone`.")
    assert proc.returncode != 0
    assert "Could not find cross-reference target 'pkg.gone'" in proc.stdout + proc.stderr


def test_the_sources_keep_their_roles():
    """The rewrite happens in the build only: help() still shows the Sphinx roles."""
    import rankedassign

    assert ":func:`" in rankedassign.samplers.__doc__
    assert "][" not in rankedassign.samplers.__doc__
