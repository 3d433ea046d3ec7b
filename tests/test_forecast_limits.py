"""Forecast limits as a level per order (dB re 1 µm) and as a band-level spectrum, against the
closed-form growth of a single order; and the forecast said in words for a maintenance engineer."""

import warnings

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import forecast
from railwear.cli import app
from railwear.errors import OptionError, ScenarioError
from railwear.pde import dispersion
from railwear.scenario import parse_scenario
from test_forecast import A, EPSILON, ORDER, anti_diffusion, scenario_text, wheel

pytestmark = pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")

SIGMA = dispersion(anti_diffusion(100.0), ORDER, EPSILON)  # per unit normed time at 100 km/h
LIFE = 10000.0  # km, the synthetic scenario's life distance
DIAMETER = 0.92  # m, the default [wheel] radius_m 0.46


def amplitude_crossing_km(amplitude):
    """Distance (km) at which order ORDER, A e^(σ t), reaches ``amplitude`` (m)."""
    return np.log(amplitude / A) / SIGMA * LIFE


def run(tmp_path, limit, scatter=0.0, samples=2):
    angle, dev, _ = wheel(tmp_path)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", forecast.NoScatterWarning)
        return forecast.forecast(parse_scenario(scenario_text(scatter, samples)), angle, dev, limit)


def test_a_level_for_every_order_is_crossed_where_the_amplitude_says(tmp_path):
    level = 30.0  # dB re 1 um: A_n / sqrt(2) = 10^(30/20) um
    ds = run(tmp_path, "30dB")
    expected = amplitude_crossing_km(np.sqrt(2) * 10 ** (level / 20) * 1e-6)
    np.testing.assert_allclose(ds.crossing_distance.values, expected, rtol=1e-3)
    assert ds.attrs["limit_kind"] == "order_level" and np.all(ds.limiting_order.values == ORDER)
    # the measured wheel starts 20 lg(A / sqrt 2 / 1 um) = 23.0 dB in order 4: 7.0 dB under the limit
    # (to the spline's error of the 2-degree record on the grid, 1e-6 dB)
    assert ds.attrs["initial_excess_db"] == pytest.approx(20 * np.log10(A / np.sqrt(2) / 1e-6) - level, abs=1e-4)


def test_a_table_of_levels_per_order_limits_only_its_orders(tmp_path):
    table = tmp_path / "orders.csv"
    table.write_text("order;level_db\n3;0\n4;27,5\n5;0\n")  # a device's dialect: ';' and a decimal comma
    ds = run(tmp_path, str(table))
    expected = amplitude_crossing_km(np.sqrt(2) * 10 ** (27.5 / 20) * 1e-6)
    np.testing.assert_allclose(ds.crossing_distance.values, expected, rtol=1e-3)
    (tmp_path / "wide.csv").write_text("order,level_db\n40,0\n")
    with pytest.raises(OptionError, match="limit: order 40 is above the grid's highest order 31"):
        run(tmp_path, str(tmp_path / "wide.csv"))


def test_a_band_spectrum_is_crossed_where_the_shared_line_says(tmp_path):
    # order 4 on a 0.92 m wheel: a line from 3.5 to 4.5 per circumference L = pi D; the 800 mm band
    # (k = 1) ends at 10^0.15 per metre, so it holds the share (10^0.15 L - 3.5) of the line's energy
    circumference = np.pi * DIAMETER
    share = 10**0.15 * circumference - 3.5
    assert 0.5 < share < 0.7
    level = 25.0
    table = tmp_path / "bands.csv"
    table.write_text("wavelength_mm,level_db\n800,25\n630,90\n")
    ds = run(tmp_path, str(table))
    # 10 lg(a^2/2 share / r0^2) = level  =>  a = sqrt(2 10^(level/10) / share) r0
    expected = amplitude_crossing_km(np.sqrt(2 * 10 ** (level / 10) / share) * 1e-6)
    np.testing.assert_allclose(ds.crossing_distance.values, expected, rtol=1e-3)
    np.testing.assert_allclose(ds.limiting_wavelength.values, 0.8)
    text = forecast.report(ds)
    assert "furthest above the limit there: the 800 mm band" in text


