"""Several wheels on one rail (WheelsOnRail): the Fourier technique over the wheels of a bogie,
coupled through the rail's transfer receptance; each order's rate an eigenproblem over them."""

import json
import subprocess
import sys

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.longterm.fourier import Fourier, FourierCycle
from railwear.longterm.vehicle_track import (METRO, VehicleTrackModel, WheelsFourier, WheelsOnRail,
                                              wheels_growth_map)
from railwear.scenario import build, load_scenario, scenario_hash
from railwear.units import KM, kmh_to_m_s

ORDERS = np.arange(2, 21)


@pytest.fixture(scope="module")
def metro():
    sc = load_scenario("metro")
    model, band = build.linear_model(sc, build.one_speed(sc))
    law = build.wear_law(sc)
    return model, law, band, Fourier.disk_wheel(model, law, band).rates(ORDERS)


def test_one_wheel_is_the_single_wheel_model(metro):
    model, law, band, single = metro
    lam, modes = WheelsOnRail(model, (0.0,)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam[:, 0], single, rtol=1e-12)  # measured 2e-14 (the bay unfolded)
    np.testing.assert_allclose(np.abs(modes), 1.0, rtol=1e-15)


def test_two_wheels_far_apart_are_two_independent_wheels(metro):
    """60 m apart the rail carries nothing from one to the other: both rates are the single wheel's."""
    model, law, band, single = metro
    lam, _ = WheelsOnRail(model, (0.0, 60.0)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam, np.column_stack([single, single]), rtol=1e-6)


def test_a_bogie_splits_each_order_into_in_phase_and_anti_phase(metro):
    """Wheelbase 2.4 m, four sleeper bays: the bay-averaged matrix is symmetric (reciprocity) with
    equal diagonals, so its combinations are the wheels in phase and in anti-phase, (1, ±1)/√2, to
    1e-10; at order 8 they grow at different rates (anti-phase +0.19, in phase +0.16 per 10 000 km,
    the single wheel's +0.18 between them: a split of 12 % of it, the mean 3.5 % below)."""
    model, law, band, single = metro
    lam, modes = WheelsOnRail(model, (0.0, 2.4)).rates(ORDERS, law, band)
    ratio = modes[:, 1, :] / modes[:, 0, :]
    np.testing.assert_allclose(np.abs(ratio), 1.0, atol=1e-10)
    assert np.all(np.isclose(ratio.real, 1.0, atol=1e-10) | np.isclose(ratio.real, -1.0, atol=1e-10))
    k = list(ORDERS).index(8)
    assert lam[k, 0].real > single[k].real > lam[k, 1].real and ratio[k, 0].real == pytest.approx(-1.0)
    assert 0.1 < (lam[k, 0].real - lam[k, 1].real) / single[k].real < 0.15


def test_where_the_coupling_is_weak_the_mean_of_the_pair_is_the_single_wheel(metro):
    """At 4.8 m the split is first order in the coupling (0.8 % of the rate at order 8), the mean's
    departure from the single wheel second order (measured at most 7e-4 over orders 2-20)."""
    model, law, band, single = metro
    lam, _ = WheelsOnRail(model, (0.0, 4.8)).rates(ORDERS, law, band)
    np.testing.assert_allclose(lam.real.mean(axis=1), single.real, rtol=1e-3)
    k = list(ORDERS).index(8)
    assert (lam[k, 0].real - lam[k, 1].real) / single[k].real > 5e-3


def test_positions_are_checked():
    sc = load_scenario("metro")
    model, _ = build.linear_model(sc, build.one_speed(sc))
    with pytest.raises(Exception, match="positions"):
        WheelsOnRail(model, (1.0, 2.0))


def test_the_docs_table_is_what_its_script_prints(capsys):
    """docs/vehicle_track.md's wheelbase table is docs/wheels_on_rail.py's output, row for row."""
    import runpy
    from pathlib import Path

    docs = Path(__file__).resolve().parents[2] / "docs"
    runpy.run_path(str(docs / "wheels_on_rail.py"), run_name="__main__")
    rows = [line for line in capsys.readouterr().out.splitlines() if line.startswith("| 0")]
    page = (docs / "vehicle_track.md").read_text(encoding="utf-8")
    assert len(rows) == 5 and all(row in page for row in rows)


