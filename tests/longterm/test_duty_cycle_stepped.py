"""Duty cycles under the stepped strategies: the stepwise frozen-geometry draws take a segment with
the probability of its share of the distance, at its speed and traction torque (DutyService), so
that the expected rate per distance is the distance-weighted mean of the segments'; the
multiplier law takes the cycle's averaged Fourier rates (local = "none"); what cannot run a cycle
is refused naming the field."""

import tomllib

import numpy as np
import pytest

import railwear
from railwear.errors import ScenarioError
from railwear.longterm.disk_wheel import DutyService, ServiceSpeeds
from railwear.scenario import build, builtin_text, parse_scenario
from railwear.units import kmh_to_m_s

# The disk wheel on its rail mass (the 'stepwise' built-in): pulling at +0.05 at 40 km/h and
# braking at -0.05 at 60 km/h, half the distance each. Orders 13 and 14 are the cycle's fastest
# growing ones (+4.1 and +3.9e-5 per km) and grow in both segments; orders 3 and 4 decay in both.
TWO = [{"share": 0.5, "speed_kmh": 40.0, "traction_coefficient": 0.05},
       {"share": 0.5, "speed_kmh": 60.0, "traction_coefficient": -0.05}]
GROWING, DECAYING = np.array([13, 14]), np.array([3, 4])


def stepwise_with(operation, body=(), initial=None, strategy=None, solver=(), scatter_kmh=0.0):
    """The 'stepwise' built-in at one speed (its [service] peaks left out) or over a cycle, the
    speeds scattered by ``scatter_kmh``."""
    data = tomllib.loads(builtin_text("stepwise"))
    data["operation"] = {"life_distance_km": 50000.0, **operation}
    if "speed_kmh" not in operation:
        data["contact"].pop("traction_coefficient")
    data["service"] = {"speed_scatter_kmh": scatter_kmh, "seed": 3}
    data["body"].update(body)
    data["solver"].update(solver)
    if initial is not None:
        data["initial"] = initial
    if strategy is not None:
        data["strategy"] = strategy
    return parse_scenario(data)


def test_a_cycle_of_one_segment_is_the_single_traction_stepwise_run_bit_for_bit():
    """Same seed, same draws (speeds scattered by 3 km/h): every variable of the result equal, and
    the cycle states its demand."""
    single = railwear.run(stepwise_with({"speed_kmh": 70.0}, solver={"depth_limit_mm": 0.1}, scatter_kmh=3.0))
    cycle = railwear.run(stepwise_with({"cycle": [{"share": 1.0, "speed_kmh": 70.0, "traction_coefficient": 0.05}]},
                                       solver={"depth_limit_mm": 0.1}, scatter_kmh=3.0))
    assert single.sizes["time"] > 3
    for name in single.data_vars:
        a, b = single[name].values, cycle[name].values
        assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f"), name
    assert float(single.speed) == float(cycle.speed)
    assert cycle.attrs["mean_traction_coefficient"] == 0.05 and cycle.attrs["braking_share"] == 0.0


def test_a_cycle_of_one_segment_draws_the_single_run_on_the_track_bit_for_bit():
    """The vehicle-track body (metro): one frozen-geometry set of draws, same seed, equal rates."""
    def metro(operation, contact):
        data = tomllib.loads(builtin_text("metro"))
        data["operation"] = {"life_distance_km": 1000.0, **operation}
        data["contact"] = {k: v for k, v in data["contact"].items() if k != "traction_coefficient"} | contact
        data["strategy"] = {"kind": "stepwise"}
        data["solver"] = {"points": 64}
        data["initial"] = {"kind": "harmonics", "orders": [8], "amplitudes_um": [5.0]}
        data["body"].update(samples=2, revolutions=1, transient_revolutions=1)
        return parse_scenario(data)

    single = metro({"speed_kmh": 70.0}, {"traction_coefficient": -0.04})
    cycle = metro({"cycle": [{"share": 1.0, "speed_kmh": 70.0, "traction_coefficient": -0.04}]}, {})
    u = build.initial_state(single)
    a, b = (build.body(s).statistics(u, np.random.default_rng(5)) for s in (single, cycle))
    assert isinstance(build.body(cycle).service, DutyService)
    for x, y in zip(a[:2], b[:2]):
        assert np.array_equal(x, y)


