"""The explorer page of the built book (book/explorer.md), used as a reader uses it, offline.

The page is opened from disk in headless Chromium with every request that would leave the machine
aborted and recorded (as in tests/book/test_pages.py). It must draw its plotly figure without a
script or console error and without any such request; moving a slider and choosing another species
must change the point shown: the readout line above the figure, the point's index, and the
curves drawn. Skips (fails under ``FLAPPING_REQUIRE_BROWSER=1``, as in ``.ci/run``) when the book
is not built or Chromium is missing.
"""

from __future__ import annotations

import os
import shutil
from pathlib import Path
from types import SimpleNamespace

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
BOOK_HTML = Path(os.environ.get("FLAPPING_BOOK_HTML", ROOT / "_build" / "html"))
PAGE = BOOK_HTML / "explorer.html"
CHROMIUM = os.environ.get("FLAPPING_CHROMIUM") or shutil.which("chromium") or "/usr/bin/chromium"
REQUIRED = os.environ.get("FLAPPING_REQUIRE_BROWSER", "") not in ("", "0")
DIV = "stability-explorer"
TIMEOUT_MS = 60_000
#: The page's size bound (bytes): plotly.js (~4.7 MB) and the grid's data.
PAGE_BOUND = 8e6


def _unavailable(reason: str):
    if REQUIRED:
        pytest.fail(f"{reason} (FLAPPING_REQUIRE_BROWSER is set: the browser test must run)")
    pytest.skip(reason)


@pytest.fixture(scope="module")
def page():
    if not PAGE.is_file():
        _unavailable(f"the book is not built: no {PAGE}")
    if not Path(CHROMIUM).is_file():
        _unavailable(f"no Chromium at {CHROMIUM} (apt-get install chromium)")
    sync_api = pytest.importorskip("playwright.sync_api")
    blocked: list[str] = []
    errors: list[str] = []

    def offline(route):
        url = route.request.url
        if url.startswith(("file://", "data:", "blob:", "about:")):
            route.continue_()
        else:
            blocked.append(url)
            route.abort("internetdisconnected")

    with sync_api.sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=CHROMIUM, headless=True,
                                             args=["--headless", "--no-sandbox", "--disable-gpu"])
        context = browser.new_context(viewport={"width": 1280, "height": 900})
        context.route("**/*", offline)
        tab = context.new_page()
        tab.set_default_timeout(TIMEOUT_MS)
        tab.on("pageerror", lambda exc: errors.append(f"page error: {exc}"))
        tab.on("console", lambda m: errors.append(f"console {m.type}: {m.text}")
               if m.type == "error" else None)
        tab.goto(PAGE.as_uri(), wait_until="load")
        tab.wait_for_selector(f"#{DIV}.js-plotly-plot .main-svg")
        try:
            yield SimpleNamespace(tab=tab, blocked=blocked, errors=errors)
        finally:
            browser.close()


def _state(page) -> dict:
    return page.tab.evaluate(f"""() => {{
      const gd = document.getElementById('{DIV}');
      return {{text: document.getElementById('{DIV}-readout').textContent,
               point: gd.getAttribute('data-point'),
               u: Array.from(gd.data[0].y || []),
               mu: Array.from(gd.data[4].x || [])}};
    }}""")


def test_page_size_is_bounded():
    if not PAGE.is_file():
        _unavailable(f"the book is not built: no {PAGE}")
    assert PAGE.stat().st_size < PAGE_BOUND


def test_figure_renders_offline_without_errors(page):
    assert page.tab.locator(f"#{DIV} .main-svg").count() >= 1
    assert page.tab.locator(f"#{DIV} .slider-group").count() == 3
    assert page.tab.locator(f"#{DIV} .updatemenu-header").count() == 1
    state = _state(page)
    assert "hawkmoth" in state["text"] and "|μ₁| = " in state["text"]
    assert state["point"] is not None and len(state["u"]) > 10 and len(state["mu"]) == 4
    assert page.tab.evaluate("() => typeof window.Plotly") == "object"
    assert page.blocked == [], f"requests that need the network: {page.blocked}"
    assert page.errors == [], page.errors


def test_a_slider_moves_the_point_shown(page):
    before = _state(page)
    rail = page.tab.locator(f"#{DIV} .slider-group").nth(1).locator(".slider-rail-touch-rect")
    rail.scroll_into_view_if_needed()  # the mouse clicks where the viewport shows the rail
    box = rail.bounding_box()
    page.tab.mouse.click(box["x"] + box["width"] - 2, box["y"] + box["height"] / 2)
    page.tab.wait_for_function(f"() => document.getElementById('{DIV}').getAttribute('data-point')"
                           f" !== '{before['point']}'")
    after = _state(page)
    assert after["text"] != before["text"] and "hawkmoth" in after["text"]
    assert after["u"] != before["u"] and after["mu"] != before["mu"]
    assert page.errors == [] and page.blocked == []


def test_the_species_menu_moves_the_point_shown(page):
    before = _state(page)
    page.tab.locator(f"#{DIV} .updatemenu-header").click()
    page.tab.locator(f"#{DIV} .updatemenu-dropdown-button").nth(1).click()
    page.tab.wait_for_function(f"() => document.getElementById('{DIV}').getAttribute('data-point')"
                           f" !== '{before['point']}'")
    after = _state(page)
    assert "hawkmoth" not in after["text"] and after["text"] != before["text"]
    assert after["u"] != before["u"]
    assert page.errors == [] and page.blocked == []
