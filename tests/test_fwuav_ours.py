"""Our model at FWUAV's morphology (flapping.studies.fwuav): the translation, the derivatives,
the swap."""

from __future__ import annotations

import dataclasses
import json
import math
from pathlib import Path

import numpy as np
import pytest

from flapping._numdiff import central_jacobian
from flapping.peers.fwuav import FwuavPitchFree, prescribed_motion
from flapping.peers.fwuav.data import species
from flapping.peers.fwuav.model import _rot
from flapping.studies import fwuav as F
from flapping.studies.cfd import DERIVATIVES

SP = species("hawkmoth")


@pytest.fixture(scope="module")
def ours():
    tr = F.fwuav_translation("hawkmoth")
    orbit, stab = F._solve(tr.insect, tr.alpha_m)
    return tr, orbit, stab


def test_mass_centre_of_mass_and_inertia_match_fwuav_by_the_parallel_axes_the_other_way():
    # Independent route: FWUAV's pitch-free model's own bodies (inertias about their centres of
    # mass), FWUAV's rotation, the inertia about the thorax's centre of mass first and then
    # shifted to the combined centre of mass (I_G = I_O - m |OG|^2).
    tr = F.fwuav_translation("hawkmoth", "inertia")
    m = SP.morphology
    assert tr.insect.mass == pytest.approx(m.m_B + m.m_A + 2 * m.m_wing, rel=1e-15)
    m_A, mu_A, nu_A, Jc_A = FwuavPitchFree("hawkmoth")._bodies[2]
    p = mu_A + _rot(1, SP.kinematics.theta_A_0) @ nu_A
    body = m.m_B + m_A
    cg = m_A * p / body
    i_origin = np.array(m.J_B).reshape(3, 3)[1, 1] + Jc_A[1, 1] + m_A * (p[0] ** 2 + p[2] ** 2)
    i_cg = i_origin - body * (cg[0] ** 2 + cg[2] ** 2)
    np.testing.assert_allclose(tr.centre_of_mass, cg, rtol=1e-12, atol=1e-15)
    assert tr.insect.pitch_inertia == pytest.approx(i_cg, rel=1e-12)


def test_lumped_inertia_is_the_wingbeat_mean_of_the_four_bodies_inertia():
    # Independent route: at each instant the four bodies' pitch inertia about the mean centre
    # of mass (left wing from FWUAV's own left-wing attitude), averaged over a wingbeat.
    tr = F.fwuav_translation("hawkmoth", "lumped")
    model = FwuavPitchFree("hawkmoth")
    (m_w, mu_R, nu_R, J_R), (_, mu_L, nu_L, J_L), (m_A, mu_A, nu_A, J_A) = model._bodies
    T, n = model.period, 256
    cg, total = tr.centre_of_mass, []
    for t in np.arange(n) * T / n:
        mo = prescribed_motion(SP, float(t))
        parts = [(SP.morphology.m_B, np.zeros(3), np.array(SP.morphology.J_B).reshape(3, 3)),
                 (m_A, mu_A + _rot(1, SP.kinematics.theta_A_0) @ nu_A, J_A),
                 (m_w, mu_R + mo.Q_R @ nu_R, mo.Q_R @ J_R @ mo.Q_R.T),
                 (m_w, mu_L + mo.Q_L @ nu_L, mo.Q_L @ J_L @ mo.Q_L.T)]
        total.append(sum(J[1, 1] + mi * ((p[0] - cg[0]) ** 2 + (p[2] - cg[2]) ** 2)
                         for mi, p, J in parts))
    assert tr.insect.wing_mass == 0.0
    assert tr.insect.pitch_inertia == pytest.approx(np.mean(total), rel=1e-12)


