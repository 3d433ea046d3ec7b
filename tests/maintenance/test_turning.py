"""A turning conserves what it should, leaves the residual asked for, and a life under a policy
resumes bit for bit; with no growth the life has its closed form (docs/maintenance.md)."""

from dataclasses import dataclass

import numpy as np
import pytest

from railwear.geometry import bands, roundness
from railwear.maintenance.plan import WheelRates, re_profiled
from railwear.maintenance.policy import load_policy
from railwear.maintenance.turning import (BELOW, WORN, CutRule, Policy, RateTable, Residual, Triggers, Turning,
                                          WheelState)
from railwear.scenario import load_scenario
from railwear.units import KM, MM, UM

N = 256
X = roundness.grid_angles(N)


COARSE = ["solver.points=128"]  # the metro on 128 points: its roughness (orders 1-40) whole, a build 4x cheaper


@pytest.fixture(scope="module")
def metro():
    """The metro wheel's Fourier technique at any diameter (orders 1..64 of 128 points)."""
    return WheelRates(load_scenario("metro", COARSE), 64)


def test_diameter_after_a_turning_is_before_minus_twice_the_cut_and_the_cut_cleans_the_polygon():
    u = 30 * UM * np.cos(8 * X + 0.3) + 12 * UM * np.cos(3 * X) - 0.8 * MM  # worn 0.8 mm, out of round
    state = WheelState(u, 0.84, distance=3e8, since=2e8, turnings=2)
    rule = CutRule(0.2 * MM, 0.1 * MM, 0.5 * MM)
    turned, record = Turning(rule, Residual("round")).apply(state, "test")
    assert record.after == record.before - 2 * record.cut  # exact
    assert record.before == state.mean_diameter and turned.diameter == record.after
    assert abs(turned.mean_diameter - record.after) < 1e-15
    # ū - min u = 42 µm (nearly; the crests are out of phase) + 0.2 mm margin: 0.3 mm, up to the least cut 0.5 mm
    assert record.cut == 0.5 * MM
    deeper = Turning(CutRule(0.6 * MM, 0.25 * MM, 0.1 * MM), Residual("round")).apply(state)[1]
    below = np.mean(u) - np.min(u) + 0.6 * MM
    assert deeper.cut == pytest.approx(np.ceil(below / (0.25 * MM)) * 0.25 * MM, abs=1e-18) and deeper.cut >= below
    # the new round radius lies at or below the deepest point of the old wheel, by the margin
    assert turned.diameter / 2 <= state.diameter / 2 + np.min(u) - rule.margin
    assert (turned.turnings, turned.distance, turned.since) == (3, 3e8, 0.0)
    assert record.dominant_order == 8 and record.peak_to_peak == pytest.approx(np.ptp(u))


def test_a_cut_on_a_whole_number_of_steps_is_not_rounded_up_a_step():
    rule = CutRule(0.3 * MM, 0.1 * MM, 0.05 * MM)
    assert rule.depth(np.zeros(N)) == pytest.approx(0.3 * MM, abs=1e-18)


