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

Sphinx is imported by the build only: nothing in :mod:`flapping` imports this module.
"""

from __future__ import annotations

from typing import Any

__all__ = ["unique_scripts", "setup"]


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


def setup(app) -> dict[str, Any]:
    """Register the handler (run late, after extensions that add per-page scripts)."""
    app.connect("html-page-context", _drop_repeated_scripts, priority=900)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
