"""Track receptance against closed forms, the pinned-pinned frequency, a finite track and the
smeared support."""

import math

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.track import Rail, Support, Track, rail, rail_names, receptance
from railwear.track.finite import finite_track_receptance, span_dynamic_stiffness

F = np.array([0.0, 5.0, 60.0, 250.0, 800.0, 1500.0, 3000.0])
SEAT = Support(pad_stiffness=1.2e8, pad_loss_factor=0.25, sleeper_mass=150.0, ballast_stiffness=5e7,
               ballast_loss_factor=1.0)


def winkler_closed_form(r, s, omega, x):
    """Euler-Bernoulli beam on a foundation ``s`` [N/m²] (complex): the textbook Green's function
    ``w = e^{-β|x|}(cos β|x| + sin β|x|) / (8 EI β³)`` per newton, continued to complex
    ``β⁴ = (s - m ω²) / (4 EI)`` on the root with ``|arg β| < π/4`` (both waves decay)."""
    EI = r.bending_stiffness
    b4 = (s - r.mass_per_metre * omega**2) / (4 * EI) + 0j
    roots = b4[..., None] ** 0.25 * np.array([1, 1j, -1, -1j])
    beta = np.take_along_axis(roots, np.argmin(np.abs(np.angle(roots)), axis=-1)[..., None], -1)[..., 0]
    z = beta * abs(x)
    return np.exp(-z) * (np.cos(z) + np.sin(z)) / (8 * EI * beta**3)


def timoshenko_closed_form(r, s, omega, x):
    """Timoshenko beam on a foundation ``s``: residues of ``W(κ) = -(EIκ² + S - Jω²) / D(κ)`` with
    ``D = (mω² - s - Sκ²)(EIκ² + S - Jω²) + S²κ²`` (a quadratic in κ²), taken in the lower half plane."""
    EI, S, J, m = r.bending_stiffness, r.shear_stiffness, r.rotary_inertia, r.mass_per_metre
    out = []
    for om, sf in zip(np.atleast_1d(omega), np.broadcast_to(s, np.shape(np.atleast_1d(omega)))):
        c = S - J * om**2
        a2 = -S * EI  # coefficients of D in p = κ²
        a1 = (m * om**2 - sf) * EI - S * c + S**2
        a0 = (m * om**2 - sf) * c
        total = 0.0
        for p in np.roots([a2, a1, a0]):
            k = np.sqrt(p + 0j)
            k = k if k.imag < 0 else -k
            dD = 2 * k * (2 * a2 * p + a1)  # dD/dκ
            total += -(EI * p + c) / dD * np.exp(-1j * k * abs(x)) * (-1j)  # (1/2π)(-2πi) Res
        out.append(total)
    return np.array(out)


@pytest.mark.parametrize("support", [
    Support(pad_stiffness=1.5e8, pad_loss_factor=0.3),
    Support(pad_stiffness=2.0e8, pad_damping=4.0e4, sleeper_mass=250.0, ballast_stiffness=8e7,
            ballast_damping=5e4, ballast_loss_factor=0.5),
], ids=["winkler", "two-layer"])
@pytest.mark.parametrize("x", [0.0, 0.45, -1.7])
def test_continuous_euler_matches_closed_form(support, x):
    track = Track(rail("60E1"), support, beam="euler")
    omega = 2 * np.pi * F
    exact = winkler_closed_form(track.rail, support.stiffness(omega) * np.ones_like(omega), omega, x)
    got = receptance(track, F, 0.0, response=x)
    assert np.max(np.abs(got / exact - 1)) < 1e-6  # about 1e-14 measured


@pytest.mark.parametrize("x", [0.0, 0.8])
def test_continuous_timoshenko_matches_residues(x):
    support = Support(pad_stiffness=2.0e8, pad_loss_factor=0.2, sleeper_mass=250.0, ballast_stiffness=8e7,
                      ballast_loss_factor=1.0)
    track = Track(rail("60E1", loss_factor=0.01), support, beam="timoshenko")
    omega = 2 * np.pi * F
    exact = timoshenko_closed_form(track.rail, support.stiffness(omega) * np.ones_like(omega), omega, x)
    got = receptance(track, F, 0.0, response=x)
    assert np.max(np.abs(got / exact - 1)) < 1e-6


