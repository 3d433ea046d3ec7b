"""The regime describes the wheel, not where its run stopped (issue 22, item 3): read from growth
per 10 000 km and the state reached (results.REGIME_RULE, docs/outputs.md)."""

import numpy as np
import pytest

import railwear
from railwear import results


@pytest.fixture(scope="module")
def metro():
    return railwear.run("metro")


def _measured(ds, tmp_path, peak_to_peak):
    """The metro wheel part way, where its peak to peak is nearest ``peak_to_peak`` (m), as a
    measured wheel's CSV file."""
    dev = ds.u - ds.u.mean("angle")
    k = int(np.argmin(np.abs((dev.max("angle") - dev.min("angle")).values - peak_to_peak)))
    path = tmp_path / "wheel.csv"
    rows = "\n".join(f"{a:.10g},{u:.10g}" for a, u in zip(np.degrees(ds.angle.values), dev.isel(time=k).values * 1e6))
    path.write_text("angle_deg,deviation_um\n" + rows + "\n")
    return path


def test_a_new_and_a_measured_metro_wheel_get_one_label(metro, tmp_path):
    """The new wheel runs 173 878 km to the 0.1 mm limit; the same wheel measured at 73 um
    (150 000 km on) runs 23 878 km to it. Order 8 grows at one rate in both (the Fourier
    technique is linear: 0.17864 per 10 000 km, 1e-9), so one label: polygonalising. The rule of
    before read the growth over the run and called the second 'onset'."""
    wheel = _measured(metro, tmp_path, 74e-6)
    measured = railwear.run(railwear.load_scenario("metro", ["initial.kind=measured", f"initial.file={wheel}"]))
    assert float(measured.distance[-1]) == pytest.approx(23878, abs=50)
    for ds in (metro, measured):
        assert int(ds.dominant_order) == 8
        rate = float(ds.growth_rate.sel(order=8)) * 1e4 / ds.attrs["life_distance_km"]
        assert rate == pytest.approx(0.178635, rel=1e-5)
        assert str(ds.regime.values) == "polygonalising"
    assert results.REGIME_RULE in measured.regime.attrs["rule"]


@pytest.mark.parametrize("limit_mm, regime", [(0.06, "polygonalising"), (0.05, "onset")])
def test_the_state_reached_decides_between_onset_and_polygon(limit_mm, regime):
    """With a limit the new wheel reaches before order 8 is its largest order (0.05 mm, at
    112 000 km, the eccentricity still largest) the wheel is at the onset: order 8 grows, but it
    is not yet an order-8 polygon. Once it is (0.06 mm, 133 000 km), the label is the full run's."""
    ds = railwear.run(railwear.load_scenario("metro", [f"solver.peak_to_peak_limit_mm={limit_mm}"]))
    assert str(ds.regime.values) == regime
    assert int(ds.dominant_order) == (8 if regime == "polygonalising" else 1)


@pytest.mark.parametrize("name, regime", [("stable", "stable"), ("smoothing", "smoothing"), ("onset", "onset"),
                                          ("polygonalisation", "polygonalising"),
                                          ("linear-dynamics", "polygonalising")])
def test_the_papers_cases_keep_their_labels(name, regime):
    """The paper's four regimes (Figs 9-11) under the rule from rates; the Fourier technique on
    the 70 km/h wheel grows order 8 by 47 % per 10 000 km to the largest: polygonalising (as
    stepwise, 24 %, and direct, 41 %, do: tests/scenario/test_scenarios_and_cli.py)."""
    assert str(railwear.run(name).regime.values) == regime


def _run(times, u, life=50000.0):
    """A hand-made result of the deviation ``u`` over (time, angle) at normed ``times``."""
    import xarray as xr

    from railwear.longterm.spectra import describe

    ds = xr.Dataset({"u": (("time", "angle"), u)},
                    coords={"time": times, "angle": np.arange(u.shape[1]) * 2 * np.pi / u.shape[1]})
    ds["stop_time"] = ((), float(times[-1]))
    ds = describe(ds)
    ds.attrs["life_distance_km"] = life
    return ds


def _harmonic(t, x, order, start, growth_per_10000_km, life=50000.0):
    rate = np.log1p(growth_per_10000_km) * life / 1e4
    return start * np.exp(rate * t)[:, None] * np.cos(order * x)[None, :]


