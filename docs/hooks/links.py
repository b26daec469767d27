"""mkdocs hook: links of files the site includes, written relative to their own folder.

``docs/benchmarks.md`` includes ``benchmarks/README.md`` (``pymdownx.snippets``), whose links
to the pages are written for GitHub, relative to ``benchmarks/``: ``../docs/samplers.md``. On
the site the including page lives in ``docs/`` already, so the prefix goes, after the
snippet is expanded and before mkdocs checks the links.
"""

from __future__ import annotations

import re

from markdown import Extension
from markdown.preprocessors import Preprocessor

DOCS_PREFIX = re.compile(r"\]\(\.\./docs/")


class _DocsPrefix(Preprocessor):
    def run(self, lines: list[str]) -> list[str]:
        return [DOCS_PREFIX.sub("](", line) for line in lines]


class _DocsPrefixExtension(Extension):
    def extendMarkdown(self, md) -> None:  # noqa: N802 - Markdown's API
        # snippets runs at priority 32; this runs right after it
        md.preprocessors.register(_DocsPrefix(md), "docs_prefix_links", 31)


def on_config(config):
    config.markdown_extensions.append(_DocsPrefixExtension())
    return config
