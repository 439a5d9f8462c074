"""The table of published hover-stability results (flapping.studies.literature) and the .bib."""

import dataclasses
import math
import re
from pathlib import Path

import pytest

from flapping.studies.literature import (
    ATTITUDES,
    METHODS,
    MODE_KINDS,
    MODE_STABILITIES,
    MODE_TYPES,
    MOTIONS,
    PUBLISHED,
    READINGS,
    STATUSES,
    VERDICTS,
    Mode,
    PublishedResult,
    as_rows,
    published_for,
    published_motion,
)

BIB = Path(__file__).resolve().parents[1] / "book" / "references.bib"
PRESETS = {"hawkmoth", "bumblebee", "fruit_fly", "honeybee", "hoverfly", "monarch"}

#: FWUAV's characteristic exponents [1/s] as the project's reading list gives them (READING.md,
#: three decimals): longitudinal 1, longitudinal 2, lateral.
READING_FWUAV = {
    "hawkmoth": (-1.776, -4.628, -1.481),
    "bumblebee": (-1.529, -2.892, -2.012),
    "fruit_fly": (-3.937, -7.036, -4.648),
}


def _bib_keys() -> set[str]:
    return set(re.findall(r"^@\w+\{([^,\s]+),", BIB.read_text(encoding="utf-8"), re.MULTILINE))


def _valid(**changes):
    base = dict(cite="sun2005", species="bumblebee", method="CFD", attitude="free",
                verdict="unstable", mode_type="oscillatory", status="verified", quote="q")
    base.update(changes)
    return PublishedResult(**base)


# ------------------------------------------------------------------ the records


def test_every_record_cites_a_key_of_the_bibliography():
    keys = _bib_keys()
    assert len(keys) > 30  # the parse found the file's entries
    missing = sorted({r.cite for r in PUBLISHED} - keys)
    assert not missing, f"cite keys missing from book/references.bib: {missing}"


def test_fields_are_in_their_sets():
    for r in PUBLISHED:
        assert r.status in STATUSES and r.mode_type in MODE_TYPES
        assert r.verdict in VERDICTS and r.attitude in ATTITUDES


def test_verified_records_carry_a_quote():
    for r in PUBLISHED:
        if r.status == "verified":
            assert r.quote.strip(), r


def test_numbers_are_positive_where_given():
    for r in PUBLISHED:
        for value in (r.doubling_time_s, r.oscillation_period_s, r.wingbeat_s):
            assert value is None or (math.isfinite(value) and value > 0)
        assert all(t > 0 for t in r.halving_times_s)


def test_a_doubling_time_agrees_with_the_stated_growth_rate():
    # Where a source gives both a doubling time and exponents, ln 2 / t_2 is the largest exponent.
    for r in PUBLISHED:
        if r.doubling_time_s is not None:
            assert r.verdict == "unstable"
            assert r.growth_rate_per_s == pytest.approx(math.log(2) / r.doubling_time_s)
            if r.exponents_per_s:
                assert max(r.exponents_per_s) == pytest.approx(r.growth_rate_per_s, rel=0.05)


def test_stable_records_have_no_growing_exponent():
    for r in PUBLISHED:
        if r.verdict == "stable" and r.exponents_per_s:
            assert max(r.exponents_per_s) < 0


def test_sun_and_xiong_bumblebee_is_the_abstracts_numbers():
    (r,) = [r for r in published_for("bumblebee") if r.cite == "sun2005"]
    assert (r.mode_type, r.verdict, r.status) == ("oscillatory", "unstable", "verified")
    assert (r.doubling_time_s, r.oscillation_period_s, r.wingbeat_s) == (0.1, 0.32, 6.4e-3)
    assert r.halving_times_s == (0.024, 0.37)
    assert r.doubling_time_wingbeats == pytest.approx(15.625)  # "more than 15 times"


def test_fwuav_exponents_are_the_reading_lists():
    for species, expected in READING_FWUAV.items():
        (r,) = [r for r in published_for(species) if r.cite == "fwuav"]
        assert r.attitude == "prescribed" and r.verdict == "stable"
        assert [round(e, 3) for e in r.exponents_per_s] == list(expected)


