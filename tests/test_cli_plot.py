"""``railwear plot FILE`` draws again every file railwear writes, not only result.nc."""

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from railwear import results
from railwear.cli import app


def _sweep(ran=True):
    """A sweep.nc as ``railwear sweep`` writes it (one field, two points)."""
    radius = np.array([0.4, 0.5])
    return xr.Dataset(
        {"peak_to_peak": ("wheel.radius_m", [2e-5, 3e-5]), "peak_to_peak_initial": ("wheel.radius_m", [1e-5, 1e-5]),
         "maxima": ("wheel.radius_m", [5.0, 6.0]), "dominant_order": ("wheel.radius_m", [5.0, 6.0]),
         "max_removed_depth": ("wheel.radius_m", [1e-3, 1e-3]),
         "regime": ("wheel.radius_m", ["onset", "polygonalising"] if ran else ["failed", "failed"]),
         "error": ("wheel.radius_m", ["", ""] if ran else ["ScenarioError: x", "ScenarioError: y"])},
        coords={"wheel.radius_m": radius}, attrs={"base_scenario": "", "base_scenario_hash": "0" * 64,
                                                  "design": "grid", "seed": 0})


def _forecast():
    distance = np.linspace(0, 1000, 11)
    ptp = np.array([1e-4 + 3e-7 * distance, 1e-4 + 1e-7 * distance])
    return xr.Dataset(
        {"peak_to_peak": (("sample", "distance"), ptp), "crossing_distance": ("sample", [667.0, np.inf]),
         "dominant_order": ("sample", [5, 5]), "u_initial": ("angle", np.zeros(8))},
        coords={"sample": [0, 1], "distance": distance, "angle": np.linspace(0, 2 * np.pi, 8, endpoint=False)},
        attrs={"limit_m": 3e-4, "crossing_median_km": np.inf, "crossing_p05_km": 667.0, "crossing_p95_km": np.inf,
               "fraction_crossed": 0.5, "dominant_order": 5, "horizon_km": 1000.0})


def _dynamics(kind):
    """dynamics.nc of ``railwear simulate`` for each model kind."""
    t = np.linspace(0, 1, 50)
    if kind == "cooperrider":
        return xr.Dataset({"amplitude": ("speed", [0.0, 3e-3])}, coords={"speed": [60.0, 70.0]},
                          attrs={"hopf_speed": 65.0, "nonlinear_critical_speed": 62.0})
    if kind == "wheelset":
        return xr.Dataset({"lateral_displacement": (("speed", "time"), [1e-3 * np.sin(9 * t)])},
                          coords={"time": t, "speed": [30.0]}, attrs={"linear_critical_speed_kmh": 120.0})
    return xr.Dataset({"contact_angle": (("speed", "time"), [60 * t]), "frictional_power": (("speed", "time"), [t])},
                      coords={"time": t, "speed": [30.0]})


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    out = tmp_path_factory.mktemp("written")
    runner = CliRunner()
    assert runner.invoke(app, ["stability", "onset", "--speeds", "100,200", "--orders", "1:5:1", "-o", str(out)]).exit_code == 0
    assert runner.invoke(app, ["hunting-map", "--conicity", "0.1,0.2", "--yaw-stiffness", "1e6,2e6",
                               "-o", str(out)]).exit_code == 0
    made = {"stability.nc": "stability.png", "hunting.nc": "hunting.png"}
    for name, ds, figure in [("sweep.nc", _sweep(), "sweep.png"), ("forecast.nc", _forecast(), "forecast.png"),
                             ("bogie.nc", _dynamics("cooperrider"), "bifurcation.png"),
                             ("wheelset.nc", _dynamics("wheelset"), "hunting.png"),
                             ("disk.nc", _dynamics("disk_wheel"), "contact-path.png")]:
        results.write_netcdf(ds, out / name)
        made[name] = figure
    return out, made


@pytest.mark.parametrize("name", ["stability.nc", "hunting.nc", "sweep.nc", "forecast.nc", "bogie.nc",
                                  "wheelset.nc", "disk.nc"])
def test_plot_draws_every_file_again(files, name, tmp_path):
    out, made = files
    result = CliRunner().invoke(app, ["plot", str(out / name), "-o", str(tmp_path)])
    assert result.exit_code == 0, result.output
    assert (tmp_path / made[name]).is_file() and result.output == f"wrote {tmp_path / made[name]}\n"


def test_a_sweep_where_no_point_ran_has_nothing_to_draw(tmp_path):
    results.write_netcdf(_sweep(ran=False), tmp_path / "sweep.nc")
    result = CliRunner().invoke(app, ["plot", str(tmp_path / "sweep.nc")])
    assert result.exit_code == 1 and "no point of the sweep ran" in result.output  # a failed run, not bad input
    assert not (tmp_path / "sweep.png").exists()


def test_a_file_railwear_did_not_write_is_refused(tmp_path):
    results.write_netcdf(xr.Dataset({"x": ("t", [1.0])}), tmp_path / "other.nc")
    result = CliRunner().invoke(app, ["plot", str(tmp_path / "other.nc")])
    assert result.exit_code == 2 and "is not a railwear result" in result.output
