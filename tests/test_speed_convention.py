"""One convention for speed in the files railwear writes (docs/outputs.md): ``speed`` in m s-1,
with ``speed_kmh`` in km h-1 beside it on the same dimensions (issue 12, item 6)."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import analysis, api, results, sweep
from railwear.cli import app
from railwear.scenario import builtin_text, dynamics, parse_scenario

pytestmark = pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")


def _both(ds, kmh, dims):
    """``speed`` in m s-1 and ``speed_kmh`` in km h-1 over ``dims``, the latter reading ``kmh`` exactly."""
    speed, speed_kmh = ds["speed"], ds["speed_kmh"]
    assert speed.attrs["units"] == "m s-1" and speed_kmh.attrs["units"] == "km h-1"
    assert speed.dims == speed_kmh.dims == dims
    np.testing.assert_array_equal(speed_kmh.values, kmh)
    np.testing.assert_allclose(speed.values, np.asarray(kmh) / 3.6, rtol=1e-15)


def _stable(speeds="20.0"):
    text = builtin_text("stable").replace("points = 1024", "points = 64").replace("n_save = 101", "n_save = 5")
    return parse_scenario(text.replace("speed_kmh = 20.0", f"speed_kmh = {speeds}"))


def test_long_term_results_and_their_file(tmp_path):
    one = api.run(_stable())
    _both(one, 20.0, ())
    assert "speed_kmh" in one.coords
    batch = api.run(_stable("[20.0, 40.0]"))
    _both(batch, [20.0, 40.0], ("speed",))
    results.write_netcdf(batch, tmp_path / "result.nc")
    _both(results.read_netcdf(tmp_path / "result.nc"), [20.0, 40.0], ("speed",))


def test_stability_maps():
    ds = analysis.stability("onset", speeds_kmh=[100, 230], orders=[2, 5])
    _both(ds, [100.0, 230.0], ("speed",))
    assert "speed_kmh" in ds.coords


def test_dynamics_files(tmp_path):
    text = (dynamics._builtin_dir() / "hunting.toml").read_text()
    path = tmp_path / "short.toml"
    path.write_text(text.replace("duration_s = 4.0", "duration_s = 0.05").replace("n_output = 4001", "n_output = 11"))
    r = CliRunner().invoke(app, ["simulate", str(path), "-o", str(tmp_path / "out")])
    assert r.exit_code == 0, r.output
    _both(results.read_netcdf(tmp_path / "out" / "dynamics.nc"), [180.0, 280.0], ("speed",))


def test_sweeps_over_the_speed_and_over_another_field(tmp_path):
    base = _stable()
    over_speed = sweep.run_sweep(base, [sweep.parse_vary("operation.speed_kmh=20,40")], tmp_path / "a")
    _both(over_speed, [20.0, 40.0], ("operation.speed_kmh",))
    # variables, not coordinates: the coordinates of a sweep are the fields it varies
    assert list(over_speed.coords) == ["angle", "operation.speed_kmh"]
    _both(results.read_netcdf(tmp_path / "a" / "sweep.nc"), [20.0, 40.0], ("operation.speed_kmh",))
    over_load = sweep.run_sweep(base, [sweep.parse_vary("wheel.static_load_kN=70")], tmp_path / "b",
                                executor=sweep.SerialExecutor())
    _both(over_load, 20.0, ())
    sampled = sweep.with_speeds(over_load, base, {"operation.speed_m_s": np.array([5.0, 12.5])}, True)
    _both(sampled, [18.0, 45.0], ("sample",))


def test_speeds_that_are_results_say_km_h_in_their_units():
    from railwear import forecast
    from railwear.scenario import load_scenario

    m = sweep.hunting_map(load_scenario("polygonalisation"), np.array([0.1]), np.array([2e6]))
    assert m.critical_speed.attrs["units"] == "km h-1" and "speed" not in m.coords
    sc = load_scenario("forecast")
    sc = sc.model_copy(update={"solver": sc.solver.model_copy(update={"points": 64}),
                               "service": sc.service.model_copy(update={"samples": 2})})
    x = 2 * np.pi * np.arange(64) / 64
    ds = forecast.forecast(sc, x, 10e-6 * np.cos(3 * x), 0.1e-3, horizon=0.01, n_save=3)
    assert ds.speed.attrs["units"] == "km h-1" and ds.speed.dims == ("sample",)