@pytest.mark.parametrize("wings", F.WINGS)
def test_hinge_is_the_wing_root_from_the_centre_of_mass_in_stroke_plane_axes(wings):
    # Independent route: through the inertial frame at FWUAV's hover posture: the stroke
    # plane's forward tangent R(theta_B0) Ry(beta) e3 and its upward normal R Ry(beta) e1.
    tr = F.fwuav_translation("hawkmoth", wings)
    k = SP.kinematics
    R = _rot(1, k.theta_B_0)
    d = R @ (np.array([0.0, 0.0, 0.0]) - tr.centre_of_mass)  # the root is on the thorax's axis
    forward = R @ _rot(1, k.beta) @ np.array([0.0, 0.0, 1.0])
    up = R @ _rot(1, k.beta) @ np.array([1.0, 0.0, 0.0])
    assert up[2] < 0  # the stroke plane's normal points up (z down)
    assert tr.insect.hinge_offset == pytest.approx(float(d @ forward), rel=1e-12)
    assert tr.insect.hinge_height == pytest.approx(float(d @ up), rel=1e-12)
    assert tr.insect.hinge_height > 0  # the wing root above the centre of mass


def test_a_root_off_the_thorax_axis_moves_the_hinge_by_its_offset(monkeypatch):
    # FWUAV's three insects have the root on the thorax's axis (mu_R x = z = 0), so the root's
    # own term is checked here: moved by (dx, dz) in the thorax frame, through the inertial
    # frame as above; with wings="inertia" the centre of mass does not depend on the root.
    dx, dz = 1.3e-3, -0.7e-3
    m = dataclasses.replace(SP.morphology, mu_R=(SP.morphology.mu_R[0] + dx,
                                                 SP.morphology.mu_R[1],
                                                 SP.morphology.mu_R[2] + dz))
    moved = dataclasses.replace(SP, morphology=m)
    monkeypatch.setattr(F, "species", lambda name: moved)
    tr = F.fwuav_translation("hawkmoth", "inertia")
    k = SP.kinematics
    R = _rot(1, k.theta_B_0)
    d = R @ (np.array([m.mu_R[0], 0.0, m.mu_R[2]]) - tr.centre_of_mass)
    forward = R @ _rot(1, k.beta) @ np.array([0.0, 0.0, 1.0])
    up = R @ _rot(1, k.beta) @ np.array([1.0, 0.0, 0.0])
    assert tr.insect.hinge_offset == pytest.approx(float(d @ forward), rel=1e-12)
    assert tr.insect.hinge_height == pytest.approx(float(d @ up), rel=1e-12)


def test_wing_shape_radii_from_the_chord_polynomial_by_the_trapezoid_rule():
    tr = F.fwuav_translation("hawkmoth")
    m = SP.morphology
    r = np.linspace(0.0, m.span, 200_001)
    c = np.polyval(np.array(m.chord_poly), r / m.scale) * m.scale
    area = np.trapezoid(c, r)
    # trapezoid error ~ (R/N)^2: 1e-9 relative here
    assert tr.insect.wing_area == pytest.approx(area, rel=1e-8)
    assert tr.insect.wing_area == pytest.approx(m.area, rel=1e-6)  # FWUAV's stored S
    assert tr.insect.r1 == pytest.approx(np.trapezoid(c * r, r) / (area * m.span), rel=1e-8)
    assert tr.insect.r2 == pytest.approx(
        math.sqrt(np.trapezoid(c * r * r, r) / (area * m.span ** 2)), rel=1e-8)


def test_every_field_has_a_known_status_and_the_gaps_are_sized():
    tr = F.fwuav_translation("bumblebee")
    assert {r["status"] for r in tr.rows} <= set(F.STATUSES)
    assert all(math.isfinite(g["size"]) for g in tr.not_represented)
    # alpha_m is pi/2 minus FWUAV's mid-stroke wing pitch: between the two half-strokes' values
    k = species("bumblebee").kinematics
    assert 0.5 * math.pi - k.theta_m - abs(k.theta_0) <= tr.alpha_m <= 0.5 * math.pi


def test_our_derivatives_agree_with_central_differences_of_our_loads_along_the_orbit(ours):
    # The averaged Jacobian of the hover analysis against central differences of our
    # right-hand side, averaged by the trapezoid rule on each half-stroke (the loads jump at
    # reversal): O(h^2) with 256 intervals per half-stroke, ~1e-5 relative.
    tr, orbit, stab = ours
    t, x, model = orbit.t, orbit.x, orbit.model
    half = (len(t) - 1) // 2
    total = np.zeros((4, 4))
    for sl, stroke in ((slice(0, half + 1), -1.0), (slice(half, None), 1.0)):
        js = np.array([central_jacobian(lambda z, ti=ti, s=stroke: model.rhs(ti, z, stroke=s), xi)
                       for ti, xi in zip(t[sl], x[:, sl].T, strict=True)])
        total += np.trapezoid(js, t[sl], axis=0)
    fd = total / orbit.period
    ref = F.Reference.of(tr)
    d_fd = ref.derivatives(ref.nondimensional(fd))
    d = ref.derivatives(ref.nondimensional(stab.averaged_jacobian))
    scale = np.max(np.abs(d))
    np.testing.assert_allclose(d, d_fd, atol=1e-4 * scale)
    assert d[DERIVATIVES.index("Mu")] == pytest.approx(d_fd[DERIVATIVES.index("Mu")],
                                                       abs=1e-4 * scale)


