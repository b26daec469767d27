"""The built documentation in a real browser without network: the browser tier.

Run with ``python -m pytest -m browser -W error`` (excluded from the default run by the marker
configuration of ``pyproject.toml``). It needs the ``browser`` extra (Playwright, used only to
drive the browser) and a Chromium from the system's packages (Debian: ``apt-get install
chromium``); ``CHROMIUM`` names another executable.

The module builds the site strictly into ``$RANKEDASSIGN_SITE_DIR`` (default ``.site-browser``),
opens every page from disk (``file://``) in headless Chromium whose network is off and whose
resolver knows no host, and checks:

* no page loads anything from another host, neither as written in the HTML and CSS nor as
  requested by the browser;
* every page that has math shows it typeset: MathML that Chromium lays out, no raw ``\\(``,
  ``\\[`` or ``$...\\cmd...$`` left in the rendered text;
* no page shows a literal Sphinx role (``:func:`` and the others) and the API pages carry the
  cross-references as links;
* every link to a page or anchor of the site resolves to a file of the build and an ``id`` in it;
* the theme's stylesheet is applied (the layout is Material's, not unstyled HTML);
* search finds ``sample_short_chains``. Material's search runs in a web worker, which Chromium
  does not start from ``file://``; the test serves the build on ``127.0.0.1`` for this check only.

Two screenshots (the Samplers page at its first display formula, the samplers API page) are
saved into ``<site>/screenshots/`` for CI to keep as artifacts.
"""

from __future__ import annotations

import functools
import http.server
import os
import re
import shutil
import subprocess
import sys
import threading
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
SITE = Path(os.environ.get("RANKEDASSIGN_SITE_DIR", ROOT / ".site-browser")).resolve()
ROLE = re.compile(r":(?:py:)?(?:func|class|meth|mod|data|attr|obj|exc|const):")
RAW_DELIMITER = re.compile(r"\\[()\[\]]")
RAW_DOLLAR = re.compile(r"\$[^$\n]*\\[A-Za-z]+[^$\n]*\$")
ASSET = re.compile(
    r"<(?:script|link|img|iframe|source|audio|video|embed|object|track)\b[^>]*?"
    r"\b(?:src|href|srcset|data)\s*=\s*[\"']?(?P<url>(?:https?:)?//[^\"'\s>]+)",
    re.IGNORECASE,
)
CSS_URL = re.compile(r"(?:url\(\s*[\"']?|@import\s+[\"'])(?P<url>(?:https?:)?//[^\"')\s]+)")
ID = re.compile(r"\bid=\"([^\"]+)\"")

# Collected in the page once per page, so that the checks below share one visit.
PAGE_SCRIPT = """() => {
  const skip = "pre, code, math, script, style, noscript, textarea";
  const walker = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
  const parts = [];
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    const el = n.parentElement;
    if (!el || el.closest(skip) || !el.checkVisibility()) continue;
    parts.push(n.textContent);
  }
  const maths = [...document.querySelectorAll("article math")];
  const laidOut = maths.filter(m => {
    const d = getComputedStyle(m).display;
    return d.includes("math");
  }).length;
  const visible = maths.filter(m => m.checkVisibility());
  const sized = visible.filter(m => m.getBoundingClientRect().width > 0).length;
  const header = document.querySelector(".md-header");
  return {
    text: parts.join(""),
    maths: maths.length,
    mathsLaidOut: laidOut,
    mathsVisible: visible.length,
    mathsSized: sized,
    wrappersWithoutMath: [...document.querySelectorAll(".arithmatex")]
        .filter(w => !w.querySelector("math")).length,
    hrefs: [...document.querySelectorAll("a[href]")].map(a => a.href),
    autorefs: document.querySelectorAll("a.autorefs-internal").length,
    headerPosition: header ? getComputedStyle(header).position : null,
    font: getComputedStyle(document.body).fontFamily,
  };
}"""


@pytest.fixture(scope="session", autouse=True)
def _compiled_samplers():
    """Overrides tests/conftest.py's warm-up of the same name: the site needs no kernel."""


def _chromium() -> str:
    for candidate in (os.environ.get("CHROMIUM"), "/usr/lib/chromium/chromium",
                      shutil.which("chromium"), shutil.which("chromium-browser")):
        if candidate and Path(candidate).is_file():
            return candidate
    pytest.fail("no Chromium: apt-get install chromium, or set CHROMIUM to its executable")


@pytest.fixture(scope="module")
def site() -> Path:
    """The site, built strictly as the default test does, into the build folder (no --quiet:
    it hides the warnings from the strict count)."""
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(SITE)],
        cwd=ROOT, capture_output=True, text=True, timeout=300,
        env={**os.environ, "NO_MKDOCS_2_WARNING": "1"},
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    return SITE


def _pages(site: Path) -> list[Path]:
    return sorted(p for p in site.rglob("*.html") if p.name != "404.html"
                  and "screenshots" not in p.parts)


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as pw:
        browser = pw.chromium.launch(
            executable_path=_chromium(),
            headless=True,
            # no name resolves except the loopback address, whatever the machine's network
            args=["--host-resolver-rules=MAP * ~NOTFOUND, EXCLUDE 127.0.0.1",
                  "--no-proxy-server", "--disable-background-networking"],
        )
        yield browser
        browser.close()


def _context(browser, foreign: list[str], allowed_prefix: str = "file://"):
    """A browser context that aborts, and records, every request outside ``allowed_prefix``."""
    context = browser.new_context(viewport={"width": 1280, "height": 900},
                                  offline=allowed_prefix == "file://")

    def route(r):
        url = r.request.url
        if url.startswith((allowed_prefix, "data:", "blob:")):
            r.continue_()
        else:
            foreign.append(url)
            r.abort()

    context.route("**/*", route)
    context.on("request", lambda req: None if req.url.startswith(
        (allowed_prefix, "data:", "blob:", "file://")) else foreign.append(req.url))
    return context


