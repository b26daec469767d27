"""The documentation site cannot rot: its examples run, its API pages cover the public API.

* Every ```` ```pycon ```` block of a page under ``docs/`` runs as a doctest and every
  ```` ```python ```` block is executed, in page order, in one namespace per page. A block
  directly preceded by the line ``<!-- skip-test -->`` is not run (used for commands that
  need an external service, such as a Dask scheduler).
* Every ``::: module`` directive of the API pages names a module that imports, and every name in
  ``rankedassign.__all__`` and ``oracle.__all__`` is documented by one of them.
* Every page is in the navigation and every figure a page shows exists.
* ``mkdocs build --strict`` passes.
"""

from __future__ import annotations

import doctest
import importlib
import os
import re
import subprocess
import sys
import types
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
SKIP_MARK = "<!-- skip-test -->"
FENCE = re.compile(r"^(?P<indent>[ ]*)```(?P<lang>[\w-]*)[^\n]*$")
DIRECTIVE = re.compile(r"^:::\s+([\w.]+)\s*$", re.MULTILINE)
DOCTEST_FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


def _pages() -> list[Path]:
    return sorted(p for p in DOCS.rglob("*.md") if "scripts" not in p.parts)


def _code_blocks(text: str) -> list[tuple[int, str, str, bool]]:
    """Fenced blocks as ``(line number, language, code, skipped)``, in page order."""
    lines = text.splitlines()
    out = []
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, lang = m.group("indent"), m.group("lang")
        start = i
        body = []
        i += 1
        while i < len(lines) and lines[i].strip() != "```":
            line = lines[i]
            body.append(line[len(indent) :] if line.startswith(indent) else line.lstrip())
            i += 1
        skipped = start > 0 and lines[start - 1].strip() == SKIP_MARK
        out.append((start + 1, lang, "\n".join(body) + "\n", skipped))
        i += 1
    return out


def _runnable_pages() -> list[Path]:
    return [
        p
        for p in _pages()
        if any(lang in ("python", "pycon") for _, lang, _, _ in _code_blocks(p.read_text()))
    ]


@pytest.mark.parametrize("page", _runnable_pages(), ids=lambda p: str(p.relative_to(DOCS)))
def test_page_examples_run(page, tmp_path, monkeypatch):
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)  # examples that write files write them here
    with np.printoptions():  # a page may set print options; they must not leak
        _run_page(page)


def _run_page(page: Path) -> None:
    rel = page.relative_to(ROOT)
    namespace: dict = {"__name__": f"docs_{page.stem.replace('-', '_')}"}
    parser = doctest.DocTestParser()
    runner = doctest.DocTestRunner(optionflags=DOCTEST_FLAGS)
    n_run = 0
    for lineno, lang, code, skipped in _code_blocks(page.read_text()):
        if skipped or lang not in ("python", "pycon"):
            continue
        n_run += 1
        name = f"{rel}:{lineno}"
        if lang == "python":
            exec(compile(code, name, "exec"), namespace)
            continue
        test = parser.get_doctest(code, namespace, name, str(rel), lineno)
        result = runner.run(test, clear_globs=False)
        namespace.update(test.globs)  # DocTest works on a copy; later blocks see its names
        assert result.failed == 0, f"{name}: {result.failed} doctest example(s) failed (see above)"
    assert n_run > 0


def _directives() -> dict[str, Path]:
    found = {}
    for page in (DOCS / "api").glob("*.md"):
        for target in DIRECTIVE.findall(page.read_text()):
            found[target] = page
    return found


def _resolve(target: str):
    """Import ``a.b.c``: the longest importable module prefix, then attributes."""
    parts = target.split(".")
    for n in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:n]))
        except ModuleNotFoundError:
            continue
        for attr in parts[n:]:
            obj = getattr(obj, attr)
        return obj
    raise ModuleNotFoundError(target)


def test_api_directives_import():
    directives = _directives()
    assert "rankedassign.single.problem" in directives
    for target in directives:
        _resolve(target)


def _documented(obj_name: str, obj, package: str, directives: dict[str, Path]) -> bool:
    """Whether ``package.obj_name`` is rendered by one of the ``:::`` directives."""
    if f"{package}.{obj_name}" in directives:
        return True
    if isinstance(obj, types.ModuleType):
        return obj.__name__ in directives
    module = getattr(obj, "__module__", None) or ""
    if module in directives:
        return True
    # A name re-exported from a private module is documented where a public module that
    # re-exports it in its ``__all__`` is rendered.
    for target in directives:
        mod = _resolve(target)
        if obj_name in getattr(mod, "__all__", ()) and getattr(mod, obj_name, None) is obj:
            return True
    return False


