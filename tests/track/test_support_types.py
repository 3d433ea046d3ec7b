"""The track types: a ballast mass on a subgrade (two-layer ballasted support) and slab track.

Closed forms in the continuous limit (the support's dynamic stiffness condensed from its chain's
stiffness matrix, the Euler beam's Green's function and the Timoshenko beam's residues on it), the
limit of the two-layer support to the single-layer one, the exact finite track against the
periodic one, the shipped sets, and the time-domain track's refusal."""

import dataclasses
import math

import numpy as np
import pytest
from test_receptance import timoshenko_closed_form, winkler_closed_form

from railwear.errors import ScenarioError
from railwear.track import (BASES, ModalTrack, Support, Track, base_fields, default_support_set, rail, receptance,
                            support_of, support_set, support_set_names)
from railwear.track.finite import finite_track_receptance

F = np.array([0.0, 5.0, 40.0, 85.0, 250.0, 800.0, 1500.0, 3000.0])
NEW = ["zhai-2004", "crts-slab-2019", "crts-slab-2021"]
# the two-layer set with loss factors on every spring as well (hysteretic and viscous together)
LOSSY = dataclasses.replace(support_set("zhai-2004").support, pad_loss_factor=0.2, ballast_loss_factor=0.5,
                            subgrade_loss_factor=0.3)


def chain_stiffness(s: Support, omega):
    """The force per rail displacement of the chain rail - pad - M_s - ballast - M_b - subgrade -
    ground, condensed from its dynamic stiffness matrix (the masses' rows eliminated): an
    independent evaluation of :meth:`Support.stiffness`."""
    out = []
    for w in np.atleast_1d(omega):
        p, b = (s.pad_stiffness * (1 + 1j * s.pad_loss_factor) + 1j * w * s.pad_damping,
                s.ballast_stiffness * (1 + 1j * s.ballast_loss_factor) + 1j * w * s.ballast_damping)
        g = (s.subgrade_stiffness * (1 + 1j * s.subgrade_loss_factor) + 1j * w * s.subgrade_damping
             if math.isfinite(s.subgrade_stiffness) else None)
        if g is None:  # rail, sleeper
            K = np.array([[p, -p], [-p, p + b - s.sleeper_mass * w**2]])
        else:  # rail, sleeper, ballast mass
            K = np.array([[p, -p, 0], [-p, p + b - s.sleeper_mass * w**2, -b],
                          [0, -b, b + g - s.ballast_mass * w**2]])
        out.append(K[0, 0] - K[0, 1:] @ np.linalg.solve(K[1:, 1:], K[1:, 0]))
    return np.array(out)


@pytest.mark.parametrize("support", [support_set(n).support for n in NEW] + [LOSSY], ids=NEW + ["lossy"])
def test_support_stiffness_is_the_condensed_chain(support):
    omega = 2 * np.pi * F
    for s in (support, support.scaled(1 / 0.6)):  # per rail seat and per metre
        assert np.max(np.abs(s.stiffness(omega) / chain_stiffness(s, omega) - 1)) < 1e-12


@pytest.mark.parametrize("name", NEW + ["lossy"])
@pytest.mark.parametrize("x", [0.0, 0.45, -1.7])
def test_continuous_euler_on_the_new_supports_matches_closed_form(name, x):
    """The smeared track, Euler beam: the exact receptance against the Green's function on the
    chain's stiffness per metre (1e-6 asserted)."""
    support = LOSSY if name == "lossy" else support_set(name).support
    track = Track(rail("60E1"), support, 0.6, beam="euler").smeared()
    omega = 2 * np.pi * F
    exact = winkler_closed_form(track.rail, chain_stiffness(track.support, omega), omega, x)
    got = receptance(track, F, 0.0, response=x)
    assert np.max(np.abs(got / exact - 1)) < 1e-6


@pytest.mark.parametrize("name", NEW + ["lossy"])
@pytest.mark.parametrize("x", [0.0, 0.8])
def test_continuous_timoshenko_on_the_new_supports_matches_residues(name, x):
    support = LOSSY if name == "lossy" else support_set(name).support
    track = Track(rail("60E1", loss_factor=0.01), support, 0.6).smeared()
    omega = 2 * np.pi * F
    exact = timoshenko_closed_form(track.rail, chain_stiffness(track.support, omega), omega, x)
    got = receptance(track, F, 0.0, response=x)
    assert np.max(np.abs(got / exact - 1)) < 1e-6


def test_two_layer_tends_to_the_single_layer():
    """Ballast mass ε M_b and subgrade k_f / ε: the receptance differs from the single-layer one's
    by O(ε), discrete and smeared, and by round-off at ε = 1e-20 (1e-13 asserted)."""
    two = support_set("zhai-2004").support
    single = support_set("zhai-2004-no-subgrade").support
    assert dataclasses.replace(two, ballast_mass=0.0, subgrade_stiffness=math.inf, subgrade_damping=0.0) == single
    f = np.array([0.0, 10.0, 45.0, 130.0, 700.0, 1500.0])
    ref = {p: receptance(Track(rail("60E1", loss_factor=0.02), single, 0.6), f, p) for p in ("midspan", "sleeper")}
    ref["smeared"] = receptance(Track(rail("60E1", loss_factor=0.02), single, 0.6).smeared(), f)
    errors = []
    for eps in (1e-2, 1e-4, 1e-6, 1e-20):
        s = dataclasses.replace(two, ballast_mass=two.ballast_mass * eps, subgrade_stiffness=two.subgrade_stiffness / eps,
                                subgrade_damping=two.subgrade_damping / eps)
        track = Track(rail("60E1", loss_factor=0.02), s, 0.6)
        got = {p: receptance(track, f, p) for p in ("midspan", "sleeper")} | {"smeared": receptance(track.smeared(), f)}
        errors.append(max(np.max(np.abs(got[k] / ref[k] - 1)) for k in ref))
    assert errors[-1] < 1e-13
    slopes = np.log10(np.array(errors[:2]) / np.array(errors[1:3])) / 2
    assert np.all(np.abs(slopes - 1) < 0.05)  # first order in ε