def test_the_draws_take_the_segments_in_proportion_to_their_shares():
    """3000 draws of a three-segment cycle: each runs one segment's speed and torque ``f W R0``, and
    the counts pass Pearson's chi-square test against the shares (2 degrees of freedom; 13.8 is
    the 0.1 % point, so a right sampler fails one seed in a thousand)."""
    cycle = [{"share": 0.2, "speed_kmh": 40.0, "traction_coefficient": 0.1},
             {"share": 0.5, "speed_kmh": 70.0, "traction_coefficient": 0.003},
             {"share": 0.3, "speed_kmh": 50.0, "traction_coefficient": -0.09}]
    sc = stepwise_with({"cycle": cycle}, body={"samples": 3000, "transient_revolutions": 0})
    body = build.body(sc)
    u = build.initial_state(sc)
    load, radius = body.model.static_load, body.model.radius
    runs = [(m.speed, m.traction_torque) for m, *_ in body.frozen_runs(u - u.mean(), np.random.default_rng(11),
                                                                       body.new_cost())]
    segments = {(kmh_to_m_s(s["speed_kmh"]), s["traction_coefficient"] * load * radius): k for k, s in enumerate(cycle)}
    counts = np.bincount([segments[r] for r in runs], minlength=3)  # a draw off every segment is a KeyError
    expected = 3000 * np.array([s["share"] for s in cycle])
    chi2 = float(np.sum((counts - expected) ** 2 / expected))
    assert chi2 < 13.8, (counts, chi2)
    # the service itself, as the body draws it: speeds and peaks from one generator, as before
    service = body.service
    v, k = service.draw(np.random.default_rng(2), 8)
    assert np.array_equal(v, service.sample(np.random.default_rng(2), 8)) and np.array_equal(v, np.asarray(service.peaks)[k])


def test_the_service_of_a_cycle_counts_seconds_at_the_distance_over_time_speed():
    sc = stepwise_with({"cycle": TWO})
    service = build.service_speeds(sc)
    assert service.mean == pytest.approx(1 / (0.5 / kmh_to_m_s(40.0) + 0.5 / kmh_to_m_s(60.0)), rel=1e-15)
    assert service.mean == sc.operation.speeds
    assert ServiceSpeeds((10.0, 20.0)).mean == 15.0  # a plain service keeps its arithmetic mean
    with pytest.raises(ScenarioError, match="demands: one per peak"):
        DutyService((10.0, 20.0), (0.5, 0.5), 0.0, (0.05,))


def test_a_stepped_run_over_a_cycle_matches_the_averaged_fourier_rates():
    """The stepwise run (Euler, 64 draws in 8 steps of 8) from 2 um harmonics over 2500 km: the
    growth of each order per step, ``Re(Δû_n / (û_n ΔT))``, is that step's Monte Carlo rate; its
    mean over the steps against the cycle's averaged Fourier rates ``Σ p_k λ_n^k / V_k`` (with the
    64-point grid's filter sinc³(n/64), as for the direct run).

    Error budget: within a segment every draw gives the same rate (the dynamics over a frozen
    harmonic reach the same periodic state whatever the phase); the draws differ by the segment
    they take, so the Monte Carlo error of the mean is ``sqrt(p (1-p) / N) |r_1 - r_2|``: 0.8 %
    and 1.2 % of orders 13 and 14 at N = 64 (their segments' rates differ by 12 % and 19 %).
    Each segment alone is 1.2-1.5 % above (braking) and 1.3-1.9 % below (traction) its own
    Fourier rate; in the mean these cancel to 0.1 %. 5 % is more than four standard errors:
    measured -1.2 % (13) and -1.9 % (14) with this seed (standard errors of the run 0.5 % and
    0.7 %), -1.2 to +2.0 % over four seeds. The slow decaying orders 3 and 4: each segment 1.6-5 %
    above its Fourier rate, their mean 2-4.5 %, and 1.3 % and 2.1 % Monte Carlo error, so 10 %
    (measured +2.5 % and -1.3 %; up to +6.9 % over four seeds). The mean wear per metre is the
    same in both segments (the frictional power per distance, ``F² / f11``), to 1e-3."""
    orders = np.concatenate([DECAYING, GROWING])
    sc = stepwise_with({"cycle": TWO, "life_distance_km": 2500.0}, body={"samples": 8, "revolutions": 2,
                                                                          "transient_revolutions": 2},
                       initial={"kind": "harmonics", "orders": orders.tolist(), "amplitudes_um": [2.0] * orders.size},
                       strategy={"kind": "stepwise", "step_limit_um": 10.0})
    ds = railwear.run(sc)
    spectrum = np.fft.rfft(ds.u.values, axis=1)[:, orders]
    dT = np.diff(ds.time.values)
    per_step = ((spectrum[1:] - spectrum[:-1]) / (spectrum[:-1] * dT[:, None])).real
    assert per_step.shape[0] == 8
    stepped = (per_step * dT[:, None]).sum(0) / dT.sum()
    error = per_step.std(0, ddof=1) / np.sqrt(per_step.shape[0])
    technique = build.fourier_technique(sc)
    fourier = (technique.rates(orders).real * build.life_distance(sc) / technique.speed * np.sinc(orders / 64) ** 3)
    assert np.all(fourier[-2:] > 0) and np.all(fourier[:2] < 0)
    np.testing.assert_allclose(stepped[-2:], fourier[-2:], rtol=0.05)
    np.testing.assert_allclose(stepped[:2], fourier[:2], rtol=0.10)
    assert np.all(error[-2:] < 0.02 * fourier[-2:])  # the run reports a standard error of the budget's size
    mean_depth = float(ds.mean_removed_depth[-1]) / (build.life_distance(sc) * float(ds.time[-1]))
    assert mean_depth == pytest.approx(-technique.mean_rate / technique.speed, rel=1e-3)