@pytest.mark.parametrize("growth, start, span, regime", [
    (0.20, 2e-6, 3.0, "polygonalising"),  # order 8 grows 20 % per 10 000 km, 2 -> 31 um, and ends largest
    (0.20, 2e-6, 0.2, "onset"),  # the same growth, stopped before order 8 is largest: the state says onset
    (0.05, 20e-6, 1.0, "onset"),  # largest throughout, but growing 5 % per 10 000 km: under 10 %
    (0.11, 20e-6, 0.1, "polygonalising"),  # 11 %, largest: a short run (5000 km, x1.05) says so too
    (-0.001, 2e-6, 1.0, "stable"),
])
def test_hand_made_wheels(growth, start, span, regime):
    """An eccentricity of 15 um that stays, and order 8 from ``start`` growing as given; the label
    depends on the growth per 10 000 km and on which order is largest at the end, not on the
    factor over the run."""
    t = np.linspace(0.0, span, 21)
    x = np.arange(256) * 2 * np.pi / 256
    u = _harmonic(t, x, 1, 15e-6, 0.0) + _harmonic(t, x, 8, start, growth)
    assert results.wheel_regime(_run(t, u), 50000.0) == regime


def test_an_order_the_run_made_from_nothing_does_not_make_a_polygon():
    """An order 1 grown 400x from under 1 % of the largest start amplitude past a steady order 8:
    largest at the end but not an order the wheel had; the rms grows, so onset."""
    t = np.linspace(0.0, 1.0, 21)
    x = np.arange(256) * 2 * np.pi / 256
    u = _harmonic(t, x, 1, 1e-8, np.expm1(np.log(400) / 5)) + _harmonic(t, x, 8, 2e-6, 0.0)
    ds = _run(t, u)
    assert int(ds.dominant_order) == 1 and results.wheel_regime(ds, 50000.0) == "onset"


def test_a_round_wheel_is_stable():
    t = np.linspace(0.0, 1.0, 5)
    assert results.wheel_regime(_run(t, np.zeros((5, 64)) - t[:, None] * 1e-3), 50000.0) == "stable"


def test_an_order_growing_within_its_noise_is_not_onset():
    """Order 2 ends 3x higher, but dips to 0.2 between: its fitted rate is within 2 standard
    errors of zero, and the rms falls; stable (the old rule's case, under the wheel's rule)."""
    from railwear.geometry import roundness

    times = np.array([0.0, 0.5, 1.0])
    u = np.array([roundness.harmonics(64, [2, 3, 4], [1e-5 * a, 1e-5 * b, 1e-5 * b])
                  for a, b in ((1.0, 1.0), (0.2, 0.6), (3.0, 0.55))])
    ds = _run(times, u)
    rate, error = float(ds.growth_rate.sel(order=2)), float(ds.growth_rate_error.sel(order=2))
    assert rate > 0 and rate < 2 * error
    assert results.wheel_regime(ds, 50000.0) == "stable"


def test_a_strategy_result_carries_the_wheel_s_label_from_its_distance():
    """One rule: describe() labels a result by the wheel's rule where its distance coordinate gives
    the life, so a strategy's run() from Python and railwear.run agree (no second rule)."""
    t = np.linspace(0.0, 0.2, 21)
    x = np.arange(256) * 2 * np.pi / 256
    u = _harmonic(t, x, 1, 15e-6, 0.0) + _harmonic(t, x, 8, 2e-6, 0.20)
    import xarray as xr

    from railwear.longterm import regime
    from railwear.longterm.spectra import describe

    ds = xr.Dataset({"u": (("time", "angle"), u)},
                    coords={"time": t, "angle": x, "distance": ("time", t * 50000.0)})
    ds["stop_time"] = ((), float(t[-1]))
    ds = describe(ds)
    assert str(ds.regime.values) == "onset" == results.wheel_regime(ds, 50000.0)
    assert ds.regime.attrs["rule"] == regime.REGIME_RULE == results.REGIME_RULE
    bare = describe(xr.Dataset({"u": (("time", "angle"), u)}, coords={"time": t, "angle": x}))
    assert "regime" not in bare  # no distance, no life: no label rather than one of another rule