BOGIE = {"body.wheel_positions_m": [0.0, 2.5]}


def test_one_wheel_given_is_the_one_wheel_scenario_bit_for_bit(metro):
    """``wheel_positions_m = [0]`` builds the single-wheel Fourier technique, the same numbers bit
    for bit; left out, the scenario (and its hash) is what it was before the field existed."""
    sc = load_scenario("metro")
    one = load_scenario("metro", {"body.wheel_positions_m": [0.0]})
    assert "wheel_positions_m" not in sc.applicable()["body"] and scenario_hash(sc) != scenario_hash(one)
    a, b = build.fourier_technique(sc), build.fourier_technique(one)
    assert type(a) is type(b) is Fourier
    assert np.array_equal(a.rates(ORDERS), b.rates(ORDERS)) and a.mean_rate == b.mean_rate


def test_wheels_fourier_of_one_wheel_is_fourier_and_averages_a_cycle_by_distance(metro):
    """One wheel: the fastest eigen-rate is the single wheel's rate to 1e-12. Over a cycle of two
    segments (70 km/h traction on 3/4 of the distance, 40 km/h braking) the per-metre rates are
    :class:`FourierCycle`'s distance-weighted mean to 1e-12 and the mean wear the same."""
    model, law, band, single = metro
    one = WheelsFourier((WheelsOnRail(model, (0.0,)),), law, band)
    np.testing.assert_allclose(one.rates(ORDERS), single, rtol=1e-12)
    assert one.mean_rate == pytest.approx(Fourier.disk_wheel(model, law, band).mean_rate, rel=1e-14)
    slow = build.linear_model(build.at_demand(load_scenario("metro"), -0.03), kmh_to_m_s(40.0))[0]
    cycle = WheelsFourier((WheelsOnRail(model, (0.0,)), WheelsOnRail(slow, (0.0,))), law, band, (0.75, 0.25))
    reference = FourierCycle.of([Fourier.disk_wheel(m, law, band) for m in (model, slow)], (0.75, 0.25))
    np.testing.assert_allclose(cycle.rates(ORDERS), reference.rates(ORDERS), rtol=1e-12)
    assert cycle.mean_rate == pytest.approx(reference.mean_rate, rel=1e-12)
    with pytest.raises(ScenarioError, match="shares"):
        WheelsFourier((WheelsOnRail(model, (0.0,)),), law, band, (0.5,))


def test_a_bogie_run_takes_the_fastest_combination_and_names_it(metro):
    """``railwear.api.run`` of the metro scenario with a bogie of 2.5 m: each order evolves at the
    fastest eigen-rate of :meth:`WheelsOnRail.rates`, and the result and summary name its
    combination: at order 8 the two wheels in anti-phase with equal amplitudes."""
    from railwear import api, results

    model, law, band, _ = metro
    ds = api.run(load_scenario("metro", BOGIE))
    lam, _ = WheelsOnRail(model, (0.0, 2.5)).rates(ORDERS, law, band)
    np.testing.assert_allclose(ds.harmonic_growth_rate.sel(order=ORDERS).values, lam[:, 0].real, rtol=1e-12)
    run = results.summary(ds)["runs"][0]
    assert run["dominant_order"] == 8 and run["wheel_positions_m"] == [0.0, 2.5]
    phases, amplitudes = run["combination"]["phases_deg"], run["combination"]["amplitudes"]
    assert phases[0] == 0.0 and abs(abs(phases[1]) - 180.0) < 0.5  # measured -179.87: 2.5 m is not whole bays
    np.testing.assert_allclose(amplitudes, [1.0, 1.0], atol=1e-2)
    text = results.summary_text(results.summary(ds))
    assert "wheels at 0, 2.5 m on one rail: order 8 grows with their polygons at phases 0, -180 deg" in text
    modes = WheelsOnRail(model, (0.0, 2.5)).rail_modes()
    np.testing.assert_array_equal(ds.rail_mode_clamped.values, modes["clamped"])
    assert "rail between the wheels at 0 and 2.5 m: bending modes at 226-270, 368-469, 656-770 Hz" in text


