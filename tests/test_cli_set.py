"""``--set FIELD=VALUE`` on run, sweep, forecast and stability: scenario fields without a file."""

import pytest
import xarray as xr
from typer.testing import CliRunner

from railwear import api, forecast, sweep
from railwear.cli import app
from railwear.errors import OptionError, ScenarioError
from railwear.scenario import load_scenario, parse_set, scenario_hash


@pytest.mark.parametrize("text, value", [
    ("operation.speed_kmh=180", 180), ('name="x y"', "x y"), ("initial.orders=[1, 2]", [1, 2]),
    ("solver.dealias=true", True), ("strategy.kind=stepwise", "stepwise"), ("a.b = 1e-4 ", 1e-4)])
def test_values_are_toml_values_or_bare_words(text, value):
    assert parse_set(text) == (text.split("=")[0].strip(), value)


@pytest.mark.parametrize("text", ["speed", "=1", "operation.speed_kmh=", "initial.orders=[1,", 'name="x'])
def test_a_bad_set_is_refused(text):
    with pytest.raises(OptionError, match="--set"):
        parse_set(text)


def test_overrides_apply_as_in_a_file():
    sc = load_scenario("onset", ["operation.speed_kmh=180", "wheel.radius_m=0.5", "initial.orders=[3, 5]"])
    assert sc.operation.speed_kmh == 180 and sc.wheel.radius_m == 0.5 and list(sc.initial.orders) == [3, 5]
    assert load_scenario("onset", {"operation.speed_m_s": 50.0}).operation.speed_kmh is None  # one speed replaces the other


def test_a_new_kind_drops_the_fields_of_the_old_one():
    """onset's [solver] epsilon and nu belong to the phenomenological strategy: they give way."""
    sc = load_scenario("onset", ["operation.speed_kmh=180", "strategy.kind=stepwise"])
    assert sc.strategy.kind == "stepwise" and sc.operation.speed_kmh == 180
    sc = load_scenario("stepwise", ["strategy.kind=fourier"])
    assert sc.strategy.kind == "fourier"
    with pytest.raises(ScenarioError, match="solver.epsilon"):  # given with --set, it is an error
        load_scenario("onset", ["strategy.kind=stepwise", "solver.epsilon=1e-4"])


@pytest.mark.parametrize("command", [
    ["run", "onset"], ["stability", "onset", "--speeds", "100"], ["sweep", "onset", "--vary", "wheel.radius_m=0.4,0.5"],
    ["forecast", "wheel.csv", "--scenario", "forecast"]])
def test_every_command_takes_set(command, monkeypatch, tmp_path):
    seen = []

    def record(scenario, *args, **kwargs):
        seen.append(scenario)
        raise ScenarioError("stopped by the test")

    monkeypatch.setattr(api, "run", record)
    monkeypatch.setattr(sweep, "run_sweep", record)
    monkeypatch.setattr(forecast, "forecast_file", lambda measured, scenario, *a, **k: record(scenario))
    monkeypatch.setattr("railwear.analysis.stability", record)
    result = CliRunner().invoke(app, [*command, "-o", str(tmp_path / "out"),
                                      "--set", "wheel.radius_m=0.5", "--set", "contact.poisson=0.3"])
    assert result.exit_code == 2 and "stopped by the test" in result.output, result.output
    assert seen[0].wheel.radius_m == 0.5 and seen[0].contact.poisson == 0.3


def test_stability_writes_the_scenario_with_its_overrides(tmp_path):
    sets = ["operation.speed_kmh=150", "wheel.static_load_kN=60"]
    result = CliRunner().invoke(app, ["stability", "onset", "--speeds", "100,200", "--orders", "1:5:1",
                                      "-o", str(tmp_path), *[a for s in sets for a in ("--set", s)]])
    assert result.exit_code == 0, result.output
    with xr.open_dataset(tmp_path / "stability.nc", engine="h5netcdf") as ds:
        assert ds.attrs["scenario_hash"] == scenario_hash(load_scenario("onset", sets))


@pytest.mark.parametrize("value, field", [
    ("operation.speed_kmh=0", "operation.speed_kmh"), ("wheel.radius_m=big", "wheel.radius_m"),
    ("wheel.bogus=1", "wheel.bogus"), ("wheel.radius_m.x=1", "wheel.radius_m.x"), ("initial.orders=[1,", "initial.orders"),
    ("strategy.kind=bogus", "strategy")])
def test_a_bad_field_is_one_line_naming_it_with_status_2(value, field, tmp_path):
    result = CliRunner().invoke(app, ["run", "onset", "-o", str(tmp_path), "--set", value])
    assert result.exit_code == 2 and "Traceback" not in result.output, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and field in lines[0], result.output
