"""The book's conventions: one colour per quantity, derivatives coloured by their state or load."""

import numpy as np
import pytest

from flapping_book import style


def test_each_state_and_load_has_its_own_colour():
    colours = list(style.STATE_COLORS.values()) + list(style.LOAD_COLORS.values())
    assert len(set(colours)) == len(colours)
    assert set(style.STATE_COLORS) == set(style.STATE_NAMES) == set(style.STATE_LABELS)


def test_derivative_takes_the_colour_of_its_state_or_load():
    assert style.derivative_color("Mw") == style.STATE_COLORS["w"]
    assert style.derivative_color("Z0") == style.LOAD_COLORS["Z"]
    with pytest.raises(ValueError, match="name"):
        style.derivative_color("Xtheta")


def test_every_model_has_a_line_style_and_a_label():
    assert set(style.MODEL_LINESTYLES) == set(style.MODEL_LABELS)
    assert len(set(style.MODEL_LINESTYLES.values())) == len(style.MODEL_LINESTYLES)


def test_load_colours_are_not_grey():
    # grey is reserved for guide lines (zero, cycle means, envelopes)
    assert not any(style.is_grey(colour) for colour in style.LOAD_COLORS.values())


def test_sources_do_not_reuse_a_quantity_colour():
    quantities = set(style.STATE_COLORS.values()) | set(style.LOAD_COLORS.values())
    assert not quantities & set(style.SOURCE_COLORS.values())


def _redmean_distance(a: str, b: str) -> float:
    """Colour difference weighted for the eye ("redmean"); 0..~765, about 100 is a clear step."""
    import matplotlib.colors as mcolors

    (r1, g1, b1), (r2, g2, b2) = (255 * np.array(mcolors.to_rgb(c)) for c in (a, b))
    r = (r1 + r2) / 2
    return float(np.sqrt((2 + r / 256) * (r1 - r2) ** 2 + 4 * (g1 - g2) ** 2
                         + (2 + (255 - r) / 256) * (b1 - b2) ** 2))


def test_load_colours_are_far_from_state_and_source_colours():
    others = {**style.STATE_COLORS, **style.SOURCE_COLORS}
    for load, colour in style.LOAD_COLORS.items():
        for name, other in others.items():
            assert _redmean_distance(colour, other) > 130, (load, name)


@pytest.mark.parametrize("colour", ["0.55", "0", "1.0", "k", "white", "Grey", "#7f7f7f", "#FFFFFFFF",
                                    style.GUIDE_COLOR, style.SOURCE_COLORS["ours"]])
def test_greys_are_greys(colour):
    assert style.is_grey(colour)


@pytest.mark.parametrize("colour", [*style.STATE_COLORS.values(), style.SOURCE_COLORS["paper"],
                                    style.SOURCE_COLORS["averaged"], "C0", "red", "#7f7f7e", "1.5",
                                    "#zzzzzz"])
def test_colours_are_not_greys(colour):
    assert not style.is_grey(colour)


def test_is_grey_wants_a_string():
    with pytest.raises(ValueError, match="color"):
        style.is_grey((0.5, 0.5, 0.5))


def test_guide_lines_are_grey_and_distinct_from_every_quantity():
    import matplotlib.colors as mcolors

    assert style.is_grey(style.GUIDE_COLOR)
    r, g, b = mcolors.to_rgb(style.GUIDE_COLOR)
    assert r == g == b
