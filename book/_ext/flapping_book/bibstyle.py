"""The References page's style: pybtex's ``plain``, sorted alphabetically as a reader reads names.

pybtex's ``plain`` sorts on the raw BibTeX of the names, lower-cased: a name in braces
(``{FDCL}``) or with an accent command (``Cvitanovi{\\'c}``) sorted after every plain letter, and an
entry with neither author nor editor (an online resource) came first. This style sorts on the
names as printed (LaTeX rendered to text, case-folded) and falls back on the title for an entry
without a person. It also prints an article's volume and issue when its pages are unknown (plain
printed the volume only together with pages).

Registered as the pybtex formatting style ``flapping`` (and its sorting style of the same name)
by :func:`register`, which the book's Sphinx extension calls (``_config.yml``:
``bibtex_default_style: flapping``). pybtex is imported by the build only.
"""

from __future__ import annotations

from typing import Any

__all__ = ["STYLE_NAME", "plain_text", "register", "sorting_key"]

#: The name of the style in ``_config.yml`` (``bibtex_default_style``).
STYLE_NAME = "flapping"


def plain_text(latex: str) -> str:
    """BibTeX/LaTeX as a reader reads it: ``Cvitanovi{\\'c}`` -> ``Cvitanović``, ``{FDCL}`` ->
    ``FDCL``."""
    from pybtex.richtext import Text  # type: ignore[import-untyped]

    return Text.from_latex(str(latex)).render_as("text")


def _person(person) -> str:
    names = (person.prelast_names + person.last_names, person.first_names + person.middle_names,
             person.lineage_names)
    return "  ".join(plain_text(" ".join(part)) for part in names)


def sorting_key(entry) -> tuple[str, str, str]:
    """(names, year, title) of a pybtex entry, as printed and case-folded: the authors (for a book
    without authors, its editors), else the title."""
    persons = entry.persons.get("author") or entry.persons.get("editor") or []
    title = plain_text(entry.fields.get("title", "")).casefold()
    names = "   ".join(_person(p) for p in persons).casefold() or title
    return names, str(entry.fields.get("year", "")), title


def register() -> None:
    """Register the ``flapping`` formatting and sorting styles with pybtex (idempotent)."""
    from pybtex.plugin import register_plugin  # type: ignore[import-untyped]
    from pybtex.style.formatting import toplevel  # type: ignore[import-untyped]
    from pybtex.style.formatting.plain import Style as Plain  # type: ignore[import-untyped]
    from pybtex.style.formatting.unsrt import date, pages  # type: ignore[import-untyped]
    from pybtex.style.sorting import BaseSortingStyle  # type: ignore[import-untyped]
    from pybtex.style.template import (  # type: ignore[import-untyped]
        field,
        first_of,
        join,
        optional,
        optional_field,
        sentence,
        tag,
        words,
    )

    class SortingStyle(BaseSortingStyle):
        def sorting_key(self, entry: Any) -> tuple[str, str, str]:
            return sorting_key(entry)

    class Style(Plain):
        default_sorting_style = STYLE_NAME

        def get_article_template(self, e: Any) -> Any:
            # plain's, plus its missing case: a volume (and issue) without pages, which plain
            # dropped (an article known by its number only printed no volume at all)
            volume_and_pages = first_of[
                optional[join[field("volume"), optional["(", field("number"), ")"], ":", pages]],
                optional[join[field("volume"), optional["(", field("number"), ")"]]],
                words["pages", pages],
            ]
            return toplevel[
                self.format_names("author"),
                self.format_title(e, "title"),
                sentence[tag("em")[field("journal")], optional[volume_and_pages], date],
                sentence[optional_field("note")],
                self.format_web_refs(e),
            ]

    register_plugin("pybtex.style.sorting", STYLE_NAME, SortingStyle, force=True)
    register_plugin("pybtex.style.formatting", STYLE_NAME, Style, force=True)