def test_the_wheels_growth_map_of_one_wheel_is_the_growth_map():
    """The map of the fastest combination, one wheel: :meth:`VehicleCase.growth_map` to 1e-12."""
    law = build.wear_law(load_scenario("metro"))
    speeds, orders = kmh_to_m_s(np.array([60.0, 80.0])), np.arange(5, 12)
    one = wheels_growth_map(METRO, (0.0,), speeds, orders, law)
    np.testing.assert_allclose(one.growth_rate, METRO.growth_map(speeds, orders, law).growth_rate, rtol=1e-12)
    two = wheels_growth_map(METRO, (0.0, 2.5), speeds, orders, law)
    model = VehicleTrackModel(METRO.wheel(speeds[0]), METRO.track, 8, METRO.wheel_modes)
    lam, _ = WheelsOnRail(model, (0.0, 2.5)).rates(orders, law, METRO.band_width)
    np.testing.assert_allclose(two.growth_rate[0], lam[:, 0].real / speeds[0] * KM, rtol=1e-10)


def test_the_scenario_refuses_what_one_wheel_models_cannot_take():
    for positions in ([1.0, 2.5], [0.0, 2.5, 2.5], [0.0, 200.0]):
        with pytest.raises(ScenarioError, match="body.wheel_positions_m"):
            load_scenario("metro", {"body.wheel_positions_m": positions})
    with pytest.raises(ScenarioError, match="body.wheel_positions_m: the time-domain"):
        build.body(load_scenario("metro", {**BOGIE, "strategy.kind": "phenomenological"}))


