"""Helpers for the book's chapters: figures, the model schematic, tables and the paper's numbers.

- :mod:`~flapping.book.style`: one colour per quantity, one line style per model (plain data);
- :mod:`~flapping.book.plotting`: the figures (time histories, derivatives, multipliers);
- :mod:`~flapping.book.schematic`: the drawing of the paper's model, :func:`draw_insect_model`;
- :mod:`~flapping.book.tables`: Markdown tables and LaTeX ``aligned`` blocks for ``glue``;
- :mod:`~flapping.book.paper`: the paper's printed numbers and the consistency checks on them;
- :mod:`~flapping.book.sphinx_ext`: a Sphinx extension of the book's build (``_config.yml``).

Not re-exported from :mod:`flapping`: the chapters import them explicitly. Plotting needs the
``plot`` extra (matplotlib).
"""