@pytest.mark.parametrize("name", ["zhai-2004", "crts-slab-2019"])
def test_finite_track_on_the_new_supports_converges_to_periodic(name):
    """The exact finite track of 41 and 241 sleepers against the Floquet solution, at the coupled
    resonances and below the pinned-pinned frequency."""
    track = Track(rail("60E1", loss_factor=0.02), support_set(name).support, 0.6)
    f = np.array([20.0, 40.0, 85.0, 150.0])
    ref = receptance(track, f, "midspan", response=[0.3, 1.5])
    errors = [np.max(np.abs(finite_track_receptance(track, f, "midspan", response=[0.3, 1.5], n_sleepers=n) / ref - 1))
              for n in (41, 241)]
    assert errors[0] < 1e-4 and errors[1] < 1e-10


def test_low_frequency_discrete_tends_to_smeared_on_the_two_layer_support():
    """At 1 Hz, fixed support per metre: the discrete track tends to the smeared one as L²."""
    per_metre = support_set("zhai-2004").support.scaled(1 / 0.6)
    diffs = []
    for L in (0.6, 0.3, 0.15):
        track = Track(rail("60E1"), per_metre.scaled(L), sleeper_spacing=L)
        ref = receptance(track.smeared(), 1.0)
        diffs.append(max(abs(receptance(track, 1.0, p) / ref - 1) for p in ("midspan", "sleeper")))
    orders = np.log2(np.array(diffs[:-1]) / np.array(diffs[1:]))
    assert np.all((orders > 1.8) & (orders < 2.5))


def test_shipped_sets_and_their_sources():
    assert set(support_set_names()) >= set(NEW) | {"zhai-2004-no-subgrade"}
    zhai = support_set("zhai-2004")
    assert (zhai.base, zhai.sleeper_spacing) == ("ballast_subgrade", 0.6) and "JSV 270 (2004) 673" in zhai.source
    assert (zhai.support.ballast_mass, zhai.support.subgrade_stiffness, zhai.support.subgrade_damping) == (
        531.4, 77.5e6, 31.15e3)
    slab = support_set("crts-slab-2019")
    assert "2015465" in slab.source and slab.support.sleeper_mass == pytest.approx(2400 * 0.19 * 2.40 / 2 * 0.6)
    assert (slab.support.pad_stiffness, slab.support.ballast_stiffness) == (29e6, 60e6)
    assert support_set("crts-slab-2021").support.ballast_stiffness == 240e6
    assert default_support_set("ballast_subgrade") == zhai and default_support_set("slab") == slab
    assert default_support_set("ballast") is None and default_support_set("rigid") is None
    for name in support_set_names():  # every set gives only its base's values, and says where they come from
        s = support_set(name)
        assert set(s.values) <= set(base_fields(s.base)) and s.source


def test_slab_is_the_one_mass_chain():
    """A slab's mass and CA mortar take the sleeper's and the ballast's place in the chain."""
    slab = support_of("slab", pad_stiffness=40e6, slab_mass=300.0, mortar_stiffness=240e6, mortar_damping=5e4)
    assert slab == Support(pad_stiffness=40e6, sleeper_mass=300.0, ballast_stiffness=240e6, ballast_damping=5e4)


@pytest.mark.parametrize("make, field", [
    (lambda: Support(pad_stiffness=1e8, subgrade_stiffness=5e7), "subgrade_stiffness"),
    (lambda: Support(pad_stiffness=1e8, ballast_stiffness=1e8, ballast_mass=500.0), "ballast_mass"),
    (lambda: Support(pad_stiffness=1e8, ballast_stiffness=1e8, subgrade_stiffness=-1.0), "subgrade_stiffness"),
    (lambda: Support(pad_stiffness=1e8, ballast_stiffness=1e8, subgrade_stiffness=5e7, subgrade_damping=-1.0),
     "subgrade_damping"),
    (lambda: support_of("slab", pad_stiffness=4e7, sleeper_mass=100.0), "sleeper_mass"),
    (lambda: support_of("rigid", pad_stiffness=4e7, ballast_stiffness=1e8), "ballast_stiffness"),
    (lambda: support_of("gravel", pad_stiffness=4e7), "base"),
    (lambda: support_set("no-such-track"), "preset"),
    (lambda: ModalTrack(Track(rail(), support_set("zhai-2004").support, 0.6), n_sleepers=11), "subgrade_stiffness"),
])
def test_bad_input_names_the_field(make, field):
    with pytest.raises(ScenarioError, match=f"^{field}:"):
        make()


def test_time_domain_track_takes_a_slab():
    """The slab is the one-mass chain, so the time-domain track runs on it (the two-layer support
    is refused above)."""
    model = ModalTrack(Track(rail(), support_set("crts-slab-2019").support, 0.6), n_sleepers=11, max_frequency_hz=2000)
    assert model.support_parameters[:5] == pytest.approx((29e6, 50e3, 60e6, 90e3, 328.32))


def test_bases():
    assert BASES == ("ballast", "ballast_subgrade", "slab", "rigid")
    assert set(base_fields("ballast")) < set(base_fields("ballast_subgrade"))