def test_species_names_are_presets_or_the_sources_own():
    for r in PUBLISHED:
        assert r.species in PRESETS or "_" not in r.species, r.species


def test_a_record_compared_with_a_preset_names_one_and_says_why():
    # Xu & Sun's model dronefly is our hoverfly's morphology; Wu & Sun's dronefly gives its
    # frequency: both compared with the hoverfly, each note saying how close the insects are.
    for r in PUBLISHED:
        assert r.preset is None or r.preset in PRESETS, r.preset
        assert r.compared_with == (r.preset or r.species)
    for cite in ("xu2015", "wu2012"):
        (r,) = [r for r in PUBLISHED if r.cite == cite and r.species == "dronefly"]
        assert r.compared_with == "hoverfly" and "hoverfly" in r.note


def test_preset_must_be_a_name_or_none():
    base = dict(cite="xu2015", species="dronefly", method="CFD", attitude="free",
                verdict="unstable", mode_type=None, status="verified", quote="q")
    assert PublishedResult(**base).compared_with == "dronefly"
    with pytest.raises(ValueError, match="`preset`"):
        PublishedResult(**base, preset="")


def test_records_are_frozen():
    with pytest.raises(dataclasses.FrozenInstanceError):
        PUBLISHED[0].status = "unverified"  # type: ignore[misc]


# ------------------------------------------------------------------ helpers


def test_published_for_returns_the_species_records_in_order():
    hawk = published_for("hawkmoth")
    assert hawk and all(r.species == "hawkmoth" for r in hawk)
    assert list(hawk) == [r for r in PUBLISHED if r.species == "hawkmoth"]
    assert {r.cite for r in hawk} >= {"gao2009", "taha2020", "fwuav", "sun2007acta", "wu2012"}


@pytest.mark.parametrize("bad", ["locust", "", None, 3, "Hawkmoth"])
def test_published_for_refuses_an_unknown_species(bad):
    with pytest.raises(ValueError, match="`species`"):
        published_for(bad)


def test_as_rows_puts_units_in_the_keys():
    rows = as_rows()
    assert len(rows) == len(PUBLISHED)
    row = next(r for r in rows if r["cite"] == "sun2005")
    assert row["doubling_time_ms"] == pytest.approx(100.0)
    assert row["oscillation_period_ms"] == pytest.approx(320.0)
    assert row["doubling_time_wingbeats"] == pytest.approx(0.1 / 6.4e-3)
    assert row["halving_times_ms"] == pytest.approx((24.0, 370.0))
    no_wingbeat = next(r for r in rows if r["cite"] == "gao2009")
    assert no_wingbeat["doubling_time_wingbeats"] is None


def test_as_rows_takes_a_selection_and_refuses_other_things():
    assert as_rows(published_for("monarch"))[0]["species"] == "monarch"
    assert as_rows([]) == []
    with pytest.raises(ValueError, match="`records`"):
        as_rows("sun2005")
    with pytest.raises(ValueError, match=r"`records\[0\]`"):
        as_rows([{"cite": "sun2005"}])


# ------------------------------------------------------------------ validation of a record


@pytest.mark.parametrize("field, value", [
    ("status", "checked"), ("mode_type", "divergent"), ("verdict", "neutral"),
    ("attitude", "fixed"), ("cite", ""), ("species", None), ("method", 3),
    ("doubling_time_s", -0.1), ("doubling_time_s", 0.0), ("wingbeat_s", float("nan")),
    ("oscillation_period_s", "0.3"), ("halving_times_s", (0.1, -1.0)), ("halving_times_s", 0.1),
    ("exponents_per_s", (1.0, float("inf"))), ("exponents_per_s", "1.0"), ("note", None),
])
def test_a_bad_field_is_refused_by_name(field, value):
    with pytest.raises(ValueError, match=rf"`{field}"):
        _valid(**{field: value})