def test_static_winkler_deflection():
    """At 0 Hz the Euler beam on a spring bed deflects ``β / (2 s)`` per newton, ``β = (s/4EI)^(1/4)``."""
    r, s = rail("60E1"), 1.5e8
    beta = (s / (4 * r.youngs_modulus * r.second_moment)) ** 0.25
    got = receptance(Track(r, Support(pad_stiffness=s), beam="euler"), 0.0)
    assert abs(got / (beta / (2 * s)) - 1) < 1e-12


@pytest.mark.parametrize("beam", ["euler", "timoshenko"])
def test_midspan_peak_at_pinned_pinned(beam):
    """The pinned-pinned mode has nodes at the sleepers, so the support does not damp it: with an
    undamped rail the midspan receptance peaks at it (asserted 1e-4; measured below the grid step)."""
    track = Track(rail("60E1"), SEAT, sleeper_spacing=0.6, beam=beam)
    fpp = track.pinned_pinned_frequency()
    f = np.linspace(0.8 * fpp, 1.2 * fpp, 4001)
    coarse = f[np.argmax(np.abs(receptance(track, f, "midspan")))]
    fine = np.linspace(coarse - 1e-4 * fpp, coarse + 1e-4 * fpp, 401)
    peak = fine[np.argmax(np.abs(receptance(track, fine, "midspan")))]
    assert abs(peak / fpp - 1) < 1e-4
    # above a sleeper the mode is not excited: an anti-resonance just above it (1-2 % measured)
    dip = f[np.argmin(np.abs(receptance(track, f, "sleeper")))]
    assert 0.0 < dip / fpp - 1 < 0.03


def test_pinned_pinned_formulas():
    """Euler ``(π / 2L²) sqrt(EI/m)``; Timoshenko lower and tends to it for long spans."""
    r = rail("60E1")
    euler = Track(r, SEAT, sleeper_spacing=0.6, beam="euler").pinned_pinned_frequency()
    assert euler == pytest.approx(math.pi / (2 * 0.36) * math.sqrt(r.youngs_modulus * r.second_moment / r.mass_per_metre))
    timo = Track(r, SEAT, sleeper_spacing=0.6).pinned_pinned_frequency()
    assert 0.70 < timo / euler < 0.80  # 1067 / 1420 Hz
    long_timo = Track(r, SEAT, sleeper_spacing=6.0).pinned_pinned_frequency()
    long_euler = Track(r, SEAT, sleeper_spacing=6.0, beam="euler").pinned_pinned_frequency()
    assert abs(long_timo / long_euler - 1) < 0.01


@pytest.mark.parametrize("beam", ["euler", "timoshenko"])
def test_finite_track_converges_to_periodic(beam):
    """The exact finite track (no mesh) approaches the Floquet solution as it grows: to round-off
    below the sleeper resonances, and by |λ|^(n/2) in the pass band (|λ| ≈ 0.975 per bay here)."""
    track = Track(rail("60E1", loss_factor=0.02), SEAT, sleeper_spacing=0.6, beam=beam)
    f = np.array([20.0, 150.0, 700.0, 1500.0])
    ref = receptance(track, f, "midspan", response=[0.3, 1.5])
    errors = [np.max(np.abs(finite_track_receptance(track, f, "midspan", response=[0.3, 1.5], n_sleepers=n)
                            / ref - 1), axis=1) for n in (41, 121, 241)]
    assert np.all(errors[0][:2] < 1e-5) and np.all(errors[2][:2] < 1e-11)
    assert np.all(errors[1][2:] < errors[0][2:] / 5) and np.all(errors[2][2:] < errors[1][2:] / 5)
    assert np.all(errors[2] < 5e-3)