def test_the_multiplier_takes_the_averaged_fourier_rates_of_a_cycle():
    """local = "none": the multiplier law's solution is the Fourier technique's over the cycle
    (ETDRK4 exact on the linear part), to 1e-9 of the wheel's out-of-roundness."""
    def direct_with(strategy):
        data = tomllib.loads(builtin_text("direct"))
        data["operation"] = {"life_distance_km": 20000.0, "cycle": TWO}
        data["contact"].pop("traction_coefficient")
        data["strategy"] = strategy
        data["body"].pop("transient_revolutions")
        return parse_scenario(data)

    multiplier = build.strategy(direct_with({"kind": "multiplier", "local": "none"}))
    sc = direct_with({"kind": "fourier"})
    u0 = build.initial_state(sc)
    a = multiplier.run(u0, until=0.5).u.values[-1]
    b = build.strategy(sc).run(u0, until=0.5).u.values[-1]
    assert np.max(np.abs(a - b)) < 1e-9 * np.ptp(u0)


@pytest.mark.parametrize("change, field", [
    ({"strategy": {"kind": "phenomenological"}}, r"operation\.cycle: the phenomenological strategy runs one operating point"),
    ({"strategy": {"kind": "multiplier"}}, r"strategy\.local: the load nonlinearity is one per segment"),
])
def test_what_cannot_run_a_cycle_is_refused_naming_the_field(change, field):
    data = tomllib.loads(builtin_text("direct"))
    data["operation"] = {"life_distance_km": 20000.0, "cycle": TWO}
    data["contact"].pop("traction_coefficient")
    if change["strategy"]["kind"] != "direct":
        data["body"].pop("transient_revolutions")
    data.update(change)
    with pytest.raises(ScenarioError, match=field):
        parse_scenario(data)


def test_a_cycle_with_service_peaks_or_on_the_wheelset_is_refused():
    data = tomllib.loads(builtin_text("stepwise"))
    data["operation"] = {"cycle": TWO}
    data["contact"].pop("traction_coefficient")
    with pytest.raises(ScenarioError, match=r"service\.speed_kmh: operation\.cycle gives the speeds"):
        parse_scenario(data)
    data = tomllib.loads(builtin_text("wheelset-wear"))
    data["operation"] = {"cycle": TWO}
    data["contact"].pop("traction_coefficient", None)
    with pytest.raises(ScenarioError, match=r"operation\.cycle: body 'wheelset' carries no longitudinal demand"):
        parse_scenario(data)


def test_the_fit_of_h_refuses_a_cycle():
    """h is fitted at one demand over speeds: a cycle would be left out silently, so it is refused."""
    with pytest.raises(ScenarioError, match=r"operation\.cycle: h is fitted at one traction demand"):
        build.fitted_h(stepwise_with({"cycle": TWO}))
