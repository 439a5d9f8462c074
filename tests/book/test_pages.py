"""The built book, read as a reader reads it: every page of ``_build/html`` in headless Chromium.

Each page is opened from disk (``file://``) with the network cut off (every other request is
aborted and recorded), so what passes here renders on a laptop on a plane. A page fails on:

- a request that would need the network (MathJax from a CDN, a web font, ...);
- a script error (``pageerror``) or an error logged to the console;
- raw LaTeX left in the text (``\\(``, ``$$``, ``\\begin{``, ...): MathJax did not typeset it;
- a MathJax error (``mjx-merror``: an unknown macro, unbalanced braces);
- a broken image (``naturalWidth`` 0);
- a raw NumPy or dict repr in a cell's output (``array([...])``, ``np.float64(...)``, ``{256: ...}``):
  outputs show tables or formatted text;
- a table or math display cut at the column edge (viewport 1280 x 900, a ~750 px column): wider
  than the article column without a scroll container of its own, a scroll container that is
  itself wider than the column or that the keyboard cannot reach, or content clipped by an element
  that does not scroll. Math displays must fit the column outright (MathJax 3 does not break
  lines, and a scrolled equation hides its right-hand side);
- any element wider than the text column, on a laptop (1280 px) and on a phone (390 px): a table
  and its caption, a code line, a figure, a paragraph. A scroll bar does not count as fitting: a
  reader must see every column of a table and its whole caption without scrolling. The one
  exception is a display equation on the phone, which may scroll inside its own container (MathJax
  3 cannot break a line; on the laptop every equation fits).

And the API reference lists every public name of the package's modules.

The browser is the system's Chromium (``/usr/bin/chromium``; ``FLAPPING_CHROMIUM`` overrides),
driven through playwright's Python API: no browser is downloaded. The tests skip when the book is
not built (``_build/html``; ``FLAPPING_BOOK_HTML`` overrides) or Chromium is missing, so that
``python -m pytest`` passes before the build; ``.ci/run`` sets ``FLAPPING_REQUIRE_BROWSER=1``,
which turns those skips into failures, and runs ``python -m pytest -m browser`` after the build.
"""

from __future__ import annotations