def test_railwear_run_on_a_bogie_file(tmp_path):
    """The user path in a fresh interpreter: a scenario file with two wheels runs, its summary
    names the combination; a bad position is one line naming the field, exit 2."""
    from railwear.scenario import builtin_text

    text = builtin_text("metro").replace('kind = "vehicle_track"', 'kind = "vehicle_track"\nwheel_positions_m = [0, 2.5]')
    (tmp_path / "bogie.toml").write_text(text)
    out = subprocess.run([sys.executable, "-m", "railwear", "run", str(tmp_path / "bogie.toml"), "-o",
                          str(tmp_path / "out"), "--no-figures"], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    run = json.loads((tmp_path / "out" / "summary.json").read_text())["runs"][0]
    assert run["combination"]["order"] == 8 and abs(abs(run["combination"]["phases_deg"][1]) - 180) < 0.5
    (tmp_path / "bad.toml").write_text(text.replace("[0, 2.5]", "[0, -2.5]"))
    bad = subprocess.run([sys.executable, "-m", "railwear", "run", str(tmp_path / "bad.toml"), "-o",
                          str(tmp_path / "bad")], capture_output=True, text=True, timeout=120)
    assert bad.returncode == 2 and "body.wheel_positions_m" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1 and "Traceback" not in bad.stderr


def test_the_high_speed_wheelbase_row_is_in_the_docs():
    """docs/vehicle_track.md's wheelbase table holds docs/wheelbase_high_speed.py's 2.5 m row (the
    fastest order 24 on the 300 km/h line, the held third rail mode at 682 Hz, 23.7 orders)."""
    import runpy
    from pathlib import Path

    docs = Path(__file__).resolve().parents[2] / "docs"
    script = runpy.run_path(str(docs / "wheelbase_high_speed.py"))
    row = script["wheelbase_row"](2.5)[0]
    assert row.startswith("| 2.5 | 24 |") and "| 682 | 23.7 / 28.9 | yes |" in row
    assert row in (docs / "vehicle_track.md").read_text(encoding="utf-8")


def test_the_stability_map_of_a_bogie_says_it_maps_the_wheels_combination():
    from railwear import analysis

    ds = analysis.stability(load_scenario("metro", BOGIE), speeds_kmh=[60.0, 80.0], orders=[7, 8])
    assert ds.attrs["source"].endswith("; the fastest combination of the wheels at 0, 2.5 m")
    assert "wheels" not in analysis.stability("metro", speeds_kmh=[60.0], orders=[8]).attrs["source"]


def test_drifting_phases_average_the_coupling_out(metro):
    """Wheels of different diameters: wheel 2's order n reaches wheel 1 with a phase slipping at
    ``Δ`` (rad/s) on its tread. In wheel 1's frame the pair evolves with the constant matrix
    ``K = [[a, b], [b', d + iΔ]]`` (wheel 2's amplitude times ``e^{iΔt}``); its fastest real rate
    is the locked eigen-rate at ``Δ = 0`` and tends to wheel 1's own rate ``Re a`` as ``1/Δ``, the
    drifting model's rate."""
    model, law, band, _ = metro
    M = WheelsOnRail(model, (0.0, 2.5)).rate_matrix([8], law, band)[0]
    (a, b), (c, d) = M
    scale = abs(b)

    def rates(delta):  # wheel 1's branch, then wheel 2's (the one rotating at Δ)
        lam = np.linalg.eigvals(np.array([[a, b], [c, d + 1j * delta]]))
        return lam[np.argsort(lam.imag)].real

    lam, _ = WheelsOnRail(model, (0.0, 2.5)).rates([8], law, band)
    np.testing.assert_allclose(rates(0.0).max(), lam[0, 0].real, rtol=1e-12)
    errors = [np.max(np.abs(rates(k * scale) - [a.real, d.real])) for k in (50, 100, 200, 400)]
    assert errors[-1] < 1e-3 * scale  # about |b|² / Δ
    np.testing.assert_allclose(np.array(errors[:-1]) / np.array(errors[1:]), 2.0, rtol=0.05)  # first order in 1/Δ


def test_a_bogie_with_drifting_phases_grows_each_wheel_at_its_own_rate(metro):
    """``[body] wheel_phases = "drifting"``: the run's rate per order is the fastest wheel's own
    ``M_jj``, the result gives each wheel's, the summary says so; one wheel is unchanged."""
    from railwear import api, results

    model, law, band, single = metro
    ds = api.run(load_scenario("metro", {**BOGIE, "body.wheel_phases": "drifting"}))
    own = np.diagonal(WheelsOnRail(model, (0.0, 2.5)).rate_matrix(ORDERS, law, band), axis1=1, axis2=2)
    np.testing.assert_allclose(ds.harmonic_growth_rate.sel(order=ORDERS).values, own.real.max(axis=1), rtol=1e-12)
    np.testing.assert_allclose(ds.wheel_growth_per_km.sel(order=ORDERS).values, own.real / model.speed * KM,
                               rtol=1e-12)
    assert "combination_phase" not in ds and ds.attrs["wheel_phases"] == "drifting"
    locked = WheelsOnRail(model, (0.0, 2.5)).rates(ORDERS, law, band)[0].real
    assert np.all(own.real.max(axis=1) <= locked[:, 0] + 1e-18)  # no faster than the locked pair
    text = results.summary_text(results.summary(ds))
    assert "wheels at 0, 2.5 m on one rail, their polygons' phases drifting: each grows on its own, order 8 at" in text
    with pytest.raises(ScenarioError, match="body.wheel_phases: the relative phases"):
        load_scenario("metro", {"body.wheel_phases": "drifting"})
    with pytest.raises(ScenarioError, match="^body.wheel_phases: the time-domain"):
        build.strategy(load_scenario("metro", {**BOGIE, "body.wheel_phases": "drifting", "strategy.kind": "stepwise"}))
    assert scenario_hash(load_scenario("metro")) == scenario_hash(load_scenario("metro", {"body.wheel_phases": None}))


def test_the_multiplier_over_several_wheels_names_their_combination_too():
    from railwear import api, results

    over = {**BOGIE, "strategy.kind": "multiplier", "strategy.local": "none"}
    ds, fourier = api.run(load_scenario("metro", over)), api.run(load_scenario("metro", BOGIE))
    np.testing.assert_array_equal(ds.combination_phase.values, fourier.combination_phase.values)
    text = results.summary_text(results.summary(ds))
    assert "wheels at 0, 2.5 m on one rail: order 8 grows with their polygons at phases 0, -180 deg" in text
    drifting = api.run(load_scenario("metro", {**over, "body.wheel_phases": "drifting"}))
    assert "phases drifting: each grows on its own, order 8 at" in results.summary_text(results.summary(drifting))
