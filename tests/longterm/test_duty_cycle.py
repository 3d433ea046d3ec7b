"""Duty cycles: segments of distance at their speed and signed demand (railwear.longterm.duty),
the Fourier technique averaged over them (FourierCycle), a line's derived cycle, and the
[operation] fields that describe them."""

import tomllib

import numpy as np
import pytest

import railwear
from railwear.errors import ScenarioError
from railwear.longterm.duty import GRAVITY, DutyCycle, DutySegment, line_cycle
from railwear.longterm.fourier import FourierCycle
from railwear.scenario import build, builtin_text, load_scenario, parse_scenario
from railwear.units import kmh_to_m_s

ORDERS = np.arange(1, 41)


def metro_with(operation, **contact):
    data = tomllib.loads(builtin_text("metro"))
    data["operation"] = {"life_distance_km": 100000.0, **operation}
    data["contact"] = {k: v for k, v in data["contact"].items() if k != "traction_coefficient"} | contact
    return parse_scenario(data)


CYCLE = [{"share": 0.2, "speed_kmh": 40.0, "traction_coefficient": 0.1},
         {"share": 0.5, "speed_kmh": 70.0, "traction_coefficient": 0.003},
         {"share": 0.3, "speed_kmh": 50.0, "traction_coefficient": -0.09}]


def test_a_cycle_of_one_segment_is_the_single_traction_run_bit_for_bit():
    single = railwear.run("metro")
    cycle = railwear.run(metro_with({"cycle": [{"share": 1.0, "speed_kmh": 70.0, "traction_coefficient": 0.05}]}))
    for name in single.data_vars:
        a, b = single[name].values, cycle[name].values
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name
    assert cycle.attrs["mean_traction_coefficient"] == 0.05 and cycle.attrs["braking_share"] == 0.0


def test_the_cycle_rates_are_the_distance_weighted_mean_of_the_segments():
    """Per metre, ``Σ p_k λ_k / V_k`` to 1e-12; the mean radius likewise; seconds at ``1/Σ p_k/V_k``."""
    sc = metro_with({"cycle": CYCLE})
    cycle = build.fourier_technique(sc)
    assert isinstance(cycle, FourierCycle)
    parts = [build.fourier_technique(metro_with({"speed_kmh": s["speed_kmh"]}, traction_coefficient=s["traction_coefficient"]))
             for s in CYCLE]
    shares = [s["share"] for s in CYCLE]
    per_metre = sum(p * f.rates(ORDERS) / f.speed for p, f in zip(shares, parts))
    np.testing.assert_allclose(cycle.rates(ORDERS) / cycle.speed, per_metre, rtol=1e-12)
    assert cycle.mean_rate / cycle.speed == pytest.approx(sum(p * f.mean_rate / f.speed for p, f in zip(shares, parts)),
                                                          rel=1e-12)
    assert cycle.speed == pytest.approx(1 / sum(p / kmh_to_m_s(s["speed_kmh"]) for p, s in zip(shares, CYCLE)), rel=1e-15)


def test_the_averaged_evolution_is_exact_for_segments_run_one_after_another():
    """Run each segment for its share of 5000 km in turn, twice over in another order: the same
    wheel as the averaged technique over 10 000 km (the operators commute), to 1e-10."""
    sc = metro_with({"cycle": CYCLE})
    cycle = build.fourier_technique(sc)
    u0 = build.initial_state(sc)
    distance = 1e7  # m
    u = u0
    for k in (0, 1, 2, 2, 0, 1):
        part = cycle.parts[k]
        u = part.evolve(u, cycle.shares[k] * distance / 2 / part.speed)[0]
    averaged = cycle.evolve(u0, distance / cycle.speed)[0]
    np.testing.assert_allclose(u, averaged, rtol=0, atol=1e-10 * np.ptp(u0))


def test_a_line_gives_its_trapezoid_by_distance():
    """Stations 1.2 km apart, 80 km/h, 1.0 and 0.8 m/s²: acceleration over V²/2a, braking over
    V²/2b, the rest cruising; shares sum to 1; a motor wheel's demands (1 + ρ) a / g + r,
    r, -(1 + ρ) b / g + r; a trailer's -r and -(1 + ρ) b / g."""
    v = kmh_to_m_s(80.0)
    duty = line_cycle(1200.0, v, 1.0, 0.8, "motor", bins=4)
    s = duty.shares
    assert s.sum() == pytest.approx(1.0, abs=1e-12)
    assert s[:4].sum() * 1200 == pytest.approx(v**2 / 2, rel=1e-12)
    assert s[-4:].sum() * 1200 == pytest.approx(v**2 / 1.6, rel=1e-12)
    f = duty.demands
    assert f[0] == pytest.approx(1.08 / GRAVITY + 0.002) and f[4] == 0.002 and f[-1] == pytest.approx(-0.8 * 1.08 / GRAVITY + 0.002)
    assert duty.braking_share == pytest.approx(s[-4:].sum())
    trailer = line_cycle(1200.0, v, 1.0, 0.8, "trailer")
    assert trailer.braking_share == 1.0 and trailer.demands[-1] == pytest.approx(-0.8 * 1.08 / GRAVITY)
    short = line_cycle(300.0, v, 1.0, 1.0)  # too short to reach 80 km/h: a triangle, no cruise
    assert len(short.segments) == 8 and max(short.speeds) < v


