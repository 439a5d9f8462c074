"""The References page as printed: alphabetical, every article's volume, no "3 edition"."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

pybtex = pytest.importorskip("pybtex")

from flapping_book.bibstyle import STYLE_NAME, plain_text, register  # noqa: E402

BIB = Path(__file__).resolve().parents[2] / "book" / "references.bib"


@pytest.fixture(scope="module")
def printed():
    """(key, text) of every entry, in the order of the References page."""
    import pybtex.plugin
    from pybtex.database import parse_file

    register()
    bibliography = parse_file(str(BIB))
    style = pybtex.plugin.find_plugin("pybtex.style.formatting", STYLE_NAME)()
    entries = style.format_bibliography(bibliography).entries
    return bibliography, [(e.key, e.text.render_as("text")) for e in entries]


def test_the_book_uses_this_style():
    config = (BIB.parents[1] / "_config.yml").read_text(encoding="utf-8")
    assert re.search(rf"bibtex_default_style:\s*{STYLE_NAME}\b", config)


def test_references_are_alphabetical_as_printed(printed):
    # by the first author's (or editor's) surname as printed, else the title: what a reader scans
    bibliography, entries = printed
    names = []
    for key, text in entries:
        entry = bibliography.entries[key]
        persons = entry.persons.get("author") or entry.persons.get("editor")
        surname = " ".join(persons[0].last_names) if persons else entry.fields["title"]
        names.append(plain_text(surname).casefold())
        assert plain_text(surname).casefold() in text.casefold(), (key, text)
    out_of_order = [(a, b) for a, b in zip(names[:-1], names[1:], strict=True) if a > b]
    assert not out_of_order, out_of_order


def test_every_article_prints_its_volume_and_no_edition_as_a_digit(printed):
    bibliography, entries = printed
    for key, text in entries:
        fields = bibliography.entries[key].fields
        if "volume" in fields:
            assert re.search(rf"\b{re.escape(fields['volume'])}\b", text), (key, text)
        assert not re.search(r"\b\d+ edition\b", text), (key, text)
        assert "\\url" not in text, (key, text)


def test_plain_text_renders_latex_names():
    assert plain_text("Cvitanovi{\\'c}") == "Cvitanović"
    assert plain_text("{FDCL}") == "FDCL"
