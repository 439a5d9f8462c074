"""Fixtures shared by the unit tests: the paper's hawkmoth and its hover orbit, solved once."""

import pytest

import flapping


@pytest.fixture(scope="session")
def insect():
    return flapping.hawkmoth()


@pytest.fixture(scope="session")
def orbit(insect):
    # The reference: the paper's method (LM shooting on adaptive DOP853), whose diagnostics the
    # tests read; the compiled default is checked against it in tests/test_hover_problem.py.
    return flapping.find_hover_orbit(insect, backend="adaptive")
