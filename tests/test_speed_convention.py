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


def _small_forecast(samples=3):
    from railwear import forecast
    from railwear.scenario import load_scenario

    sc = load_scenario("forecast")
    sc = sc.model_copy(update={"solver": sc.solver.model_copy(update={"points": 64}),
                               "service": sc.service.model_copy(update={"samples": samples})})
    x = 2 * np.pi * np.arange(64) / 64
    return sc, forecast.forecast(sc, x, 10e-6 * np.cos(3 * x), 0.1e-3, horizon=0.01, n_save=3)


def test_forecast_files_give_each_sample_its_speed_in_m_s(tmp_path):
    from railwear import forecast

    sc, ds = _small_forecast()
    drawn_kmh = forecast.draw_conditions(sc)[0]
    results.write_netcdf(ds, tmp_path / "forecast.nc")
    for d in (ds, results.read_netcdf(tmp_path / "forecast.nc")):
        speed, speed_kmh = d["speed"], d["speed_kmh"]
        assert speed.attrs["units"] == "m s-1" and speed_kmh.attrs["units"] == "km h-1"
        assert speed.dims == speed_kmh.dims == ("sample",)
        # the speed each sample ran (the scenario's own km/h -> m/s), and its km/h for reading
        np.testing.assert_array_equal(speed.values, drawn_kmh / 3.6)
        np.testing.assert_allclose(speed_kmh.values, drawn_kmh, rtol=0, atol=1e-6)
        assert np.ptp(speed.values) > 0  # the samples did draw different speeds


def _hunting(tmp_path):
    r = CliRunner().invoke(app, ["hunting-map", "polygonalisation", "--conicity", "0.05,0.2",
                                 "--yaw-stiffness", "2e6,1e7,1e8", "-o", str(tmp_path)])
    assert r.exit_code == 0, r.output
    return r.output, results.read_netcdf(tmp_path / "hunting.nc")


def test_hunting_files_give_the_critical_speed_in_m_s(tmp_path):
    from railwear.scenario import load_scenario

    output, ds = _hunting(tmp_path)
    m = sweep.hunting_map(load_scenario("polygonalisation"), [0.05, 0.2], [2e6, 1e7, 1e8])
    kmh = m.critical_speed_kmh
    speed, speed_kmh = ds["critical_speed"], ds["critical_speed_kmh"]
    assert speed.attrs["units"] == "m s-1" and speed_kmh.attrs["units"] == "km h-1"
    assert speed.dims == speed_kmh.dims == ("conicity", "yaw_stiffness")
    finite = np.isfinite(kmh.values)
    assert finite.any() and (~finite).any()  # stiff in yaw: stable at every speed, inf in both
    np.testing.assert_array_equal(np.isinf(speed.values), ~finite)
    np.testing.assert_array_equal(speed.values, m.critical_speed.values)  # the API returns what the file holds
    np.testing.assert_allclose(speed.values[finite] * 3.6, kmh.values[finite], rtol=0, atol=1e-6)
    np.testing.assert_allclose(speed_kmh.values[finite], kmh.values[finite], rtol=0, atol=1e-6)
    assert f"lowest critical speed {np.min(kmh.values):.0f} km/h" in output


def _as_before(ds, name):
    """``ds`` as the version before this convention wrote it: ``name`` in km h-1, no ``*_kmh``."""
    old = ds.drop_vars(f"{name}_kmh")
    return old.assign({name: old[name].copy(data=old[name].values * 3.6).assign_attrs(units="km h-1")})


def test_plot_draws_the_files_of_the_version_before(tmp_path):
    from matplotlib.image import imread

    _, new = _hunting(tmp_path / "new")
    _, forecast_ds = _small_forecast()
    old = {"hunting.nc": _as_before(new, "critical_speed"), "forecast.nc": _as_before(forecast_ds, "speed")}
    for name, ds in old.items():
        results.write_netcdf(ds, tmp_path / "old" / name)
        r = CliRunner().invoke(app, ["plot", str(tmp_path / "old" / name), "-o", str(tmp_path / "old")])
        assert r.exit_code == 0, r.output
    # the km/h of the old file is read by its units: the same map as from the new file
    np.testing.assert_array_equal(imread(tmp_path / "old" / "hunting.png"), imread(tmp_path / "new" / "hunting.png"))
    assert (tmp_path / "old" / "forecast.png").is_file()


def test_plot_refuses_a_speed_in_an_unknown_unit_in_one_line(tmp_path):
    _, ds = _hunting(tmp_path)
    ds["critical_speed"].attrs["units"] = "mph"
    results.write_netcdf(ds.drop_vars("critical_speed_kmh"), tmp_path / "odd" / "hunting.nc")
    r = CliRunner().invoke(app, ["plot", str(tmp_path / "odd" / "hunting.nc")])
    assert r.exit_code == 2
    assert r.output.count("\n") == 1 and "critical_speed" in r.output and "'mph'" in r.output
    assert "Traceback" not in r.output and not (tmp_path / "odd" / "hunting.png").exists()
