"""Fixtures shared by the unit tests: the paper's hawkmoth and its hover orbit, solved once."""

import pytest

import flapping


@pytest.fixture(scope="session")
def insect():
    return flapping.hawkmoth()


@pytest.fixture(scope="session")
def orbit(insect):
    return flapping.find_hover_orbit(insect)
