"""Tables and equations for ``myst_nb.glue``: Markdown pipe tables and LaTeX ``aligned`` blocks.

The chapters glue the strings as ``IPython.display.Markdown`` / ``Math`` objects. SymPy is needed
only for symbolic right-hand sides of :func:`latex_aligned` and is imported there.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from flapping_book.formatting import text_minus

__all__ = ["markdown_table", "latex_aligned", "book_symbols"]


def markdown_table(header: Sequence[str], rows: Sequence[Sequence],
                   align: str | None = None) -> str:
    """A Markdown (GFM/MyST) pipe table, for ``glue`` of ``IPython.display.Markdown`` objects.

    Parameters
    ----------
    header : sequence of str
        Column titles.
    rows : sequence of sequences
        Cells, converted with ``str``; ``|`` inside a cell is escaped, and a hyphen used as a
        minus sign outside math and code becomes U+2212
        (:func:`flapping_book.formatting.text_minus`).
    align : str, optional
        One character per column: ``l``, ``c`` or ``r``; default all left.

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If a row or ``align`` does not have one entry per column.
    """
    n = len(header)
    align = "l" * n if align is None else align
    if len(align) != n or set(align) - set("lcr"):
        raise ValueError(f"align must have one of 'l', 'c', 'r' per column ({n}); got {align!r}")
    rule = {"l": ":--", "c": ":-:", "r": "--:"}

    def line(cells):
        return "| " + " | ".join(str(c).replace("|", "\\|") for c in cells) + " |"

    out = [line(header), "|" + "|".join(rule[a] for a in align) + "|"]
    for row in rows:
        if len(row) != n:
            raise ValueError(f"every row needs {n} cells; got {len(row)} in {row!r}")
        out.append(line([text_minus(c) for c in row]))
    return "\n".join(out)


def latex_aligned(rows: Mapping[str, object], terms_per_line: int = 3, key=None) -> str:
    r"""A LaTeX ``aligned`` block of equations ``lhs &= rhs``, long sums broken every few terms.

    Parameters
    ----------
    rows : mapping
        Left-hand side (LaTeX) -> right-hand side: a SymPy expression (printed term by term with
        ``sympy.latex``) or a LaTeX string (used as is).
    terms_per_line : int
        Terms of a sum per line, >= 1.
    key : callable, optional
        Sort key for the terms of a sum (SymPy expressions), e.g. to put the terms that vanish
        for the hawkmoth last; default SymPy's order.

    Returns
    -------
    str
        ``\begin{aligned} ... \end{aligned}``, without math delimiters.
    """
    if terms_per_line < 1:
        raise ValueError(f"terms_per_line must be >= 1; got {terms_per_line!r}")
    lines = []
    for lhs, rhs in rows.items():
        if isinstance(rhs, str):
            lines.append(f"{lhs} &= {rhs}")
            continue
        import sympy  # only needed for symbolic right-hand sides

        terms = list(sympy.Add.make_args(rhs))
        if key is not None:
            terms.sort(key=key)
        printed = []
        for k, term in enumerate(terms):
            text = sympy.latex(term)
            printed.append(text if k == 0 or text.startswith("-") else "+ " + text)
        chunks = [" ".join(printed[k:k + terms_per_line])
                  for k in range(0, len(printed), terms_per_line)]
        lines.append(f"{lhs} &= " + r" \\ &\qquad ".join(chunks))
    return "\\begin{aligned}\n" + " \\\\[6pt]\n".join(lines) + "\n\\end{aligned}"


def book_symbols(latex: str) -> str:
    """The book's names in LaTeX made from the package's SymPy symbols.

    The package names Berman and Wang's damping coefficients ``mu1``, ``mu2`` as their paper
    does; the book writes them nu_1, nu_2, since mu_k are the Floquet multipliers there
    (book/notation.md). SymPy writes the subscript with or without braces; both are renamed.

    Parameters
    ----------
    latex : str
        LaTeX, e.g. from :func:`sympy.latex`.

    Returns
    -------
    str
    """
    for k in "12":
        latex = latex.replace(rf"\mu_{{{k}}}", rf"\nu_{{{k}}}").replace(rf"\mu_{k}", rf"\nu_{k}")
    return latex

