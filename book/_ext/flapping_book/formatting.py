"""Numbers as a reader reads them: 1.2 × 10⁻¹³, not 1.2e-13; and a Sphinx extension doing it.

The chapters glue plain floats and write the format in the text (``{glue:text}`key:.1e```), so
that the glued *value* stays the number itself (``.ci/glue_dump.py`` diffs the values). Python's
``e`` format then prints ``1.2e-13``. :func:`scientific` turns such a string into the typeset form,
and the Sphinx extension (``setup``; listed in ``_config.yml``) applies it at build time to every
glued number (myst-nb's ``span.pasted-text``) and to every table cell that holds only such a
number (a plain negative number there gets a true minus sign, :func:`minus_sign`), so the text of
the chapters never needs to change for it. Code, math and literals are left alone.

Sphinx and docutils are imported by the build only.
"""

from __future__ import annotations

import re
from typing import Any

import numpy as np

__all__ = ["E_NUMBER", "PLAIN_NUMBER", "minus_sign", "text_minus", "scientific",
           "split_scientific", "latex_scientific", "roundoff_bound", "term_latex", "complex_text",
           "text_number", "latex_complex", "bmatrix", "latex_array", "source_markdown",
           "is_number_text", "setup"]

#: A number in Python's ``e`` notation, alone in its text: ``1.2e-13``, ``-3e+05``, ``4.0E2``.
E_NUMBER = re.compile(r"^(?P<sign>[-+−]?)(?P<mantissa>\d+(?:\.\d+)?)[eE](?P<exponent>[-+]?\d+)$")

#: A plain decimal number alone in its text, with its sign: ``-0.10``, ``+3``, ``12.5``.
PLAIN_NUMBER = re.compile(r"^[-+]?\d+(?:\.\d+)?$")

#: A hyphen used as a minus sign in text: not after a letter, digit, ``_`` or ``.`` (so not in
#: ``0.1-0.2``, ``e-04`` or ``k-1``), and before a digit, directly or after one space
#: (``0.98 - 0.01i``).
_TEXT_MINUS = re.compile(r"(?<![\w.])-(?= ?\d)")

_SUPERSCRIPT = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def term_latex(name: str) -> str:
    r"""A term of the equations of motion as the book writes it: ``"Z0/m"`` -> ``$Z_0/m$``,
    ``"Xu u"`` -> ``$X_u u$``, ``"g cos(theta)"`` -> ``$g \cos\theta$``, ``"M0/Iy"`` ->
    ``$M_0/I_y$`` (the keys of :func:`flapping.hover.orbit.force_budget`).

    Parameters
    ----------
    name : str

    Returns
    -------
    str
        Inline math.
    """
    tex = re.sub(r"\b([XZM])([0uwq])\b", r"\1_\2", name)
    tex = re.sub(r"(sin|cos)\(theta\)", lambda m: "\\" + m.group(1) + "\\theta", tex)
    return "$" + tex.replace("Iy", "I_y") + "$"


def split_scientific(text: str) -> tuple[str, str] | None:
    """``"1.2e-13"`` -> ``("1.2 × 10", "−13")``: the base and the exponent to set as superscript.

    A mantissa of exactly one (``"1e-06"``) is dropped: ``("10", "−6")``. The exponent loses its
    ``+`` and leading zeros and takes a true minus sign. Zero (``"0e+00"``) is ``("0", "")``.
    Returns ``None`` if ``text`` (stripped) is not a single number in ``e`` notation.
    """
    match = E_NUMBER.match(text.strip())
    if match is None:
        return None
    if float(match["mantissa"]) == 0:   # "0e+00": zero, not "0 × 10⁰"
        return "0", ""
    sign = "−" if match["sign"] in ("-", "−") else ""
    exponent = int(match["exponent"])
    power = ("−" if exponent < 0 else "") + str(abs(exponent))
    mantissa = match["mantissa"]
    base = "10" if mantissa == "1" else f"{mantissa} × 10"
    return sign + base, power


def scientific(text: str) -> str:
    """``"1.2e-13"`` -> ``"1.2 × 10⁻¹³"`` in Unicode; any other text unchanged."""
    parts = split_scientific(text)
    if parts is None:
        return text
    base, power = parts
    return base + power.replace("−", "-").translate(_SUPERSCRIPT)


def minus_sign(text: str) -> str:
    """``"-0.10"`` -> ``"−0.10"``: a lone plain number's hyphen becomes the minus sign (U+2212)."""
    stripped = text.strip()
    if stripped.startswith("-") and PLAIN_NUMBER.match(stripped):
        return text.replace("-", "\u2212", 1)
    return text