def test_the_residual_spectrum_is_the_one_asked_for():
    old = 40 * UM * np.cos(8 * X + 1.0) + 15 * UM * np.cos(9 * X - 0.4) + 5 * UM * np.cos(21 * X)
    spectrum = Residual("spectrum", orders=(3, 12), amplitudes=(10 * UM, 2 * UM), phases=(0.5, -1.0))
    u = spectrum.shape(old, 0.83, 1)
    c = np.fft.rfft(u) * 2 / N
    assert np.max(np.abs(c[[3, 12]] - np.array([10 * UM * np.exp(0.5j), 2 * UM * np.exp(-1.0j)]))) < 1e-12 * 10 * UM
    assert np.max(np.abs(np.delete(c, [3, 12]))) < 1e-12 * 10 * UM

    inherit = Residual("inherit", orders=(8, 21), fractions=(0.25, 0.5)).shape(old, 0.83, 1)
    ratio = np.fft.rfft(inherit) - np.fft.rfft(old) * np.isin(np.arange(N // 2 + 1), [8, 21]) * np.where(
        np.arange(N // 2 + 1) == 8, 0.25, 0.5)
    assert np.max(np.abs(ratio)) < 1e-12 * np.max(np.abs(np.fft.rfft(old)))
    every = Residual("inherit", fractions=(0.1,)).shape(old, 0.83, 1)
    assert np.max(np.abs(every - 0.1 * old)) < 1e-12 * np.max(np.abs(old))

    band = Residual("band", wavelength=0.2, level=5.0, seed=3)
    u = band.shape(old, 0.83, 4)
    levels = bands.band_levels(u, 0.83)
    k = list(levels.index).index(int(bands.band_index(0.2)))
    assert abs(levels.mean_square[k] / (UM**2 * 10**0.5) - 1) < 1e-12  # 5 dB re 1 µm in the 200 mm band
    orders, _ = band.band_orders(0.83, N)
    assert set(np.flatnonzero(np.abs(np.fft.rfft(u)) > 1e-9 * np.max(np.abs(np.fft.rfft(u))))) == set(orders)
    assert np.array_equal(band.shape(old, 0.83, 4), u) and not np.array_equal(band.shape(old, 0.83, 5), u)


def test_the_turned_wheel_adds_the_re_profiled_roughness_when_asked():
    base = 3 * UM * np.cos(17 * X + 0.2) + 1 * UM  # its mean is dropped
    old = 40 * UM * np.cos(8 * X)
    state = WheelState(old, 0.84)
    residual = Residual("spectrum", orders=(3,), amplitudes=(10 * UM,), phases=(0.0,))
    turned, _ = Turning(CutRule(0.2 * MM, 0.1 * MM, 0.5 * MM), residual, base).apply(state)
    assert np.max(np.abs(turned.u - residual.shape(old, 0.84, 1) - (base - 1 * UM))) < 1e-18


@dataclass(frozen=True, eq=False)
class _Stub(RateTable):
    """A wheel whose polygon neither grows nor decays and whose radius wears at a constant rate."""


def _flat(wear, diameter, speed=20.0):
    return _Stub(np.zeros(N // 2, complex), -wear * speed, speed, diameter / 2)


@pytest.mark.parametrize("wear, interval_km, cut_mm, ends", [(1.2e-11, 200_000.0, 0.5, WORN),
                                                              (1.0e-11, 100_000.0, 3.0, BELOW),
                                                              (2.3e-12, 90_000.0, 0.7, None)])
def test_with_no_growth_and_an_interval_the_life_has_its_closed_form(wear, interval_km, cut_mm, ends):
    d0, ds, interval, cut = 0.84, 0.77, interval_km * KM, cut_mm * MM
    policy = Policy("interval", Triggers((), interval), Turning(CutRule(0.0, 0.1 * MM, cut), Residual("round")), ds)
    life = policy.life(WheelState(np.zeros(N), d0), lambda d: _flat(wear, d), horizon=1e10)
    per_cycle = 2 * (wear * interval + cut)  # diameter lost per interval and its turning
    n = int(np.floor((d0 - ds) / per_cycle))
    after = d0 - n * per_cycle
    distance = n * interval + min(interval, (after - ds) / (2 * wear))
    assert len(life.turnings) == n
    assert life.end.distance == pytest.approx(distance, rel=1e-12)
    assert life.reason == (WORN if (after - ds) / (2 * wear) < interval else BELOW)
    if ends is not None:
        assert life.reason == ends
    assert [t.distance for t in life.turnings] == pytest.approx(interval * np.arange(1, n + 1), rel=1e-12)
    assert [t.after for t in life.turnings] == pytest.approx(d0 - per_cycle * np.arange(1, n + 1), rel=1e-12)


def test_a_life_resumed_from_a_post_turning_state_equals_the_rest_of_the_life_bit_for_bit(metro):
    policy = load_policy("metro-condition").build(re_profiled(load_scenario("metro", COARSE)))
    start = WheelState(re_profiled(load_scenario("metro", COARSE)), 0.84)
    life = policy.life(start, metro.at, horizon=700_000 * KM)
    assert len(life.turnings) >= 3 and len(life.starts) == len(life.turnings)
    k = 1
    rest = policy.life(life.starts[k], metro.at, horizon=700_000 * KM)
    assert rest.turnings == life.turnings[k + 1:]  # every field, compared exactly
    assert np.array_equal(rest.end.u, life.end.u) and rest.end.distance == life.end.distance
    assert rest.reason == life.reason and rest.selected_order == life.turnings[k].selected_order
    cut = np.flatnonzero(life.history[0] == life.starts[k].distance)[-1]
    for mine, whole in zip(rest.history, life.history):
        assert np.array_equal(mine, whole[cut:])
    # and a peak-to-peak trigger acts where the wheel reaches it
    assert all(t.peak_to_peak == pytest.approx(0.1 * MM, rel=1e-9) for t in life.turnings)


def test_the_selected_order_follows_n_proportional_to_the_diameter(metro):
    """At the fixed P2 frequency the selected order is n = 2π R f / V: in proportion to D."""
    for d in (0.70, 0.77, 0.84, 0.92, 1.00):
        assert abs(metro.at(d).selected_order() - 8 * d / 0.84) <= 1, d
    assert metro.at(0.70).selected_order() < metro.at(1.00).selected_order()


def test_a_trigger_per_order_and_a_band_trigger_act_where_the_wheel_reaches_them(metro):
    from railwear import forecast

    base = re_profiled(load_scenario("metro", COARSE))
    for limit in (forecast.order_limit([24.0], [8]), forecast.band_limit(bands.iso3095_limit())):
        policy = Policy("p", Triggers((limit,), None), Turning(CutRule(0.2 * MM, 0.1 * MM, 0.5 * MM), Residual("round"),
                                                                  base), 0.77)
        segment = policy.advance(WheelState(base, 0.84), metro.at(0.84), 1e9, 500 * KM)
        assert segment.reason == limit.name
        assert abs(float(limit.excess(segment.state.u[None], 0.84)[0][0])) < 1e-6  # dB