def test_the_iso3095_spectrum_and_a_table_it_cannot_use(tmp_path):
    ds = run(tmp_path, "iso3095")
    assert ds.attrs["limit_kind"] == "band_level" and "ISO 3095" in ds.attrs["limit_name"]
    (tmp_path / "odd.csv").write_text("wavelength_mm,level_db\n700,1\n")
    with pytest.raises(ScenarioError, match="limit: .*not a one-third-octave band centre"):
        run(tmp_path, str(tmp_path / "odd.csv"))
    with pytest.raises(OptionError, match="^limit: expected a peak-to-peak length"):
        forecast.parse_limit("3")
    with pytest.raises(OptionError, match=r"^--limit: levels must be in \[-100, 100\] dB"):
        forecast.parse_limit("300dB", "--limit")


def test_the_measured_wheel_is_echoed(tmp_path):
    ds = run(tmp_path, "0.3mm")
    a = ds.attrs
    assert a["measured_peak_to_peak_m"] == pytest.approx(2 * A, rel=1e-5)  # the spline onto the grid
    assert a["measured_dominant_order"] == ORDER
    assert a["measured_dominant_level_db"] == pytest.approx(20 * np.log10(A / np.sqrt(2) / 1e-6), abs=1e-4)
    share = 10**0.15 * np.pi * DIAMETER - 3.5
    i = int(np.argmin(np.abs(ds.band.values - 0.8)))
    assert ds.measured_band_level.values[i] == pytest.approx(10 * np.log10(A**2 / 2 * share / 1e-12), abs=1e-4)
    text = forecast.report(ds)
    assert text.startswith("measured wheel: 40.0 um peak to peak, dominant order 4 (20.0 um amplitude, 23.0 dB re 1 um)")
    assert f"(800 mm {ds.measured_band_level.values[i]:.1f})" in text  # longer than L/4: in brackets


def test_nothing_crossing_is_said_in_words_without_an_empty_panel(tmp_path):
    ds = run(tmp_path, "5mm", scatter=10.0, samples=8)
    assert ds.attrs["fraction_crossed"] == 0 and ds.attrs["dominant_order"] == ORDER
    text = forecast.report(ds)
    assert "no sample reaches the limit within the horizon of 20,000 km (8 samples)" in text
    assert "dominant order at 20,000 km: 4" in text
    assert "dominant order 0" not in text and "beyond 20,000 km to beyond" not in text
    from railwear import plots

    assert len(plots.forecast(ds).axes) == 1


def test_a_wheel_above_the_limit_at_0_km_is_said_so(tmp_path):
    ds = run(tmp_path, "10um", scatter=10.0, samples=4)
    assert np.all(ds.crossing_distance.values == 0) and ds.attrs["above_at_start"] == 1
    text = forecast.report(ds)
    assert f"already above the limit at 0 km by {20 * np.log10(40 / 10):.1f} dB" in text
    assert "median" not in text


def test_no_scatter_is_warned_and_reported_as_no_band(tmp_path):
    angle, dev, _ = wheel(tmp_path)
    with pytest.warns(forecast.NoScatterWarning, match="'90 % band' has no width"):
        ds = forecast.forecast(parse_scenario(scenario_text(0.0, 4)), angle, dev, "0.3mm")
    assert ds.attrs["scatter"] == 0
    text = forecast.report(ds)
    assert "the same for every sample" in text and "90 % band" not in text.split("warning:")[0]
    with warnings.catch_warnings():
        warnings.simplefilter("error", forecast.NoScatterWarning)
        ds = forecast.forecast(parse_scenario(scenario_text(10.0, 4)), angle, dev, "0.3mm")
    assert ds.attrs["scatter"] == 1 and "90 % band" in forecast.report(ds)


def test_cli_forecast_with_a_level_limit_and_no_scatter(tmp_path):
    _, _, path = wheel(tmp_path)
    (tmp_path / "s.toml").write_text(scenario_text(0.0, samples=2))
    r = CliRunner().invoke(app, ["forecast", str(path), "--scenario", str(tmp_path / "s.toml"),
                                 "--limit", "30dB", "-o", str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    assert "railwear: warning: the scenario's [service] gives every sample the same" in r.output
    assert "limit: 30 dB re 1 um in every order" in r.output
    assert (tmp_path / "out" / "forecast.png").is_file()
    assert (tmp_path / "out" / "forecast.txt").read_text() in r.output