def text_minus(text: str) -> str:
    """Every minus sign in running text as U+2212: ``"-21%"`` -> ``"−21%"``,
    ``"0.98 - 0.01i"`` -> ``"0.98 − 0.01i"``; ranges (``"0.1-0.2"``), exponents (``"e-04"``) and
    words stay. Text with math (``$``) or code (backticks) is returned unchanged.
    """
    text = str(text)
    if "$" in text or "`" in text:
        return text
    return _TEXT_MINUS.sub("\u2212", text)


def text_number(value: float, fmt: str = ".6g") -> str:
    """A number as a reader reads it, for printed output: formatted with ``fmt``, then
    ``1.2 × 10⁻¹³`` for e notation and a true minus sign: ``text_number(-1.28211e-14)`` ->
    ``"−1.28211 × 10⁻¹⁴"``, ``text_number(-2.40395)`` -> ``"−2.40395"``."""
    return text_minus(scientific(format(float(value), fmt)))


def complex_text(z: complex, digits: int = 4) -> str:
    """A multiplier or eigenvalue as text: ``"0.9871"`` if real, else ``"0.9871 − 0.0108i"``,
    with true minus signs (U+2212) and ``digits`` decimals."""
    z = complex(z)
    if abs(z.imag) < 1e-12:
        return text_minus(f"{z.real:.{digits}f}")
    sign = "+" if z.imag > 0 else "-"
    return text_minus(f"{z.real:.{digits}f} {sign} {abs(z.imag):.{digits}f}i")


def latex_complex(z: complex, digits: int = 4, pair: bool = False) -> str:
    r"""A complex number as LaTeX: ``-0.25 + 8.67i``, or with ``pair`` the conjugate pair
    ``-0.25 \pm 8.67i``; a real number (imaginary part below 1e-12) alone."""
    z = complex(z)
    if abs(z.imag) < 1e-12:
        return f"{z.real:.{digits}f}"
    sign = r"\pm" if pair else ("+" if z.imag > 0 else "-")
    return f"{z.real:.{digits}f} {sign} {abs(z.imag):.{digits}f}i"


def latex_array(header, rows, align: str | None = None) -> str:
    r"""A small table as a LaTeX ``array`` (no math delimiters), for a cell's ``Math`` output:
    header cells in LaTeX, a rule below them, the rows' cells in LaTeX (converted with ``str``).

    Raises
    ------
    ValueError
        If a row or ``align`` does not have one entry per column.
    """
    n = len(header)
    align = "c" * n if align is None else align
    if len(align) != n or any(len(row) != n for row in rows):
        raise ValueError(f"align and every row need {n} entries; got {align!r}, {rows!r}")
    body = r" \\ ".join(" & ".join(str(c) for c in row) for row in rows)
    return (r"\begin{array}{" + align + "}" + " & ".join(header) + r" \\ \hline " + body
            + r" \end{array}")


def bmatrix(matrix, fmt: str) -> str:
    r"""A real matrix as a LaTeX ``bmatrix`` (no math delimiters), each entry formatted with
    ``fmt``: ``bmatrix([[1, -2]], ".1f")`` -> ``\begin{bmatrix}1.0 & -2.0\end{bmatrix}``."""
    rows = [" & ".join(format(v, fmt) for v in row) for row in np.atleast_2d(np.asarray(matrix))]
    return r"\begin{bmatrix}" + r" \\ ".join(rows) + r"\end{bmatrix}"


def latex_scientific(value: float, digits: int = 2) -> str:
    r"""A float as LaTeX: ``1.2 \times 10^{-13}`` (``digits`` significant digits).

    Numbers between 10⁻² and 10⁴ are written plainly.
    """
    if value == 0 or 1e-2 <= abs(value) < 1e4:
        return f"{value:.{digits}g}"
    mantissa, exponent = f"{value:.{digits - 1}e}".split("e")
    base = "" if mantissa in ("1", "1.0") else mantissa + r" \times "
    return f"{base}10^{{{int(exponent)}}}"


def roundoff_bound(value: float, scale: float) -> float:
    """The size of a quantity that vanishes up to round-off, as a bound that never prints as 0.

    ``max(|value|, eps |scale|)``, with ``eps`` the double-precision machine epsilon and
    ``scale`` the magnitude of the numbers it was computed from: "zero to within ..." then reads
    the same whether the round-off happened to cancel exactly on this machine or not.
    """
    return max(abs(float(value)), float(np.finfo(float).eps) * abs(float(scale)))


