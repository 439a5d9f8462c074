"""What every solve reports (flapping.results): the status words, one table each."""

from __future__ import annotations

import json

import pytest

from flapping.results import STATUS_WORDS, HoverStatus, Status


def test_a_status_equals_its_word_and_nothing_of_another_table():
    # Reproducer (issue 35): HoverStatus.DRIFTING == Status.MAX_ITERATIONS was True (two
    # IntEnums), orbit.status == "hover" was False though it printed hover.
    assert HoverStatus.DRIFTING != Status.MAX_ITERATIONS
    assert all(h != s for h in HoverStatus for s in Status)
    assert HoverStatus.HOVER == "hover" and Status.SUCCESS == "success"
    assert HoverStatus.HOVER != 0 and Status.SUCCESS != 0 and Status.MAX_ITERATIONS != 1


@pytest.mark.parametrize("status", [*HoverStatus, *Status])
def test_a_status_prints_and_serialises_as_its_word(status):
    # Reproducer: json.dumps(orbit.status) gave 0 where the CLI said "hover".
    word = status.name.lower()
    assert str(status) == f"{status}" == status.value == word
    assert json.loads(json.dumps({"status": status})) == {"status": word}
    assert repr(status) == f"{type(status).__name__}.{status.name}"


def test_the_two_tables_share_no_word():
    assert len(STATUS_WORDS) == len(HoverStatus) + len(Status)


def test_a_status_is_found_by_its_kernel_code_and_nothing_else():
    assert [Status(s.code) for s in Status] == list(Status)
    assert Status.SUCCESS.code == 0
    for bad in (-1, len(Status), True, 1.0, "0"):
        with pytest.raises(ValueError):
            Status(bad)


def test_a_status_is_truthy_whatever_it_says():
    # An IntEnum's SUCCESS was falsy: code that read `if status:` for a failure now reads
    # status.success, and a word is never falsy.
    assert all(bool(s) for s in Status) and not Status.FAILED.success


def test_every_monodromy_is_offered_as_the_one_floquet_type():
    # Reproducer (issue 35): the monodromy lived in 8 types; each that carries one now gives it
    # as flapping.results.Floquet (.floquet), with the same multipliers.
    import numpy as np

    from flapping.periodic.fixedstep import find_periodic_orbit_fixed_step
    from flapping.periodic.floquet import monodromy
    from flapping.results import Floquet

    def field(t, x):
        return np.array([-x[0] + np.cos(t)])

    mon = monodromy(field, [0.5], 2 * np.pi)
    orbit = find_periodic_orbit_fixed_step(field, [0.5], 2 * np.pi)
    for source in (mon, orbit):
        assert type(source.floquet) is Floquet
        np.testing.assert_array_equal(source.floquet.multipliers, source.multipliers)
    # x' = -x + cos t: the one multiplier is exp(-2 pi), the exponent -1.
    assert mon.floquet.exponents[0] == pytest.approx(-1.0, abs=1e-9)
    assert orbit.floquet.exponents[0] == pytest.approx(-1.0, abs=1e-6)