@pytest.mark.parametrize("bins", [1, 4, 32])
def test_the_line_runs_in_the_trapezoid_time(bins):
    """The run time ``spacing / mean_speed`` is the trapezoid's ``V/a + V/b + cruise / V`` (the
    integral of dx / v(x)) to 1e-12 for any number of bins, each run at its distance over its
    time; a triangle's ``V_p/a + V_p/b`` likewise."""
    v, a, b, spacing = kmh_to_m_s(80.0), 1.0, 0.8, 1200.0
    exact = v / a + v / b + (spacing - v**2 / (2 * a) - v**2 / (2 * b)) / v
    assert spacing / line_cycle(spacing, v, a, b, bins=bins).mean_speed == pytest.approx(exact, rel=1e-12)
    peak = np.sqrt(2 * 300.0 * a * b / (a + b))
    assert 300.0 / line_cycle(300.0, v, a, b, bins=bins).mean_speed == pytest.approx(peak / a + peak / b, rel=1e-12)


@pytest.mark.parametrize("change, field", [
    ({"cycle": CYCLE, "speed_kmh": 70.0}, "operation.speed_kmh: the duty cycle gives the speeds"),
    ({"cycle": [dict(CYCLE[0], share=0.5)]}, "operation.cycle: the shares of the distance must sum to 1"),
    ({"cycle": CYCLE, "line": {"station_spacing_km": 1.0, "top_speed_kmh": 80.0}}, "operation.line: give a cycle or a line"),
    ({"cycle": [dict(CYCLE[0], traction_coefficient=1.0)]}, "operation.cycle[0].traction_coefficient"),
    ({"line": {"station_spacing_km": 1.0, "top_speed_kmh": 80.0, "braking_m_s2": 0.0}}, "operation.line.braking_m_s2"),
])
def test_a_bad_cycle_is_refused_naming_the_field(change, field):
    with pytest.raises(ScenarioError, match=field.replace(".", r"\.").replace("[", r"\[")):
        metro_with(change)


def test_a_cycle_runs_with_the_strategies_that_run_one_and_carries_the_demand():
    with pytest.raises(ScenarioError, match=r"operation\.cycle: the phenomenological strategy runs one operating point"):
        load_scenario(metro_with({"cycle": CYCLE}), ["strategy.kind=phenomenological"])
    assert load_scenario(metro_with({"cycle": CYCLE}), ["strategy.kind=stepwise"]).operation.duty() is not None
    with pytest.raises(ScenarioError, match=r"contact\.traction_coefficient: operation\.cycle gives the demand"):
        metro_with({"cycle": CYCLE}, traction_coefficient=0.05)
    braking = load_scenario("metro", ["contact.traction_coefficient=-0.05"])
    assert braking.contact.traction_coefficient == -0.05


@pytest.mark.slow
def test_under_braking_the_fourier_rates_are_the_direct_runs():
    """The disk wheel of the 'direct' scenario braking at -0.05 x its load (64 cells, A = 2000, to
    0.1 mm): orders 9-16 grow in the time-domain run as the Fourier technique says (with the
    grid's filter sinc³(n/64)), each within 15 % (measured -10 % to +7 %), their mean within 3 %
    (measured -0.7 %); under traction the same orders decay (docs/vehicle_track.md), so the sign
    of the demand is carried through both models alike. Mean wear within 2 % (measured 1.2 %)."""
    from railwear.longterm.fourier import Fourier
    from railwear.units import KM

    sc = load_scenario("direct", ["contact.traction_coefficient=-0.05", "solver.points=64", "solver.depth_limit_mm=0.1",
                                  "strategy.acceleration_factor=2000", "solver.t_end=20"])
    ds = railwear.run(sc)
    n = np.arange(9, 17)
    direct = np.log(ds.amplitude.sel(order=n).values / ds.amplitude_initial.sel(order=n).values) / float(ds.distance[-1])
    model, band = build.linear_model(sc, build.one_speed(sc))
    f = Fourier.disk_wheel(model, build.wear_law(sc), band)
    fourier = f.rates(n).real / f.speed * KM * np.sinc(n / 64) ** 3
    assert np.all(fourier > 0) and np.all(direct > 0)
    np.testing.assert_allclose(direct, fourier, rtol=0.15)
    assert np.mean(direct / fourier) == pytest.approx(1.0, abs=0.03)
    per_km = float(ds.mean_removed_depth[-1]) / float(ds.distance[-1])
    assert per_km == pytest.approx(-f.mean_rate / f.speed * KM, rel=0.02)


def test_the_stability_map_of_a_cycle_is_the_share_weighted_mean_and_says_so():
    """At every speed, the map over the cycle's demands is ``Σ p_k g(V, f_k)`` to 1e-12, and its
    label states the mean creep force and the braking share."""
    sc = metro_with({"cycle": CYCLE})
    speeds, orders = [50, 70], range(1, 21)
    cycle = railwear.stability(sc, speeds_kmh=speeds, orders=orders)
    parts = [railwear.stability(metro_with({"speed_kmh": 70.0}, traction_coefficient=s["traction_coefficient"]),
                                speeds_kmh=speeds, orders=orders).growth_rate for s in CYCLE]
    expected = sum(s["share"] * p for s, p in zip(CYCLE, parts))
    np.testing.assert_allclose(cycle.growth_rate.values, expected.values, rtol=1e-12, atol=0)
    mean = sum(s["share"] * s["traction_coefficient"] for s in CYCLE)  # -0.0055
    assert f"mean creep force {mean:+.3f} x load, braking 30%" in cycle.attrs["source"]
    assert "creep force +0.05 x load" in railwear.stability("metro", speeds_kmh=[70], orders=[8]).attrs["source"]
