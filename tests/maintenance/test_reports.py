"""The one file a planner can send: plan.html, fleet.html and load.html hold the text, the table
and the figures embedded, fetch nothing and name every policy and wheel; 'railwear plot' draws
plan.nc, fleet.nc and load.nc again and refuses a file of another kind in one line."""

import re

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import results
from railwear.cli import app
from railwear.maintenance import fleet as fleets
from railwear.maintenance import impact, outputs
from railwear.maintenance.fleet_input import write_synthetic
from railwear.maintenance.plan import plan
from railwear.maintenance.turning import RateTable
from railwear.scenario import load_scenario

SCENARIO = load_scenario("metro", ["solver.points=128"])


def known_rates(diameter):
    n = np.arange(1, 65)
    return RateTable(4e-7 - 2e-7j * n, -2.3e-10, 70 / 3.6, diameter / 2)


def small_plan():
    return plan(SCENARIO, ["metro-interval", "metro-condition"], growth=(1.0,), horizon_km=300_000)


def small_load():
    x = 2 * np.pi * np.arange(128) / 128
    inputs = impact.DynamicLoad(SCENARIO.body.case(SCENARIO), 1e-4 * np.cos(8 * x), (50 / 3.6, 70 / 3.6),
                                revolutions=1, transient=0.1, wheel="100 um of order 8")
    ds = impact.dynamic_load(inputs)
    ds.attrs.update({"scenario_name": "metro", "scenario": "name = 'metro'"})
    return ds


def self_contained(text, figures):
    """No external reference: nothing fetched, every image a data URI, one per figure."""
    assert not re.search(r"(?i)\b(?:src|href)\s*=\s*(?![\"']?data:)", text), "a reference to another file"
    assert not re.search(r"(?i)<a\s|<link|<script|<iframe|<object|@import|url\(", text)  # addresses in text are text
    images = re.findall(r'<img src="data:image/png;base64,([A-Za-z0-9+/=]+)"', text)
    assert len(images) == len(figures) and all(len(i) > 1000 for i in images)
    for f in figures:
        assert f"<figcaption>{f}</figcaption>" in text


@pytest.fixture(scope="module")
def fleet_ds(tmp_path_factory):
    folder = tmp_path_factory.mktemp("fleet")
    manifest, _ = write_synthetic(folder, 9, np.random.default_rng(3), points=90)
    return fleets.fleet(SCENARIO, manifest, "metro-condition", rates=known_rates)


def test_plan_html_is_one_file_naming_every_policy(tmp_path):
    ds = small_plan()
    outputs.write(ds, tmp_path)
    text = (tmp_path / outputs.HTML).read_text()
    self_contained(text, ["plan.png"])
    for name in ("metro-interval", "metro-condition"):
        assert text.count(name) >= 3  # the summary, the comparison and the policies' table
    assert "Chinese metro line" in text  # a policy's source
    assert "comparison (distance to scrap" in text


def test_fleet_html_is_one_file_naming_every_wheel(fleet_ds, tmp_path):
    fleets.write(fleet_ds, tmp_path)
    text = (tmp_path / fleets.HTML).read_text()
    self_contained(text, [f"{name}.png" for name in fleets.FIGURES])
    for wheel in fleet_ds.wheel.values:
        assert f"<td>{wheel}</td>" in text
    assert "metro-condition" in text and "due soonest" in text


def test_load_html_is_one_file_with_the_detectors(tmp_path):
    ds = small_load()
    impact.write(ds, tmp_path)
    text = (tmp_path / impact.HTML).read_text()
    self_contained(text, [impact.PEAK_FIGURE, impact.TRACE_FIGURE])
    for who in ("Network Rail", "Trafikverket", "North American advisory"):
        assert who in text
    assert "FRA Safety Advisory 2023-04" in text


def test_plot_draws_a_fleet_again_and_refuses_a_broken_one(fleet_ds, tmp_path):
    results.write_netcdf(fleet_ds, tmp_path / "fleet.nc")
    out = tmp_path / "again"
    done = CliRunner().invoke(app, ["plot", str(tmp_path / "fleet.nc"), "-o", str(out)])
    assert done.exit_code == 0, done.output
    for name in fleets.FIGURES:
        assert (out / f"{name}.png").is_file()
    assert (out / fleets.HTML).is_file()
    results.write_netcdf(fleet_ds.drop_vars("car"), tmp_path / "broken.nc")
    done = CliRunner().invoke(app, ["plot", str(tmp_path / "broken.nc"), "-o", str(out)])
    assert done.exit_code == 2 and len(done.output.strip().splitlines()) == 1
    assert "fleet.nc" in done.output and "car" in done.output


def test_plot_of_a_file_of_another_kind_says_what_it_draws(tmp_path):
    import xarray as xr

    results.write_netcdf(xr.Dataset({"x": ("t", [1.0])}), tmp_path / "other.nc")
    done = CliRunner().invoke(app, ["plot", str(tmp_path / "other.nc")])
    assert done.exit_code == 2 and len(done.output.strip().splitlines()) == 1
    assert "is not a railwear result" in done.output and "plan.nc, fleet.nc and load.nc" in done.output
