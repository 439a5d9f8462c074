"""The book's conventions: one colour per quantity, derivatives coloured by their state or load."""

import numpy as np
import pytest

from flapping.book import style


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