import importlib
import os
import pkgutil
import re
import shutil
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
BOOK_HTML = Path(os.environ.get("FLAPPING_BOOK_HTML", ROOT / "_build" / "html"))
CHROMIUM = os.environ.get("FLAPPING_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
REQUIRED = os.environ.get("FLAPPING_REQUIRE_BROWSER", "") not in ("", "0")
VIEWPORT = {"width": 1280, "height": 900}  # a laptop screen: the article column is ~750 px
PHONE = {"width": 390, "height": 844}     # a phone held upright: the column is ~350 px
PAGE_TIMEOUT_MS = 60_000
# Subpackages and modules the API reference must cover (private modules, _*, excepted).
API_PACKAGES = ("flapping.periodic", "flapping.model", "flapping.hover", "flapping.hover.stability")

# Raw LaTeX a reader must never see: math delimiters, environments, and common macros.
RAW_LATEX = re.compile(
    r"\\[()\[\]]|\$\$|\\(?:begin|end)\{|"
    r"\\(?:frac|mathrm|operatorname|left|right|theta|alpha|Phi|phi|lambda|mu|Psi|int|sum|hat|bar)"
    r"(?![A-Za-z])"
)
# Reprs a reader should not meet in a cell's output (the book formats numbers as text or tables).
RAW_OUTPUT = re.compile(r"\barray\(\[|\bnp\.(?:float|int|complex)\d*\(|dtype=|^\s*\{\s*['\"\d-]",
                        re.MULTILINE)


def _pages() -> list[str]:
    """Every HTML page of the build, relative to it (assets under _static/_sources excepted)."""
    if not BOOK_HTML.is_dir():
        return []
    skip = {"_static", "_sources", "_images", "_downloads"}
    return sorted(
        p.relative_to(BOOK_HTML).as_posix()
        for p in BOOK_HTML.rglob("*.html")
        if not skip & set(p.relative_to(BOOK_HTML).parts)
    )


def _unavailable(reason: str):
    if REQUIRED:
        pytest.fail(f"{reason} (FLAPPING_REQUIRE_BROWSER is set: the browser test must run)")
    pytest.skip(reason)


PAGES = _pages()


@pytest.fixture(scope="module")
def browser():
    if not (BOOK_HTML / "index.html").is_file():
        _unavailable(f"the book is not built: no {BOOK_HTML / 'index.html'}")
    if not Path(CHROMIUM).is_file():
        _unavailable(f"no Chromium at {CHROMIUM} (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api")
    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(
            executable_path=CHROMIUM,
            headless=True,
            args=["--headless", "--no-sandbox", "--disable-gpu"],
        )
        try:
            yield browser
        finally:
            browser.close()


class PageReport:
    """A page opened offline, with everything it logged while loading and typesetting."""

    def __init__(self, browser, relative: str, viewport: dict | None = None):
        self.blocked: list[str] = []
        self.errors: list[str] = []
        self.context = browser.new_context(viewport=viewport or VIEWPORT, java_script_enabled=True)
        self.context.route("**/*", self._offline)
        self.page = self.context.new_page()
        self.page.on("pageerror", lambda exc: self.errors.append(f"page error: {exc}"))
        self.page.on("console", self._console)
        self.page.set_default_timeout(PAGE_TIMEOUT_MS)
        self.page.goto((BOOK_HTML / relative).as_uri(), wait_until="load")
        # MathJax typesets after load; its startup promise resolves when the page is done.
        self.page.evaluate(_WAIT_FOR_MATHJAX)

    def _offline(self, route):
        url = route.request.url
        if url.startswith(("file://", "data:", "blob:", "about:")):
            route.continue_()
        else:
            self.blocked.append(url)
            route.abort("internetdisconnected")

    def _console(self, message):
        if message.type == "error":
            text = message.text
            location = message.location.get("url", "") if message.location else ""
            if "net::ERR_INTERNET_DISCONNECTED" in text and self.blocked:
                return  # reported once, with its URL, as a blocked request
            self.errors.append(f"console error: {text} {location}".strip())

    def close(self):
        self.context.close()


_WAIT_FOR_MATHJAX = """async () => {
  const mj = window.MathJax;
  if (mj && mj.startup && mj.startup.promise) { await mj.startup.promise; }
  if (document.fonts) { await document.fonts.ready; }
  return true;
}"""

_MATH_STATE = """() => {
  const mj = window.MathJax;
  const hasMath = document.querySelector('.math, mjx-container') !== null;
  const errors = [...document.querySelectorAll('mjx-merror, .MathJax_Error, [data-mjx-error]')]
    .map(e => (e.getAttribute('data-mjx-error') || e.getAttribute('title') || e.textContent)
              .trim().slice(0, 120));
  return {hasMath, loaded: !!(mj && mj.version), errors};
}"""

# Text a reader sees in the article, outside code, scripts and typeset math.
_VISIBLE_TEXT = """() => {
  const root = document.querySelector('article') || document.body;
  const skip = 'pre, code, script, style, textarea, mjx-container, .highlight, .MathJax';
  const walker = document.createTreeWalker(root, NodeFilter.SHOW_TEXT, {
    acceptNode: n => (n.parentElement && n.parentElement.closest(skip))
      ? NodeFilter.FILTER_REJECT : NodeFilter.FILTER_ACCEPT });
  const parts = [];
  while (walker.nextNode()) parts.push(walker.currentNode.textContent);
  return parts.join('');
}"""

_OUTPUTS = """() => [...document.querySelectorAll('.cell_output')].map(e => e.innerText)"""

_BROKEN_IMAGES = """async () => {
  const bad = [];
  for (const img of document.images) {
    img.loading = 'eager';  // lazy images below the fold load too
    try { await img.decode(); } catch (e) {}
    if (!img.complete || img.naturalWidth === 0) bad.push(img.getAttribute('src'));
  }
  return bad;
}"""

# Blocks cut at the column edge. A block may be wider than the article column only inside a
# container of its own that scrolls (overflow-x auto/scroll) and itself fits the column; math
# displays must fit outright. Any element that clips its content without scrolling is cut.
_CUT_BLOCKS = """() => {
  const column = document.querySelector('article.bd-article') || document.querySelector('main');
  if (!column) return [];
  const col = column.getBoundingClientRect();
  const problems = [];
  const scrolls = el => ['auto', 'scroll'].includes(getComputedStyle(el).overflowX);
  const clips = el => ['hidden', 'clip'].includes(getComputedStyle(el).overflowX);
  const name = el => {
    const cls = (typeof el.className === 'string' && el.className.trim())
      ? '.' + el.className.trim().split(/\\s+/).slice(0, 3).join('.') : '';
    const text = (el.innerText || el.textContent || '').replace(/\\s+/g, ' ').trim();
    return `<${el.tagName.toLowerCase()}${el.id ? '#' + el.id : ''}${cls}> "${text.slice(0, 60)}"`;
  };
  const scrollBox = el => {
    for (let a = el.parentElement; a && a !== column; a = a.parentElement) {
      if (scrolls(a)) return a;
    }
    return null;
  };
  const outside = r => r.right > col.right + 1 || r.left < col.left - 1;
  const blocks = column.querySelectorAll(
    'table, mjx-container[display="true"], div.math, img, pre, figure, .cell_output');
  for (const el of blocks) {
    const r = el.getBoundingClientRect();
    if (r.width === 0 && r.height === 0) continue;  // not displayed (e.g. a closed toggle)
    const isMath = el.matches('mjx-container, div.math');
    // The typeset width of a display is that of its mjx-math (the container is the column's).
    const typeset = isMath ? el.querySelector('mjx-math') : null;
    const width = typeset ? typeset.getBoundingClientRect().width : r.width;
    if (isMath && (width > col.width + 1 || outside(r))) {
      problems.push(`math display ${Math.round(width)} px wide in a ${Math.round(col.width)} ` +
                    `px column (MathJax cannot wrap it; it must fit): ${name(el)}`);
      continue;
    }
    const box = scrollBox(el);
    if (box) {
      if (outside(box.getBoundingClientRect())) {
        problems.push(`scroll container beyond the ${Math.round(col.width)} px column: ${name(box)}`);
      } else if (box.scrollWidth > box.clientWidth + 1 && box.tabIndex < 0) {
        // A reader scrolls it with the mouse, and with the keyboard once it is focusable (the
        // theme sets tabindex=0 on scroll containers that need scrolling).
        problems.push(`scroll container that the keyboard cannot reach: ${name(box)}`);
      }
    } else if (outside(r)) {
      problems.push(`${Math.round(r.width)} px wide, beyond the ${Math.round(col.width)} px ` +
                    `column, with no scroll container: ${name(el)}`);
    }
  }
  // Block containers only: inline math (span.math) reports its hidden assistive MathML as
  // overflow, which is not visible content.
  for (const el of column.querySelectorAll('*')) {
    if (getComputedStyle(el).display.startsWith('inline') || el.closest('span.math')) continue;
    if (clips(el) && el.scrollWidth > el.clientWidth + 1 && el.clientWidth > 0
        && el.querySelector('table, mjx-container[display="true"], img, pre')) {
      problems.push(`content clipped (${el.scrollWidth} px in ${el.clientWidth} px, ` +
                    `overflow-x ${getComputedStyle(el).overflowX}): ${name(el)}`);
    }
  }
  return problems;
}"""

# Elements wider than the text column. Only the outermost offender is named (its parent fits), so
# one wide table is one problem, not one per cell. Nothing may reach past the column's edges or
# hide part of itself behind a scroll bar; with ``mathScrolls`` (the phone) a display equation
# may scroll inside its own container, provided that container fits and the keyboard reaches it.
_WIDER_THAN_COLUMN = """(mathScrolls) => {
  const column = document.querySelector('article.bd-article') || document.querySelector('main');
  if (!column) return [];
  const col = column.getBoundingClientRect();
  const problems = [];
  const name = el => {
    const cls = (typeof el.className === 'string' && el.className.trim())
      ? '.' + el.className.trim().split(/\\s+/).slice(0, 3).join('.') : '';
    const text = (el.innerText || el.textContent || '').replace(/\\s+/g, ' ').trim();
    return `<${el.tagName.toLowerCase()}${el.id ? '#' + el.id : ''}${cls}> "${text.slice(0, 70)}"`;
  };
  const beyond = r => r.right > col.right + 1 || r.left < col.left - 1;
  // MathJax's assistive MathML is clipped to 1 px on purpose; a typeset formula is judged whole.
  const inside = el => el.closest('mjx-assistive-mml') ||
    (el.closest('mjx-container') && el.tagName.toLowerCase() !== 'mjx-container');
  const scrollingMath = el => {
    if (!mathScrolls) return false;
    const math = el.closest('mjx-container[display="true"], div.math');
    if (!math) return false;
    for (let a = math; a && a !== column; a = a.parentElement) {
      const ox = getComputedStyle(a).overflowX;
      if (ox === 'auto' || ox === 'scroll') {
        return !beyond(a.getBoundingClientRect()) &&
          (a.scrollWidth <= a.clientWidth + 1 || a.tabIndex >= 0);
      }
    }
    return false;
  };
  const seen = new Set();
  const report = (el, text) => {
    for (let a = el; a; a = a.parentElement) if (seen.has(a)) return;
    seen.add(el);
    problems.push(text);
  };
  for (const el of column.querySelectorAll('*')) {
    if (inside(el)) continue;
    const style = getComputedStyle(el);
    if (style.display === 'none' || style.visibility === 'hidden') continue;
    const r = el.getBoundingClientRect();
    if (r.width === 0 || r.height === 0) continue;  // not displayed (e.g. a closed toggle)
    if (scrollingMath(el)) continue;
    const parent = el.parentElement;
    if (beyond(r) && parent && (parent === column || !beyond(parent.getBoundingClientRect()))) {
      report(el, `${Math.round(r.width)} px wide, past the ${Math.round(col.width)} px column: ` +
                 name(el));
    } else if (['auto', 'scroll', 'hidden', 'clip'].includes(style.overflowX) &&
               el.scrollWidth > el.clientWidth + 1 && el.clientWidth > 0 &&
               !el.closest('span.math')) {
      report(el, `${el.scrollWidth} px of content in ${el.clientWidth} px, the rest behind ` +
                 `overflow-x ${style.overflowX}: ${name(el)}`);
    }
  }
  const page = document.documentElement;
  if (page.scrollWidth > window.innerWidth + 1) {
    problems.push(`the page scrolls sideways: ${page.scrollWidth} px in a ${window.innerWidth} px window`);
  }
  return problems;
}"""


_REDIRECT = re.compile(r'<meta http-equiv="refresh" content="0; url=([^"]+)"', re.IGNORECASE)


@pytest.mark.parametrize("relative", PAGES or ["index.html"])
def test_page_renders_offline(browser, relative):
    redirect = _REDIRECT.search((BOOK_HTML / relative).read_text(encoding="utf-8"))
    if redirect:  # the root index.html only sends the reader to the first chapter
        target = (BOOK_HTML / relative).parent / redirect.group(1)
        assert target.is_file(), f"{relative} redirects to a missing page: {redirect.group(1)}"
        return
    report = PageReport(browser, relative)
    try:
        page = report.page
        problems = [f"needs the network: {url}" for url in report.blocked]
        problems += report.errors
        math = page.evaluate(_MATH_STATE)
        if math["hasMath"] and not math["loaded"]:
            problems.append("the page has math but MathJax did not load")
        problems += [f"MathJax error: {e}" for e in math["errors"]]
        text = page.evaluate(_VISIBLE_TEXT)
        for match in RAW_LATEX.finditer(text):
            context = text[max(0, match.start() - 40):match.end() + 40].replace("\n", " ")
            problems.append(f"raw LaTeX in the text: ...{context}...")
        for output in page.evaluate(_OUTPUTS):
            match = RAW_OUTPUT.search(output)
            if match:
                context = output[max(0, match.start() - 20):match.end() + 60].replace("\n", " ")
                problems.append(f"raw repr in a cell output: ...{context}...")
        problems += [f"broken image: {src}" for src in page.evaluate(_BROKEN_IMAGES)]
        problems += page.evaluate(_CUT_BLOCKS)
    finally:
        report.close()
    assert not problems, f"{relative}:\n  " + "\n  ".join(problems)


@pytest.mark.parametrize("width", ["laptop", "phone"])
@pytest.mark.parametrize("relative", PAGES or ["index.html"])
def test_page_fits_its_column(browser, relative, width):
    """Every element of the page within the text column, at 1280 px and at 390 px."""
    if _REDIRECT.search((BOOK_HTML / relative).read_text(encoding="utf-8")):
        return  # the root index.html only redirects (checked above)
    viewport = VIEWPORT if width == "laptop" else PHONE
    report = PageReport(browser, relative, viewport)
    try:
        problems = report.page.evaluate(_WIDER_THAN_COLUMN, width == "phone")
    finally:
        report.close()
    assert not problems, (f"{relative} at {viewport['width']} px, elements wider than the "
                          "text column:\n  " + "\n  ".join(problems))


def _public_names() -> dict[str, list[str]]:
    """Module -> its public names (``__all__``), for every non-private module of API_PACKAGES."""
    names: dict[str, list[str]] = {}
    for package_name in API_PACKAGES:
        package = importlib.import_module(package_name)
        modules = [package_name]
        if hasattr(package, "__path__"):
            modules = [f"{package_name}.{info.name}" for info in pkgutil.iter_modules(
                package.__path__) if not info.name.startswith("_")]
        for module_name in modules:
            module = importlib.import_module(module_name)
            public = getattr(module, "__all__", None)
            if public is None:
                public = [n for n, v in vars(module).items() if not n.startswith("_")
                          and getattr(v, "__module__", None) == module_name]
            names[module_name] = list(public)
    return names


def test_api_reference_lists_every_public_name(browser):
    api = BOOK_HTML / "api.html"
    assert api.is_file(), "the book has no API reference page (book/api.md)"
    report = PageReport(browser, "api.html")
    try:
        ids = set(report.page.evaluate(
            "() => [...document.querySelectorAll('dt.sig[id]')].map(e => e.id)"))
        shown = set(report.page.evaluate(
            "() => [...document.querySelectorAll('dt.sig .sig-name')].map(e => e.textContent)"))
    finally:
        report.close()
    for name in ("find_periodic_orbit", "monodromy", "find_hover_orbit", "hover_stability",
                 "Insect", "hawkmoth"):
        assert name in shown, f"the API reference does not list {name}"
    missing = []
    for module, public in _public_names().items():
        for name in public:
            obj = getattr(importlib.import_module(module), name)
            home = getattr(obj, "__module__", module)
            # A name re-exported from another module is documented where it is defined.
            if f"{module}.{name}" not in ids and f"{home}.{name}" not in ids:
                missing.append(f"{module}.{name}")
    assert not missing, "public names missing from the API reference:\n  " + "\n  ".join(missing)
