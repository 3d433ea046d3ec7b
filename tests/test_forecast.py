"""The measured-wheel forecast against a wheel whose growth rate is known in closed form."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import forecast
from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.pde import dispersion
from railwear.scenario import parse_scenario

# Coarse grids keep these tests fast; what they check does not depend on resolution.
pytestmark = pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")

A, ORDER, LIMIT, EPSILON = 20e-6, 4, 0.3e-3, 1e-3
SPEEDS_KMH = [50.0, 75.0, 100.0, 125.0, 150.0]


def anti_diffusion(kmh):
    return 0.1 * (np.asarray(kmh) / 100.0) ** 2  # rad² per unit time: h = -a(v) u_xx


def scenario_text(scatter_kmh, samples=64):
    curvature = [-1.0, -0.5, 0.0, 0.5, 1.0]
    rate = [[-float(anti_diffusion(v)) * s for v in SPEEDS_KMH] for s in curvature]
    return f"""
name = "synthetic"
[operation]
speed_kmh = 100.0
life_distance_km = 10000.0
[wear_rate]
form = "table"
curvature_m = {curvature}
table_speed_kmh = {SPEEDS_KMH}
rate_m = {rate}
[solver]
points = 64
epsilon = {EPSILON}
nu = 0.0
t_end = 2.0
[service]
speed_kmh = [100.0]
speed_weights = [1.0]
speed_scatter_kmh = {scatter_kmh}
samples = {samples}
seed = 4
"""


def wheel(tmp_path):
    angle = np.arange(0.0, 360.0, 2.0)
    lines = ["angle_deg,deviation_um"] + [f"{a},{A * 1e6 * np.cos(np.radians(ORDER * a))}" for a in angle]
    path = tmp_path / "wheel.csv"
    path.write_text("\n".join(lines) + "\n")
    return np.radians(angle), A * np.cos(ORDER * np.radians(angle)), path


def known_crossing_km(kmh):
    sigma = dispersion(anti_diffusion(kmh), ORDER, EPSILON)
    return np.log(LIMIT / (2 * A)) / sigma * 10000.0


def test_without_scatter_the_crossing_is_the_closed_form(tmp_path):
    angle, dev, _ = wheel(tmp_path)
    ds = forecast.forecast(parse_scenario(scenario_text(0.0, samples=4)), angle, dev, LIMIT)
    np.testing.assert_allclose(ds.crossing_distance.values, known_crossing_km(100.0), rtol=2e-3)
    assert ds.attrs["dominant_order"] == ORDER


def test_the_crossing_is_also_said_in_months_at_the_daily_mileage(tmp_path):
    angle, dev, _ = wheel(tmp_path)
    text = scenario_text(0.0, samples=4).replace("life_distance_km = 10000.0", "life_distance_km = 10000.0\ndaily_distance_km = 600.0")
    ds = forecast.forecast(parse_scenario(text), angle, dev, LIMIT)
    said = forecast.report(ds)
    km = float(ds.crossing_distance[0])
    assert "months of service at 600 km a day (operation.daily_distance_km)" in said
    assert f"reached after {km:,.0f} km ({km / 600 / (365.25 / 12):.1f} months)" in said
    assert "months" not in forecast.report(forecast.forecast(parse_scenario(scenario_text(0.0, samples=4)), angle, dev, LIMIT))


def test_known_crossing_lies_in_the_monte_carlo_band(tmp_path):
    angle, dev, _ = wheel(tmp_path)
    ds = forecast.forecast(parse_scenario(scenario_text(10.0)), angle, dev, LIMIT)
    expected = known_crossing_km(100.0)
    assert ds.attrs["crossing_p05_km"] < expected < ds.attrs["crossing_p95_km"]
    # each sample crosses where its own speed says, or not within the horizon
    known = known_crossing_km(ds.speed_kmh.values)
    inside = known < ds.attrs["horizon_km"]
    np.testing.assert_allclose(ds.crossing_distance.values[inside], known[inside], rtol=2e-3)
    assert np.all(np.isinf(ds.crossing_distance.values[~inside]))


def test_speed_distribution_must_sum_to_one():
    text = scenario_text(0.0).replace("speed_kmh = [100.0]\nspeed_weights = [1.0]",
                                      "speed_kmh = [100.0, 120.0]\nspeed_weights = [0.5, 0.4]")
    with pytest.raises(ScenarioError, match="'service': the speed distribution must sum to 1"):
        parse_scenario(text, source="s")


def test_cli_forecast_and_its_errors(tmp_path):
    _, _, path = wheel(tmp_path)
    (tmp_path / "s.toml").write_text(scenario_text(10.0, samples=8))
    runner = CliRunner()
    r = runner.invoke(app, ["forecast", str(path), "--scenario", str(tmp_path / "s.toml"),
                            "--limit", "300um", "-o", str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    assert "median" in r.output and (tmp_path / "out" / "forecast.png").exists()
    r = runner.invoke(app, ["forecast", str(path), "--limit", "0.3"])
    assert r.exit_code == 2 and "--limit" in r.output
    bad = tmp_path / "bad.csv"
    bad.write_text(path.read_text().replace("angle_deg", "angle"))
    r = runner.invoke(app, ["forecast", str(bad), "--scenario", str(tmp_path / "s.toml")])
    assert r.exit_code == 2 and "without a unit" in r.output
    r = runner.invoke(app, ["forecast", str(bad), "--scenario", str(tmp_path / "s.toml"),
                            "--angle-unit", "deg", "-o", str(tmp_path / "out2")])
    assert r.exit_code == 0, r.output
