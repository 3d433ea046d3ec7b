"""The rail's bending modes between two wheels (railwear.track.between) against the beam's
closed forms, and the rail held by the wheels on the whole track."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.longterm.vehicle_track import HIGH_SPEED
from railwear.track import Support, Track, rail
from railwear.track.between import CLAMPED_ROOTS, held_receptance, localised_modes, span_modes

RAIL = rail("60E1")
EI, M = RAIL.youngs_modulus * RAIL.second_moment, RAIL.mass_per_metre
L = 2.5  # m: the high-speed bogie's wheelbase


def beam(beta_l):
    """``(β_n L)² / (2π L²) sqrt(EI/m)`` [Hz]."""
    return np.asarray(beta_l) ** 2 / (2 * np.pi * L**2) * np.sqrt(EI / M)


def test_a_span_without_support_is_the_pinned_or_clamped_euler_beam():
    """On rail seats of 1 N/m (nothing), the span's modes are the beam's: pinned ``β_n L = nπ``
    (81.8, 327.3, 736.3 Hz) and clamped ``cos βL cosh βL = 1`` (185.5, 511.2, 1002.2 Hz), to 1e-6
    (measured 5e-8: the seats' 1 N/m)."""
    free = Track(RAIL, Support(pad_stiffness=1.0), sleeper_spacing=0.6, beam="euler")
    np.testing.assert_allclose(span_modes(free, L, "pinned"), beam(np.pi * np.arange(1, 4)), rtol=1e-6)
    np.testing.assert_allclose(span_modes(free, L, "clamped"), beam(CLAMPED_ROOTS), rtol=1e-6)


def test_a_pinned_span_on_a_continuous_support_is_the_winkler_beam():
    """``f_n = sqrt(EI (nπ/L)⁴ + s) / m) / 2π`` (166.5, 358.0, 750.5 Hz at s = 50 MN/m²), to 1e-8."""
    s = 50e6
    track = Track(RAIL, Support(pad_stiffness=s), None, beam="euler")
    k = np.pi * np.arange(1, 4) / L
    np.testing.assert_allclose(span_modes(track, L, "pinned"), np.sqrt((EI * k**4 + s) / M) / (2 * np.pi), rtol=1e-8)


def test_the_rail_does_not_move_under_a_wheel_that_holds_it():
    """A rigid wheel holds the rail: the held receptance at its contact is zero (to 1e-12 of the
    free rail's), and far from both wheels it is the free rail's (to 1e-3 at 30 m)."""
    track = HIGH_SPEED.track
    f = np.array([100.0, 600.0, 1200.0])
    held = held_receptance(track, (0.0, L), f, np.array([0.0, L, 30.0]))
    free = np.abs(held_receptance(track, (0.0, L), f, np.array([0.0]), wheel_receptance=1e6))
    assert np.all(np.abs(held[:, :2]) < 1e-12 * free)
    from railwear.track import receptance, load_offset

    np.testing.assert_allclose(held[:, 2], receptance(track, f, load_offset(track, "midspan") + 30.0), rtol=1e-3)


def test_the_held_third_mode_lies_between_the_pinned_and_clamped_span():
    """High-speed slab, wheels 2.5 m apart (rigid): the rail beyond the wheels restrains the span's
    rotation in part, so the third mode's peak (measured 681.9 Hz) lies between the pinned
    (637.1 Hz) and clamped (756.4 Hz) span of the rail on its pads; the first two radiate past
    the wheels with no peak of their own (NaN)."""
    modes = localised_modes(HIGH_SPEED.track, L)
    assert modes["pinned"][2] < modes["held"][2] < modes["clamped"][2]
    assert np.all(modes["pinned"] < modes["clamped"]) and np.all(np.isnan(modes["held"][:2]))
    assert modes["held"][2] == pytest.approx(681.9, abs=0.5)


def test_lengths_and_ends_are_checked():
    with pytest.raises(ScenarioError, match="length"):
        span_modes(HIGH_SPEED.track, 0.0)
    with pytest.raises(ScenarioError, match="ends"):
        span_modes(HIGH_SPEED.track, L, "free")