def test_a_verified_record_needs_a_quote_and_a_stable_one_no_doubling_time():
    with pytest.raises(ValueError, match="`quote`"):
        _valid(quote="  ")
    assert _valid(status="unverified", quote="").quote == ""
    with pytest.raises(ValueError, match="`doubling_time_s`"):
        _valid(verdict="stable", mode_type="stable", doubling_time_s=0.1)


def test_numbers_are_stored_as_floats():
    r = _valid(doubling_time_s=1, halving_times_s=[2], exponents_per_s=[-1])
    assert type(r.doubling_time_s) is float and r.halving_times_s == (2.0,)
    assert r.exponents_per_s == (-1.0,) and isinstance(r.exponents_per_s, tuple)


# ------------------------------------------------------------------ the bibliography


def test_the_bibliography_parses_with_years_and_full_author_lists():
    database = pytest.importorskip("pybtex.database")
    entries = database.parse_file(str(BIB)).entries
    assert set(entries) == _bib_keys()
    for key, entry in entries.items():
        assert entry.fields.get("year", "").strip(), f"{key} has no year"
        for person in entry.persons.get("author", []):
            assert str(person) != "others", f"{key} ends its author list with 'and others'"


def test_every_key_the_book_cites_is_in_the_bibliography():
    book = BIB.parent
    cited = set()
    for page in book.glob("*.md"):
        for group in re.findall(r"\{cite(?::\w+)?\}`([^`]+)`", page.read_text(encoding="utf-8")):
            cited.update(k.strip() for k in group.split(","))
    assert cited and not cited - _bib_keys(), sorted(cited - _bib_keys())


def test_agreement_compares_mode_types_of_unstable_results_and_verdicts_otherwise():
    from flapping.studies.literature import agreement
    sun = next(r for r in PUBLISHED if r.cite == "sun2005" and r.species == "bumblebee")
    assert agreement(sun, "real", "unstable") == "no"  # similar rate, different instability
    assert agreement(sun, "oscillatory", "unstable") == "yes"
    assert agreement(sun, "real", "stable") == "no"
    stable = next(r for r in PUBLISHED if r.verdict == "stable")
    assert agreement(stable, "real", "stable") == "yes"
    with pytest.raises(ValueError, match="verdict"):
        agreement(sun, "real", "maybe")


# ------------------------------------------------------------------ motion, method, modes, reading


def test_labels_are_in_their_sets_and_no_row_is_there_twice():
    seen = set()
    for r in PUBLISHED:
        assert r.motion in MOTIONS and r.reading in READINGS
        assert r.methods and set(r.methods) <= set(METHODS), r.methods
        for m in r.modes:
            assert m.kind in MODE_KINDS and m.stability in MODE_STABILITIES
            assert m.motion in (None, "longitudinal", "lateral")
        key = (r.cite, r.species, r.motion)
        assert key not in seen, f"row {key} twice"
        seen.add(key)


def test_the_referees_missing_studies_are_in_the_table():
    cites = {r.cite for r in PUBLISHED}
    assert {"liang2013", "gao2011", "faruque2010a", "faruque2010b", "zhang2010", "xu2013",
            "zhu2020", "perl2022"} <= cites


def test_lateral_rows_are_found_by_the_filter_and_both_rows_by_either():
    lateral = published_motion("lateral")
    longitudinal = published_motion("longitudinal")
    assert all(r.is_lateral for r in lateral)
    assert not any(r.motion == "lateral" for r in longitudinal)
    both = [r for r in PUBLISHED if r.motion == "both"]
    assert both and all(r in lateral and r in longitudinal for r in both)
    assert {r.cite for r in lateral} >= {"zhang2010", "xu2013", "zhu2020", "perl2022", "xu2015"}
    with pytest.raises(ValueError, match="`motion`"):
        published_motion("both")


def test_zhang_and_sun_lateral_modes_type_first():
    (r,) = [r for r in PUBLISHED if r.cite == "zhang2010"]
    assert r.motion == "lateral" and r.mode_type == "real" and r.verdict == "unstable"
    assert [(m.kind, m.stability) for m in r.modes] == [
        ("real", "unstable"), ("oscillatory", "stable"), ("real", "stable")]
    assert r.mode_labels[0].startswith("real, unstable: slow divergence")
    assert r.compared_with == "hoverfly"