def test_nondimensional_form_keeps_the_modes(ours):
    # A+ = T D^-1 J D: eigenvalues of A+ over T are those of J.
    tr, _, stab = ours
    ref = F.Reference.of(tr)
    a = ref.nondimensional(stab.averaged_jacobian)
    np.testing.assert_allclose(np.sort_complex(np.linalg.eigvals(a) / ref.period),
                               np.sort_complex(np.asarray(stab.averaged_eigenvalues)),
                               rtol=1e-10)


@pytest.fixture(scope="module")
def physics():
    return F.fwuav_physics_table(F.fwuav_translation("hawkmoth"))


def _row(table, how, step):
    return table[(table.how == how) & (table.step == step)].iloc[0]


def test_accumulated_physics_end_at_the_translated_insect(ours, physics):
    # Two routes to one insect: the base with FWUAV's hinge, wing inertia and angle of attack
    # added, and the translation itself; one orbit, so M_u+ agrees to the solver's accuracy.
    tr, _, stab = ours
    ref = F.Reference.of(tr)
    mu = ref.derivatives(ref.nondimensional(stab.averaged_jacobian))[DERIVATIVES.index("Mu")]
    assert _row(physics, "accumulated", "+ angle of attack")["Mu"] == pytest.approx(mu, rel=1e-6)


def test_our_model_on_fwuavs_morphology_is_oscillatory_and_the_hinge_carries_it(ours, physics):
    # The finding: on FWUAV's morphology our leading Floquet pair is complex and unstable;
    # with the hinge at the centre of mass (all else ours) the leading multiplier is real.
    _, _, stab = ours
    lead = np.asarray(stab.multipliers)[np.argmax(np.abs(stab.multipliers))]
    assert abs(lead) > 1 and abs(lead.imag) > 0.05
    base = _row(physics, "base", "FWUAV's body, ours otherwise")
    assert base["floquet_type"] == "real" and abs(base["leading_multiplier"]) > 1
    assert _row(physics, "accumulated", "+ angle of attack")["floquet_type"] == "oscillatory"


def test_the_hinge_adds_minus_h_x_u_over_c_to_m_u(physics):
    # The law of flapping.studies.cfd: the wings' drag X_u u acting h above the centre of mass
    # adds -h X_u+ / c to M_u+. Tolerance: the hinge offset (x_h Z_u+ / c, Z_u+ ~ 0 here) and
    # the retrimmed X_u+ (a few per cent of the shift) bound the deviation.
    tr = F.fwuav_translation("hawkmoth")
    ref = F.Reference.of(tr)
    base = _row(physics, "base", "FWUAV's body, ours otherwise")
    hinge = _row(physics, "alone", "hinge position")
    shift = -tr.insect.hinge_height / ref.chord * base["Xu"]
    assert hinge["Mu"] - base["Mu"] == pytest.approx(shift, abs=0.05 * abs(shift))


@pytest.mark.parametrize(("call", "message"), [
    (lambda: F.fwuav_translation("monarch"), "`name`"),
    (lambda: F.fwuav_translation("hawkmoth", wings="massless"), "`wings`"),
    (lambda: F.fwuav_insect("dragonfly"), "`name`"),
    (lambda: F.fwuav_averaged_jacobian(FwuavPitchFree("hawkmoth"), [0, 0, 0, 0], n_average=2),
     "n_average"),
    (lambda: F.fwuav_averaged_jacobian(FwuavPitchFree("hawkmoth", pitch="prescribed"),
                                       [0, 0, 0, 0]), "pitch='free'"),
    (lambda: F.fwuav_averaged_jacobian(FwuavPitchFree("hawkmoth"), [0, 0, 0]), "y0"),
    (lambda: F.fwuav_swap_table("hawkmoth"), "comparison"),
])
def test_bad_input_is_refused_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message.replace("(", r"\(")):
        call()


