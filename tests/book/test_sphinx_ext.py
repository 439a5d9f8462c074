"""The build extension drops the inline scripts Sphinx 7.4 writes twice (sphinx-doc/sphinx#13402)."""

import pytest

from flapping_book.sphinx_ext import unique_scripts

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


def test_exec_table_status_symbols_become_words():
    from flapping_book.sphinx_ext import EXEC_STATUS_TEXT, exec_status_text

    assert exec_status_text("\u2705") == "succeeded"
    assert exec_status_text(" \u274c ") == "failed"
    assert exec_status_text("force") is None
    # the words contain no emoji (no character outside the Basic Multilingual Plane's letters)
    assert all(word.isascii() for word in EXEC_STATUS_TEXT.values())


def test_exec_table_handler_rewrites_the_table_cells():
    nodes = pytest.importorskip("docutils.nodes")
    from flapping_book.sphinx_ext import _exec_status_as_words

    doctree = nodes.document(None, None)
    table = nodes.table()
    row = nodes.row()
    for text in ("intro", "force", "\u2705"):
        row += nodes.entry("", nodes.paragraph(text=text))
    table += row
    doctree += table
    _exec_status_as_words(None, doctree, "status")
    cells = [entry.astext() for entry in doctree.findall(nodes.entry)]
    assert cells == ["intro", "force", "succeeded"]
    assert "exec-status-succeeded" in list(doctree.findall(nodes.entry))[2]["classes"]


def test_captioned_exec_table_takes_the_rows_myst_nb_writes():
    nodes = pytest.importorskip("docutils.nodes")
    from flapping_book.sphinx_ext import CAPTIONED_EXEC_TABLE, merge_captioned_exec_tables

    doctree = nodes.document(None, None)
    outer = nodes.table(classes=[CAPTIONED_EXEC_TABLE], ids=["tab-status-exec"])
    outer += nodes.title(text="Execution of each page")
    inner = nodes.table(classes=["colwidths-auto"])  # what myst-nb's post-transform puts there
    tgroup = nodes.tgroup(cols=1)
    inner += tgroup
    outer += inner
    doctree += outer
    doctree += nodes.table(classes=["other"])  # other tables are left alone
    assert merge_captioned_exec_tables(doctree) == 1
    assert [type(c).__name__ for c in outer.children] == ["title", "tgroup"]
    assert outer["ids"] == ["tab-status-exec"] and "colwidths-auto" in outer["classes"]
    assert len(list(doctree.findall(nodes.table))) == 2
    assert merge_captioned_exec_tables(doctree) == 0  # idempotent
