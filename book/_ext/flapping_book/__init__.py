"""Helpers for the book's chapters: figures, the model schematic, tables and the paper's numbers.

- :mod:`~flapping_book.style`: one colour per quantity, one line style per model (plain data);
- :mod:`~flapping_book.plotting`: the figures (time histories, derivatives, multipliers);
- :mod:`~flapping_book.schematic`: the drawing of the paper's model, :func:`draw_insect_model`;
- :mod:`~flapping_book.tables`: Markdown tables and LaTeX ``aligned`` blocks for ``glue``;
- :mod:`~flapping_book.paper`: the paper's printed numbers and the consistency checks on them;
- :mod:`~flapping_book.sphinx_ext`: a Sphinx extension of the book's build (``_config.yml``).

A package of its own beside the book (``book/_ext``, installed by ``environment.txt``), not part
of the ``flapping`` wheel: the chapters import its modules explicitly.
"""