@pytest.fixture(scope="module")
def rendered(site, browser):
    """Every page opened from disk, offline: what the checks need, per page (site-relative)."""
    foreign: list[str] = []
    context = _context(browser, foreign)
    page = context.new_page()
    errors: list[str] = []
    page.on("pageerror", lambda exc: errors.append(f"{page.url}: {exc}"))
    out = {}
    for path in _pages(site):
        page.goto(path.as_uri(), wait_until="load")
        out[path.relative_to(site).as_posix()] = page.evaluate(PAGE_SCRIPT)
    _screenshots(page, site)
    context.close()
    return {"pages": out, "foreign": sorted(set(foreign)), "errors": errors}


def _screenshots(page, site: Path) -> None:
    shots = site / "screenshots"
    shots.mkdir(exist_ok=True)
    page.goto((site / "samplers.html").as_uri(), wait_until="load")
    page.locator("div.arithmatex").first.scroll_into_view_if_needed()
    page.screenshot(path=str(shots / "samplers.png"))
    page.goto((site / "api" / "samplers.html").as_uri(), wait_until="load")
    page.locator("a.autorefs-internal").first.scroll_into_view_if_needed()
    page.screenshot(path=str(shots / "api-samplers.png"))


def test_nothing_written_to_load_from_another_host(site):
    found = []
    for path in site.rglob("*"):
        if path.suffix == ".html":
            found += [(path.name, m["url"]) for m in ASSET.finditer(path.read_text())]
        elif path.suffix == ".css":
            found += [(path.name, m["url"]) for m in CSS_URL.finditer(path.read_text())]
    assert not found, f"assets from other hosts: {found[:10]}"


def test_nothing_requested_from_another_host(rendered):
    assert not rendered["foreign"], f"requests to other hosts: {rendered['foreign'][:10]}"
    assert not rendered["errors"], f"script errors: {rendered['errors'][:5]}"


def test_theme_layout_and_system_fonts(rendered):
    for name, data in rendered["pages"].items():
        # Material's stylesheet makes the header sticky; unstyled HTML leaves it static
        assert data["headerPosition"] == "sticky", f"{name}: theme stylesheet not applied"
        assert "roboto" not in data["font"].lower(), f"{name}: {data['font']}"


def test_math_is_typeset(rendered, site):
    pages = rendered["pages"]
    with_math = {name for name, data in pages.items() if data["maths"]}
    # the Samplers page is the example; the others have math by the same route
    assert {"samplers.html", "problem.html", "multisensor.html"} <= with_math
    for name, data in pages.items():
        assert not RAW_DELIMITER.search(data["text"]), (
            f"{name}: raw TeX delimiter in the rendered text: "
            f"{RAW_DELIMITER.search(data['text']).group(0)!r}"
        )
        assert not RAW_DOLLAR.search(data["text"]), f"{name}: {RAW_DOLLAR.search(data['text'])}"
        assert data["wrappersWithoutMath"] == 0, f"{name}: formulas left as TeX"
        # Chromium lays MathML out itself (display: math / block math) and gives it a size
        assert data["mathsLaidOut"] == data["maths"], f"{name}: MathML not laid out"
        assert data["mathsSized"] == data["mathsVisible"], f"{name}: MathML of zero width"


def test_no_literal_role_and_references_are_links(rendered):
    pages = rendered["pages"]
    for name, data in pages.items():
        m = ROLE.search(data["text"])
        assert m is None, f"{name}: literal role {data['text'][m.start():m.end() + 40]!r}"
    api = {name: data for name, data in pages.items() if name.startswith("api/")}
    assert len(api) >= 12
    # the docstrings carry several hundred roles; each became a link
    assert sum(data["autorefs"] for data in api.values()) > 400


@functools.cache
def _ids(path: Path) -> frozenset[str]:
    return frozenset(ID.findall(path.read_text()))


def test_internal_links_resolve(rendered, site):
    broken = []
    for name, data in rendered["pages"].items():
        for href in data["hrefs"]:
            url = urlsplit(href)
            if url.scheme != "file":
                continue
            target = Path(unquote(url.path))
            if target.is_dir():
                target = target / "index.html"
            if not target.is_file():
                broken.append((name, href))
            elif url.fragment and target.suffix == ".html" \
                    and unquote(url.fragment) not in _ids(target):
                broken.append((name, href))
    assert not broken, f"{len(broken)} broken links, first: {broken[:10]}"


class _Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def test_search_finds_sample_short_chains(site, browser):
    handler = functools.partial(_Quiet, directory=str(site))
    with http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler) as server:
        threading.Thread(target=server.serve_forever, daemon=True).start()
        base = f"http://127.0.0.1:{server.server_address[1]}/"
        foreign: list[str] = []
        context = _context(browser, foreign, allowed_prefix=base)
        page = context.new_page()
        page.goto(base + "index.html", wait_until="load")
        box = page.locator("input.md-search__input")
        box.click()
        box.press_sequentially("sample_short_chains")
        results = page.locator(".md-search-result__item a")
        results.first.wait_for(timeout=30_000)
        hrefs = [results.nth(i).get_attribute("href") for i in range(results.count())]
        context.close()
        server.shutdown()
    assert any("api/samplers.html#rankedassign.samplers.sample_short_chains" in h
               for h in hrefs), hrefs
    assert not foreign, foreign
