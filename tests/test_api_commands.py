"""The Python API behind the thin commands: railwear.stability, .fit, .figure, .forecast."""

import subprocess
import sys

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

import railwear
from railwear import analysis, cli
from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.scenario import build, load_scenario, parse_scenario, scenario_hash
from railwear.units import UM, kmh_to_m_s, m_s_to_kmh


def test_import_stays_light_and_the_entries_resolve():
    code = ("import sys, railwear; heavy = [m for m in ('numba', 'xarray', 'matplotlib', 'railwear.api') if m in sys.modules]; "
            "print(heavy)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
    assert railwear.stability is analysis.stability and railwear.fit is analysis.fit and railwear.figure is analysis.figure
    from railwear import forecast

    assert railwear.forecast is forecast and callable(railwear.forecast.forecast_file)
    with pytest.raises(AttributeError, match="no attribute 'stabilty'"):
        railwear.stabilty


def test_stability_of_a_fourier_scenario_is_the_transfer_function_map():
    from railwear.longterm import fourier

    sc = load_scenario("linear-dynamics")
    assert sc.strategy.kind == "fourier"
    speeds_kmh, orders = [120.0, 240.0], [2, 5, 9]
    ds = railwear.stability(sc, speeds_kmh, orders, amplitude=1e-5)  # the amplitude is the PDE's only
    direct = fourier.stability_map(lambda v: build.disk_wheel_model(sc, v), kmh_to_m_s(np.array(speeds_kmh)), orders,
                                   build.wear_law(sc), build.band_width(sc))
    xr.testing.assert_allclose(ds.drop_vars("speed_kmh"), direct, rtol=1e-12)  # + speed_kmh
    assert ds.growth_rate.attrs["units"] == "km-1"
    assert ds.attrs["source"] == "disk-wheel dynamics (Fourier technique), creep force +0.05 x load"
    assert ds.attrs["scenario_name"] == "linear-dynamics" and ds.attrs["scenario_hash"] == scenario_hash(sc)


@pytest.mark.parametrize("amplitude", [None, 0.0, 25 * UM])
def test_stability_of_the_evolution_equation_is_its_dispersion_map(amplitude):
    from railwear.pde import stability_map

    sc = load_scenario("polygonalisation")
    assert sc.strategy.kind == "phenomenological"
    speeds_kmh, orders = np.array([60.0, 180.0, 300.0]), np.arange(1, 13)
    ds = railwear.stability("polygonalisation", speeds_kmh, orders, amplitude)
    a = sc.initial.rms_um * UM if amplitude is None else amplitude
    direct = stability_map(build.wear_rate(sc), kmh_to_m_s(speeds_kmh), orders, sc.solver.epsilon, sc.solver.nu, a)
    xr.testing.assert_allclose(ds.drop_vars("speed_kmh"), direct, rtol=1e-12)  # + speed_kmh
    assert ds.attrs["amplitude"] == a
    assert ds.attrs["source"] == f"evolution equation, crest amplitude {a / UM:g} µm"
    # the default grid is the command line's 20:300:10 km/h x 1:30
    full = railwear.stability("polygonalisation", amplitude=amplitude)
    np.testing.assert_allclose(m_s_to_kmh(full.speed.values), np.arange(20, 301, 10))
    np.testing.assert_array_equal(full.order.values, np.arange(1, 31))


@pytest.mark.parametrize("kwargs, field", [
    (dict(speeds_kmh=[100.0, -5.0]), "speeds_kmh"),
    (dict(speeds_kmh=[]), "speeds_kmh"),
    (dict(orders=[0, 1, 2]), "orders"),
    (dict(orders=[1.5, 2]), "orders"),
    (dict(amplitude=-1e-6), "amplitude"),
    (dict(amplitude=float("nan")), "amplitude"),
])
def test_stability_bad_input_names_the_field(kwargs, field):
    with pytest.raises(ScenarioError, match=f"^{field}: "):
        railwear.stability("polygonalisation", **kwargs)


def test_stability_bad_scenario_field_is_a_scenario_error(tmp_path):
    path = tmp_path / "s.toml"
    path.write_text("[solver]\nepsilon = -1.0\n")
    with pytest.raises(ScenarioError, match="solver.epsilon"):
        railwear.stability(path)


def test_fit_and_figure_reject_bad_input_before_any_work():
    with pytest.raises(ScenarioError, match="^speeds_kmh: "):
        railwear.fit(speeds_kmh=[0.0])
    with pytest.raises(ScenarioError, match="unknown name 'fig99'"):
        railwear.figure("fig99")
    with pytest.raises(ScenarioError, match="no built-in scenario 'nonesuch'"):
        railwear.figure("teeth", "nonesuch")


def test_fit_returns_the_statistics_the_fit_and_the_scenario_that_runs_it(monkeypatch):
    """The wiring: speeds in km/h reach the frozen-geometry fit in m/s, and the returned scenario
    is the fit written into the scenario (the fit itself is tested in tests/longterm)."""
    calls = []

    def fake_fitted_h(sc, speeds):
        calls.append((sc.name, speeds))
        return "statistics", "fit"

    monkeypatch.setattr(build, "fitted_h", fake_fitted_h)
    monkeypatch.setattr(build, "with_fitted_h", lambda sc, fit: (sc.name, fit))
    out = railwear.fit(speeds_kmh=[60.0, 80.0])
    assert out == ("statistics", "fit", ("stepwise", "fit"))
    assert out.statistics == "statistics" and out.scenario == ("stepwise", "fit")
    np.testing.assert_allclose(calls[0][1], [60 / 3.6, 80 / 3.6], rtol=1e-15)
    railwear.fit("onset")
    assert calls[1] == ("onset", None)


def test_teeth_figure_returns_its_data():
    import matplotlib

    matplotlib.use("agg")
    data, fig = railwear.figure("teeth")
    assert set(data.data_vars) >= {"wear_intensity", "tooth_depth"}
    assert data.attrs["speed"] == pytest.approx(build.service_speeds(load_scenario("stepwise")).mean)
    assert fig.axes[0].get_xlabel() == "time (s)"


FORECAST_SCENARIO = """
name = "synthetic"
[operation]
speed_kmh = 100.0
life_distance_km = 10000.0
[wear_rate]
form = "cubic"
[solver]
points = 64
epsilon = 1e-3
nu = 0.0
t_end = 0.5
[service]
speed_kmh = [100.0]
speed_weights = [1.0]
speed_scatter_kmh = 10.0
samples = 16
seed = 4
"""


@pytest.fixture
def wheel(tmp_path):
    angle = np.arange(0.0, 360.0, 4.0)
    dev = 20.0 * np.cos(np.radians(4 * angle))
    path = tmp_path / "wheel.csv"
    path.write_text("angle_deg,deviation_um\n" + "".join(f"{a},{d}\n" for a, d in zip(angle, dev)))
    (tmp_path / "s.toml").write_text(FORECAST_SCENARIO)
    return path, np.radians(angle), dev * UM, tmp_path / "s.toml"


@pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")
def test_forecast_file_is_the_forecast_with_the_overrides(wheel):
    path, angle, dev, scenario = wheel
    ds = railwear.forecast.forecast_file(path, scenario, 50 * UM, samples=3, seed=7, horizon_km=2000.0)
    sc = parse_scenario(FORECAST_SCENARIO.replace("samples = 16\nseed = 4", "samples = 3\nseed = 7"))
    direct = railwear.forecast.forecast(sc, angle, dev, 50 * UM, horizon=0.2)
    xr.testing.assert_allclose(ds, direct, rtol=1e-12)
    assert ds.attrs == direct.attrs
    assert ds.sizes["sample"] == 3 and ds.attrs["horizon_km"] == pytest.approx(2000.0)


@pytest.mark.parametrize("kwargs, message", [
    (dict(samples=0), "^samples: "),
    (dict(horizon_km=-1.0), "^horizon_km: "),
    (dict(limit=0.0), "^limit: "),
    (dict(angle_unit="deg"), None),  # accepted: the column is named with its unit
])
def test_forecast_file_bad_input_names_the_field(wheel, monkeypatch, kwargs, message):
    path, _, _, scenario = wheel
    monkeypatch.setattr(railwear.forecast, "forecast", lambda *a, **k: "ran")
    if message is None:
        assert railwear.forecast.forecast_file(path, scenario, **kwargs) == "ran"
    else:
        with pytest.raises(ScenarioError, match=message):
            railwear.forecast.forecast_file(path, scenario, **kwargs)


def test_cli_forecast_bad_samples_is_one_line_with_status_2(wheel):
    path, _, _, scenario = wheel
    r = CliRunner().invoke(app, ["forecast", str(path), "--scenario", str(scenario), "--samples", "0"])
    assert r.exit_code == 2 and r.output.startswith("railwear: error: samples: ") and r.output.count("\n") == 1


def test_compile_notice_once_when_numba_compiles_and_not_otherwise(monkeypatch, tmp_path):
    """The notice hangs on numba's compile event, which a cache hit does not raise: a kernel
    compiled during a command prints it (once), a command that compiles nothing stays quiet. (It
    prints when a compile goes on for cli.NOTICE_AFTER, 0.5 s; these two take milliseconds, so at
    once here: tests/test_compile_notice.py has the delay.)"""
    import numba

    def stub(compile_kernels):
        def stability(*args, **kwargs):
            if compile_kernels:  # two fresh kernels, no cache: numba compiles both
                numba.njit(lambda x: x + 1)(1.0)
                numba.njit(lambda x: x * 2)(1.0)
            raise ScenarioError("stub")
        return stability

    monkeypatch.setitem(cli._compile_notice, "printed", False)
    monkeypatch.setattr(cli, "NOTICE_AFTER", 0.0)
    runner = CliRunner()
    monkeypatch.setattr(analysis, "stability", stub(False))
    quiet = runner.invoke(app, ["stability", "-o", str(tmp_path)])
    assert quiet.exit_code == 2 and "compiling" not in quiet.output
    monkeypatch.setattr(analysis, "stability", stub(True))
    loud = runner.invoke(app, ["stability", "-o", str(tmp_path)])
    assert loud.exit_code == 2
    assert loud.output == "compiling kernels (first run only)...\nrailwear: error: stub\n"