@pytest.mark.parametrize("package", ["rankedassign", "oracle"])
def test_every_public_name_has_an_api_page(package):
    pkg = importlib.import_module(package)
    directives = _directives()
    missing = [
        name
        for name in getattr(pkg, "__all__", [])
        if not name.startswith("__")
        and not _documented(name, getattr(pkg, name), package, directives)
    ]
    assert not missing, f"public names of {package} missing from docs/api/: {missing}"


def _module_files(package: str) -> list[Path]:
    """The package's files: those git tracks when run from a checkout, else all on disk."""
    pkg_dir = ROOT / package
    try:
        proc = subprocess.run(
            ["git", "ls-files", "--", package], cwd=ROOT, capture_output=True, text=True,
            check=True, timeout=30,
        )
        tracked = [ROOT / line for line in proc.stdout.splitlines()]
    except (OSError, subprocess.SubprocessError):
        tracked = []
    if not tracked:
        tracked = list(pkg_dir.rglob("*.py"))
    return tracked


def test_public_modules_have_api_pages():
    """Every public module of the two packages is rendered on some API page."""
    directives = _directives()
    missing = set()
    for package in ("rankedassign", "oracle"):
        for path in _module_files(package):
            rel = path.relative_to(ROOT / package)
            if path.suffix != ".py" or rel.parts[0] in ("cli.py", "__main__.py"):
                continue
            top = rel.parts[0].removesuffix(".py")
            if top.startswith("_") or len(rel.parts) > 1 and rel.parts[-1].startswith("_") \
                    and rel.parts[-1] != "__init__.py":
                continue
            name = f"{package}.{top}"
            if name not in directives and package not in directives:
                missing.add(name)
    assert not missing, f"modules without an API page: {sorted(missing)}"


def test_every_page_is_in_the_nav_and_figures_exist():
    nav = (ROOT / "mkdocs.yml").read_text()
    for page in _pages():
        rel = page.relative_to(DOCS).as_posix()
        assert rel in nav, f"{rel} is not in the nav of mkdocs.yml"
        for target in re.findall(r"!\[[^\]]*\]\(([^)\s]+)", page.read_text()):
            assert (page.parent / target).resolve().is_file(), f"{rel} shows missing {target}"


def test_figure_script_covers_every_figure():
    """Each PNG in docs/figures/ is written by docs/scripts/make_figures.py."""
    script = (DOCS / "scripts" / "make_figures.py").read_text()
    for png in (DOCS / "figures").glob("*.png"):
        assert f'"{png.stem}"' in script, f"{png.name} is not produced by make_figures.py"


def test_code_block_parser():
    text = "a\n```python\nx = 1\n```\n<!-- skip-test -->\n```pycon\n>>> 1\n1\n```\n"
    blocks = _code_blocks(text)
    assert [(b[1], b[3]) for b in blocks] == [("python", False), ("pycon", True)]
    assert blocks[0][2] == "x = 1\n"


@pytest.mark.e2e
def test_mkdocs_build_strict(tmp_path):
    # mkdocs, Material and mkdocstrings are in the "test" extra, so `pytest -m e2e` (CI's
    # end-to-end tier) always builds the site strictly. Not with --quiet: it drops the warnings before mkdocs
    # counts them, and a strict build with --quiet passes whatever they say.
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir",
         str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
        # no timeout: the work is bounded (one site), and a loaded machine is not a failure
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert (tmp_path / "site" / "index.html").is_file()



@pytest.mark.slow
def test_figure_script_runs(tmp_path):
    """docs/scripts/make_figures.py regenerates every figure (about 20 s)."""
    proc = subprocess.run(
        [sys.executable, str(DOCS / "scripts" / "make_figures.py"), "--out", str(tmp_path)],
        # no timeout: the script's work is bounded; a clock would fail it on a loaded machine
        cwd=ROOT, capture_output=True, text=True,
        # without the test runner's own variables (a parallel run's PYTEST_XDIST_*): the
        # script runs a benchmark module under a pytest of its own
        env={**{k: v for k, v in os.environ.items() if not k.startswith("PYTEST_")},
             "MPLBACKEND": "Agg"},
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    made = sorted(p.stem for p in tmp_path.glob("*.png"))
    committed = sorted(p.stem for p in (DOCS / "figures").glob("*.png"))
    assert made == committed