#: Plain-text formulas of the presets' source notes (``flapping.model.presets``) and their LaTeX.
#: Longest first, so that ``S = R c_bar`` is replaced before ``c_bar``.
_SOURCE_FORMULAS = (
    ("r2 = 0.929 r1^0.732", r"$\hat r_2 = 0.929\,\hat r_1^{0.732}$"),
    ("m (L^2 + d^2)/20", r"$m\,(L^2 + d^2)/20$"),
    ("(m / m_monarch)^(1/3)", r"$(m/m_\mathrm{monarch})^{1/3}$"),
    ("R x c_bar = 51.9 x 18.26 mm", r"$R \times \bar c$ = 51.9 mm × 18.26 mm"),
    ("S = R c_bar", r"$S = R\,\bar c$"),
    ("2 m_w / m", r"$2 m_w / m$"),
    ("c_bar ~", r"$\bar c \approx$"),
    ("c_bar", r"$\bar c$"),
    ("+-", "±"),
    ("measured r1 ", r"measured $\hat r_1$ "),
)
#: Data-file and variable names in the source notes, set as code: ``morp_params.mat``,
#: ``sim_QS_x_hover_*.mat``, ``WK.beta``.
_SOURCE_CODE = re.compile(r"(?<![`\w])((?:[\w*-]+/)*[\w*-]+\.(?:mat|m)\b|WK\.\w+)(?![\w`])")


def source_markdown(text: str) -> str:
    r"""A preset's source or note (plain text in :mod:`flapping.model.presets`) as Markdown for a
    table: its formulas as math (``r2 = 0.929 r1^0.732`` -> :math:`\hat r_2 = 0.929\,\hat
    r_1^{0.732}`), file and variable names as code (```morp_params.mat```), ``~60 deg`` as
    ``≈60°``.

    Parameters
    ----------
    text : str
        Plain text.

    Returns
    -------
    str
        Markdown; text without formulas, names or degrees is returned unchanged.
    """
    text = str(text)
    for plain, latex in _SOURCE_FORMULAS:
        text = text.replace(plain, latex)
    text = _SOURCE_CODE.sub(r"`\1`", text)
    text = re.sub(r"~\s?(?=\d)", "≈", text)
    return re.sub(r"(\d) deg\b", "\\1°", text)


_NUMBER_CELL = re.compile(r"[-+−±]?\s?\d[\d.,]*(?:\s?(?:[eE]|×\s?10)[-+−⁻]?[\d⁰¹²³⁴⁵⁶⁷⁸⁹]+)?"
                          r"(?:\s?[-+−±]\s?\d[\d.]*i)?")


def is_number_text(text: str) -> bool:
    """Whether a table cell holds one number and nothing else: ``1.558652210716``, ``-3e-05``,
    ``−0.25 ± 8.67i``, ``+0.123`` (a sign, digits, a decimal point, an exponent, ``±`` and ``i``
    of a complex number; spaces between them)."""
    text = str(text).strip()
    return bool(text) and _NUMBER_CELL.fullmatch(text) is not None


# ------------------------------------------------------------------------------ Sphinx extension
def _typeset(node, nodes) -> bool:
    """Typeset the lone number that is ``node``'s only child: base + superscript, or a true minus
    sign; True if done."""
    if len(node.children) != 1 or not isinstance(node.children[0], nodes.Text):
        return False
    parts = split_scientific(node.astext())
    if parts is None:
        typeset = minus_sign(node.astext())
        if typeset == node.astext():
            return False
        node.children = [nodes.Text(typeset)]
        return True
    base, power = parts
    node.children = []
    node += nodes.Text(base)
    if power:
        node += nodes.superscript(power, power)
    return True


def _transform(app, doctree, docname) -> None:
    """``doctree-resolved``: glued numbers and lone numbers in table cells, in 10ⁿ form."""
    from docutils import nodes

    for node in list(doctree.findall(nodes.inline)):
        if "pasted-text" in node.get("classes", []):
            _typeset(node, nodes)
    for entry in list(doctree.findall(nodes.entry)):
        if is_number_text(entry.astext()):
            entry["classes"].append("number")  # custom.css: a long number may break on a phone
        for paragraph in entry.findall(nodes.paragraph):
            _typeset(paragraph, nodes)


def setup(app) -> dict[str, Any]:
    """Register the transform (after myst-nb has pasted the glued values)."""
    app.connect("doctree-resolved", _transform)
    return {"version": "1", "parallel_read_safe": True, "parallel_write_safe": True}