@pytest.mark.slow
def test_swap_reproduces_both_averaged_systems_and_averaging_converges():
    # Minutes: FWUAV's pitch-free orbit (pitch_free_floquet at rtol 1e-8, cached per process).
    comp = F.compare_fwuav("hawkmoth")
    swaps = F.fwuav_swap_table(comp)
    ours_none = swaps[(swaps.direction == "ours <- FWUAV") & (swaps.swapped == "none")].iloc[0]
    assert ours_none["rate"] == pytest.approx(comp.modes.loc["ours averaged", "rate"], rel=1e-9)
    assert ours_none["type"] == comp.modes.loc["ours averaged", "type"]
    whole = swaps[(swaps.direction == "ours <- FWUAV")
                  & (swaps.swapped == "all + theta column")].iloc[0]
    assert whole["rate"] == pytest.approx(comp.modes.loc["FWUAV averaged", "rate"], rel=1e-9)
    theirs_none = swaps[(swaps.direction == "FWUAV <- ours") & (swaps.swapped == "none")].iloc[0]
    assert theirs_none["period"] == pytest.approx(comp.modes.loc["FWUAV averaged", "period"],
                                                  rel=1e-9)
    # FWUAV's averaging converges: the rectangle rule on an integrand with kinks (the strip
    # loads' signs) converges algebraically; measured, 64 -> 128 instants changes the largest
    # entry by 2e-6 of itself (32 -> 64: 6e-5), so 1e-5 bounds the default's error
    fine, _ = F.fwuav_averaged_jacobian(FwuavPitchFree("hawkmoth"), comp.floquet.y0, 128)
    np.testing.assert_allclose(comp.fwuav_jacobian, fine, atol=1e-5 * np.max(np.abs(fine)))


# ------------------------------------------ the chapter's pitch-free study, stored (versioned)
STUDY = Path(__file__).resolve().parents[1] / "book" / "_data" / "fwuav_pitch_free.json"


def test_the_stored_study_holds_the_listed_cases_and_reads_back_exactly():
    results = F.load_pitch_free_study(STUDY)
    assert list(results) == list(F.PITCH_FREE_CASES)
    raw = json.loads(STUDY.read_text())["cases"]
    for key, result in results.items():
        assert F.pitch_free_to_json(result) == raw[key]["result"]  # every float exact
        trimmed = F.PITCH_FREE_CASES[key]["trim"]
        assert result.trim_parameters == (("phi_m", "phi_0") if trimmed else ())
        # what the chapter says of each: a complex leading pair outside the unit circle
        assert abs(result.multipliers[0]) > 1 and abs(result.multipliers[0].imag) > 0.05


def test_a_stored_study_with_other_cases_is_refused(tmp_path):
    data = json.loads(STUDY.read_text())
    data["cases"]["free fwuav"]["arguments"]["rtol"] = 1e-7
    stale = tmp_path / "stale.json"
    stale.write_text(json.dumps(data))
    with pytest.raises(ValueError, match="PITCH_FREE_CASES"):
        F.load_pitch_free_study(stale)


@pytest.mark.slow  # recomputes two pitch-free hovers: about a minute on two shared cores
@pytest.mark.parametrize("key", ["free fwuav", "trimmed fwuav"])
def test_recomputed_entries_of_the_stored_study_agree_with_it(key):
    saved = F.load_pitch_free_study(STUDY)[key]
    fresh = F.pitch_free_case(key)
    # the shooting closes to min(1000 rtol, 1e-6) = 1e-6 at rtol 1e-8: the orbit's start, the
    # trim and the multipliers agree to that order (1e-6 relative); on one machine, exactly
    np.testing.assert_allclose(fresh.y0, saved.y0, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fresh.trim_values, saved.trim_values, rtol=0, atol=1e-6)
    np.testing.assert_allclose(fresh.multipliers, saved.multipliers, rtol=1e-6)
    np.testing.assert_allclose(fresh.mean_velocity, saved.mean_velocity, rtol=0, atol=1e-6)