def test_span_stiffness_symmetric():
    """Reciprocity: the exact span stiffness is symmetric (1e-12 asserted)."""
    for beam in ("euler", "timoshenko"):
        K = span_dynamic_stiffness(Track(rail("54E1"), SEAT, 0.6, beam), 2 * np.pi * F, 0.37)
        assert np.max(np.abs(K - np.swapaxes(K, 1, 2))) < 1e-12 * np.max(np.abs(K))


def test_low_frequency_discrete_tends_to_smeared():
    """At 1 Hz the discrete track differs from the smeared one by about 2 % at 0.6 m spacing,
    and the difference falls as L² when the spacing shrinks at fixed support per metre."""
    per_metre = SEAT.scaled(1 / 0.6)
    diffs = []
    for L in (0.6, 0.3, 0.15):
        track = Track(rail("60E1"), per_metre.scaled(L), sleeper_spacing=L)
        ref = receptance(track.smeared(), 1.0)
        diffs.append(max(abs(receptance(track, 1.0, p) / ref - 1) for p in ("midspan", "sleeper")))
    assert 0.005 < diffs[0] < 0.04
    orders = np.log2(np.array(diffs[:-1]) / np.array(diffs[1:]))
    assert np.all((orders > 1.8) & (orders < 2.5))


def test_transfer_symmetry_and_point():
    """Reciprocity and the mirror symmetry of a bay: the load at 0.3 m seen at 0.9 m equals the
    load at 0.9 m seen at 0.3 m, and equals the response at -0.3 m (mirror about the midspan)."""
    track = Track(rail("60E1"), SEAT, sleeper_spacing=0.6)
    f = np.array([50.0, 900.0, 2500.0])
    a = receptance(track, f, 0.3, response=[0.9, -0.3, 0.3])
    b = receptance(track, f, 0.9, response=0.3)
    np.testing.assert_allclose(a[:, 0], b, rtol=1e-9)
    np.testing.assert_allclose(a[:, 0], a[:, 1], rtol=1e-9)
    np.testing.assert_allclose(a[:, 2], receptance(track, f, "midspan"), rtol=1e-12)


def test_shapes():
    track = Track(rail("60E1"), SEAT, sleeper_spacing=0.6)
    assert np.ndim(receptance(track, 100.0)) == 0
    assert receptance(track, F).shape == F.shape
    assert receptance(track, F, "sleeper", response=[0.1, 0.2]).shape == (F.size, 2)


def test_rail_data_and_overrides():
    assert set(rail_names()) >= {"60E1", "54E1"}
    r = rail("UIC60", second_moment=3.0e-5)
    assert r.name == "60E1" and r.second_moment == 3.0e-5 and r.mass_per_metre == pytest.approx(60.21)
    assert "EN 13674-1" in r.source
    assert rail("54E1").mass_per_metre < r.mass_per_metre


@pytest.mark.parametrize("make, field", [
    (lambda: rail("61E9"), "rail"),
    (lambda: rail("60E1", colour=1), "colour"),
    (lambda: Rail(mass_per_metre=-1, area=1e-2, second_moment=3e-5), "mass_per_metre"),
    (lambda: Support(pad_stiffness=0.0), "pad_stiffness"),
    (lambda: Support(pad_stiffness=1e8, pad_loss_factor=-0.1), "pad_loss_factor"),
    (lambda: Track(rail(), SEAT, sleeper_spacing=-0.6), "sleeper_spacing"),
    (lambda: Track(rail(), SEAT, beam="rayleigh"), "beam"),
    (lambda: receptance(Track(rail(), SEAT, 0.6), [-1.0]), "frequency_hz"),
    (lambda: receptance(Track(rail(), SEAT, 0.6), 1.0, "quarter"), "position"),
])
def test_bad_input_names_the_field(make, field):
    with pytest.raises(ScenarioError, match=f"^{field}:"):
        make()
