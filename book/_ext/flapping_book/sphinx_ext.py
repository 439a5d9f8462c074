"""A Sphinx extension for the book's build (``_config.yml``: ``sphinx: extra_extensions``).

It works around a Sphinx 7.4 bug that writes some inline scripts twice into every page:
``Sphinx.add_js_file(None, body=...)`` called after the builder is set up registers the script
with the HTML builder under the file name ``None``, and ``StandaloneHTMLBuilder.prepare_writing``
adds it again from the registry under the name ``""``; the two do not compare equal, so both are
written. sphinx-thebe's ``const THEBE_JS_URL = ...`` is one of them (it is added at
``env-before-read-docs``), and its second copy throws "Identifier 'THEBE_JS_URL' has already been
declared" on every page; sphinx-togglebutton's ``var togglebuttonSelector`` is another (harmless).
Fixed upstream by sphinx-doc/sphinx#13402 ("Sphinx.add_js_file(): replace None filename with ''
before passing to HTML builder", Sphinx 8.2.x); remove this extension when Sphinx is upgraded.

It also writes the status column of myst-nb's ``nb-exec-table`` (``book/status.md``) as words:
myst-nb writes it as the emoji U+2705 / U+274C, which show as empty boxes where no emoji font is
installed (the book is read offline). :func:`exec_status_text` maps them; the handler replaces
them in every table of the resolved doctree and tags the cell ``exec-status-succeeded`` or
``exec-status-failed`` for CSS.

And it numbers and captions that table like every other table of the book: myst-nb's
``nb-exec-table`` is a placeholder that a post-transform replaces with the table at write time,
after Sphinx has numbered the tables, so a ``{table}`` directive cannot wrap it. The directive
``{captioned-exec-table} caption`` (with ``:name:``) writes a table node with the caption and the
placeholder inside, which Sphinx numbers; :func:`merge_captioned_exec_tables` then moves the rows
myst-nb wrote into that numbered table (``doctree-resolved``).

Sphinx is imported by the build only: nothing in :mod:`flapping` imports this module.
"""

from __future__ import annotations

from typing import Any

__all__ = ["unique_scripts", "exec_status_text", "EXEC_STATUS_TEXT", "CAPTIONED_EXEC_TABLE",
           "merge_captioned_exec_tables", "setup"]

#: Class of the numbered table that :func:`merge_captioned_exec_tables` fills.
CAPTIONED_EXEC_TABLE = "captioned-exec-table"

#: myst-nb's execution-table status symbols (myst_nb.ext.execution_tables) and the book's words.
EXEC_STATUS_TEXT: dict[str, str] = {"\u2705": "succeeded", "\u274c": "failed"}


def _script_key(script: Any) -> tuple:
    """What makes two ``<script>`` tags the same: source file (None and "" alike), attributes."""
    filename = getattr(script, "filename", script)
    attributes = getattr(script, "attributes", {})
    return (filename or "", tuple(sorted((str(k), str(v)) for k, v in attributes.items())))


def unique_scripts(scripts: list) -> list:
    """The scripts in their order, each only at its first occurrence.

    Parameters
    ----------
    scripts : list
        Sphinx's ``script_files`` (``_JavaScript`` objects, or file names).

    Returns
    -------
    list
        ``scripts`` without the repeats.
    """
    seen: set[tuple] = set()
    unique = []
    for script in scripts:
        key = _script_key(script)
        if key not in seen:
            seen.add(key)
            unique.append(script)
    return unique


def _drop_repeated_scripts(app, pagename, templatename, context, doctree) -> None:
    """``html-page-context`` handler: the page's ``script_files`` without repeats, in place."""
    scripts = context.get("script_files")
    if scripts:
        scripts[:] = unique_scripts(scripts)


def exec_status_text(text: str) -> str | None:
    """The word for an execution-table status symbol (``"\u2705"`` -> ``"succeeded"``); None for
    any other text."""
    return EXEC_STATUS_TEXT.get(text.strip())


def _exec_status_as_words(app, doctree, docname) -> None:
    """``doctree-resolved``: the status symbols in tables (the nb-exec-table) as words."""
    from docutils import nodes

    for table in list(doctree.findall(nodes.table)):
        for text in list(table.findall(nodes.Text)):
            word = exec_status_text(text.astext())
            if word is None:
                continue
            text.parent.replace(text, nodes.Text(word))
            for entry in table.findall(nodes.entry):
                if word in entry.astext() and entry.astext().strip() == word:
                    entry["classes"].append(f"exec-status-{word}")


def merge_captioned_exec_tables(doctree) -> int:
    """Move the rows of each execution table into the numbered, captioned table around it.

    The directive leaves ``table(title, placeholder)``; myst-nb's post-transform replaces the
    placeholder by its own table, giving ``table(title, table(tgroup))``. This makes it
    ``table(title, tgroup)`` with the inner table's classes, keeping the outer ids (the number).

    Parameters
    ----------
    doctree : docutils.nodes.document
        A resolved doctree (after the post-transforms).

    Returns
    -------
    int
        How many tables were merged.
    """
    from docutils import nodes

    merged = 0
    for outer in list(doctree.findall(nodes.table)):
        if CAPTIONED_EXEC_TABLE not in outer["classes"]:
            continue
        for inner in [child for child in outer.children if isinstance(child, nodes.table)]:
            outer["classes"] += [c for c in inner["classes"] if c not in outer["classes"]]
            index = outer.index(inner)
            outer.remove(inner)
            for offset, child in enumerate(list(inner.children)):
                if not isinstance(child, nodes.title):
                    inner.remove(child)
                    outer.insert(index + offset, child)
            merged += 1
    return merged


def _merge_exec_tables(app, doctree, docname) -> None:
    """``doctree-resolved``: :func:`merge_captioned_exec_tables`."""
    merge_captioned_exec_tables(doctree)


def _captioned_exec_table_directive():
    """The ``{captioned-exec-table}`` directive class (built lazily: Sphinx and myst-nb are
    imported by the build only)."""
    from docutils import nodes
    from docutils.parsers.rst import directives
    from myst_nb.ext.execution_tables import METADATA_KEY, ExecutionStatsNode
    from myst_nb.sphinx_ import NbMetadataCollector
    from sphinx.util.docutils import SphinxDirective

    class CaptionedExecTable(SphinxDirective):
        """myst-nb's ``nb-exec-table``, inside a numbered table with a caption."""

        required_arguments = 1
        final_argument_whitespace = True
        option_spec = {"name": directives.unchanged}

        def run(self):
            NbMetadataCollector.set_doc_data(self.env, self.env.docname, METADATA_KEY, True)
            table = nodes.table(classes=[CAPTIONED_EXEC_TABLE])
            inline, messages = self.state.inline_text(self.arguments[0], self.lineno)
            table += nodes.title(self.arguments[0], "", *inline)
            self.add_name(table)
            table += ExecutionStatsNode()
            return [table, *messages]

    return CaptionedExecTable


def setup(app) -> dict[str, Any]:
    """Register the handlers (the scripts' late, after extensions that add per-page scripts)."""
    app.connect("html-page-context", _drop_repeated_scripts, priority=900)
    app.add_directive("captioned-exec-table", _captioned_exec_table_directive())
    # the rows first, then their status symbols as words
    app.connect("doctree-resolved", _merge_exec_tables, priority=400)
    app.connect("doctree-resolved", _exec_status_as_words)
    # The References page's style (bibtex_default_style: flapping): alphabetical as printed.
    from flapping_book.bibstyle import register

    register()
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
