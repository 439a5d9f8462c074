"""The build extension drops the inline scripts Sphinx 7.4 writes twice (sphinx-doc/sphinx#13402)."""

import pytest

from flapping.book.sphinx_ext import unique_scripts

assets = pytest.importorskip("sphinx.builders.html._assets")


def test_inline_script_registered_as_none_and_as_empty_name_is_kept_once():
    # The bug: the builder holds the script under None, prepare_writing re-adds it under "".
    body = 'const THEBE_JS_URL = "https://unpkg.com/thebe@0.8.2/lib/index.js"'
    first = assets._JavaScript(None, body=body, priority=500)
    again = assets._JavaScript("", body=body, priority=500)
    other = assets._JavaScript(None, body="var togglebuttonSelector = '.toggle'", priority=500)
    assert first != again  # what makes Sphinx 7.4 write both
    assert unique_scripts([first, other, again]) == [first, other]


def test_distinct_scripts_and_their_order_are_kept():
    scripts = [assets._JavaScript("_static/a.js"), assets._JavaScript("_static/b.js", defer="defer"),
               assets._JavaScript("_static/b.js")]
    assert unique_scripts(scripts) == scripts
    assert unique_scripts(["a.js", "b.js", "a.js"]) == ["a.js", "b.js"]