def test_the_lateral_rows_agree_with_the_lateral_chapters_table():
    # flapping.studies.lateral keeps its own records for its chapter: same sources, same verdicts
    # and, where both state it, the same type of unstable mode.
    from flapping.studies.lateral import PUBLISHED_LATERAL
    ours = {r.cite: r for r in published_motion("lateral")}
    for theirs in PUBLISHED_LATERAL:
        r = ours[theirs.cite]
        unstable = [kind for kind, stable in theirs.modes if not stable]
        assert r.verdict == "unstable" and unstable
        if unstable[0] is not None and r.mode_type is not None:
            assert r.mode_type == unstable[0], theirs.cite


def test_the_deciding_mode_is_among_the_stated_modes():
    # A record that names the deciding mode and lists modes must list an unstable one of that
    # type (or, for a stable verdict, only stable modes).
    for r in PUBLISHED:
        if not r.modes:
            continue
        unstable = [m for m in r.modes if m.stability == "unstable"]
        if r.verdict == "stable":
            assert not unstable, r.cite
        elif r.mode_type in ("real", "oscillatory"):
            assert any(m.kind == r.mode_type for m in unstable), r.cite
        if r.verdict == "unstable":
            assert unstable, r.cite


def test_fwuav_method_is_its_linearised_equations_and_it_covers_both_motions():
    for r in (r for r in PUBLISHED if r.cite == "fwuav"):
        assert "finite difference" not in r.method and "sim_pert" in r.method
        assert r.methods == ("QS",) and r.reading == "source" and r.motion == "both"
        assert [m.motion for m in r.modes] == ["longitudinal", "longitudinal", "lateral"]


def test_perl_and_beatus_find_an_oscillating_lateral_divergence_in_the_fruit_fly():
    rows = [r for r in published_for("fruit_fly") if r.cite in ("perl2022", "perl2023")]
    assert len(rows) == 2
    for r in rows:
        assert r.motion == "lateral" and r.mode_type == "oscillatory"
        assert r.taxon == "Drosophila melanogaster" and r.reading == "abstract"


def test_reading_follows_status_unless_given():
    assert _valid().reading == "abstract"
    assert _valid(status="second-hand").reading == "secondary"
    assert _valid(status="unverified", quote="").reading == "not read"
    assert _valid(reading="source").reading == "source"


@pytest.mark.parametrize("field, value", [
    ("motion", "vertical"), ("methods", "CFD"), ("methods", ()), ("methods", ("finite differences",)),
    ("modes", "real"), ("modes", ("real",)), ("reading", "skimmed"), ("taxon", None),
])
def test_a_bad_new_field_is_refused_by_name(field, value):
    with pytest.raises(ValueError, match=rf"`{field}"):
        _valid(**{field: value})


def test_a_mode_is_checked_and_says_its_motion_in_a_record_of_both():
    with pytest.raises(ValueError, match="`kind`"):
        Mode("divergent", "unstable")
    with pytest.raises(ValueError, match="`stability`"):
        Mode("real", "neutral")
    assert Mode("real", "stable", "fast subsidence").label == "real, stable: fast subsidence"
    with pytest.raises(ValueError, match=r"`modes\[0\]`"):
        _valid(motion="both", modes=(Mode("real", "unstable"),))
    with pytest.raises(ValueError, match=r"`modes\[0\]\.motion`"):
        _valid(motion="longitudinal", modes=(Mode("real", "unstable", motion="lateral"),))
    r = _valid(motion="both", modes=(Mode("real", "unstable", motion="lateral"),))
    assert r.mode_labels == ("lateral: real, unstable",)


def test_as_rows_carries_the_new_columns():
    row = next(r for r in as_rows() if r["cite"] == "zhang2010")
    assert row["motion"] == "lateral" and row["methods"] == ("CFD",)
    assert row["reading"] == "abstract" and len(row["modes"]) == 3
