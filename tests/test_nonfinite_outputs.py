"""No NaN or inf in a written file, and no exit 0 over a broken state (issue 19, item 2).

An undefined statistic is written masked (``_FillValue``) with an ``undefined_because``
attribute; a Fourier solution that overflows stops the run with exit 1 and the last good state.
"""

import json
import re

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import NumericalInstabilityError
from railwear.longterm.fourier import Fourier
from railwear.longterm.spectra import UNDEFINED


def assert_finite_file(path):
    """Every float variable of the netCDF file ``path``, read raw (``decode_cf=False``), is finite
    wherever it is not its ``_FillValue``; a variable with filled entries says why (``UNDEFINED``)."""
    with xr.open_dataset(path, engine="h5netcdf", decode_cf=False) as ds:
        for name, var in ds.variables.items():
            if var.dtype.kind != "f":
                continue
            values = np.asarray(var.values)
            filled = values == var.attrs["_FillValue"] if "_FillValue" in var.attrs else np.zeros(values.shape, bool)
            bad = ~np.isfinite(values) & ~filled
            assert not bad.any(), f"{path.name}: {name} has {int(bad.sum())} values that are not finite"
            if filled.any():
                assert var.attrs.get(UNDEFINED), f"{path.name}: {name} is masked without saying why"


def assert_strict_summary(directory):
    """``summary.json`` is strict JSON (no NaN or Infinity) and ``summary.txt`` prints no nan or inf."""
    def refuse(constant):
        raise AssertionError(f"summary.json holds {constant}")

    json.loads((directory / "summary.json").read_text(), parse_constant=refuse)
    text = (directory / "summary.txt").read_text()
    assert not re.search(r"\b(nan|inf)\b", text, flags=re.I), text


def invoke(args, out):
    """Run the command in process; its exit status is 0, 1 with the last good state, or 2."""
    result = CliRunner().invoke(app, args)
    assert result.exit_code in (0, 1, 2), result.output
    if result.exit_code == 1 and args[0] == "run":
        assert (out / "last_good_state.npy").is_file()
    return result


def run(tmp_path, scenario, *sets):
    out = tmp_path / "out"
    args = ["run", scenario, "-o", str(out), "--no-figures"]
    for s in sets:
        args += ["--set", s]
    return invoke(args, out), out


@pytest.mark.parametrize("scenario, sets, masked", [
    ("linear-dynamics", (), {"growth_rate": "N/2", "roughness_level": "zero at the end"}),
    ("linear-dynamics", ("solver.t_end=1e-300",), {"growth_rate": "too short", "out_of_round_growth_factor": "too short"}),
    ("linear-dynamics", ("initial.rms_um=1e-300",), {"out_of_round_growth_rate": "round", "roughness_level": "-inf"}),
    ("linear-dynamics", ("body.primary_damping_N_s_m=1e-300", "body.pad_damping_N_s_m=1e-300"), {}),
    ("linear-dynamics", ("initial.seed=4611686018427387904",), {}),
    ("linear-dynamics", ("solver.points=256", "solver.n_save=3", "solver.t_end=0.5"), {}),
    ("onset", ("solver.points=64", "solver.t_end=1e-300"), {"growth_rate": "too short"}),
    ("onset", ("solver.points=64", "solver.t_end=0.01", "initial.rms_um=1e-300"), {"growth_rate": "zero at a saved"}),
])
def test_an_undefined_statistic_is_masked_and_says_why(tmp_path, scenario, sets, masked):
    result, out = run(tmp_path, scenario, *sets)
    assert result.exit_code == 0, result.output
    assert_finite_file(out / "result.nc")
    assert_strict_summary(out)
    ds = xr.open_dataset(out / "result.nc", engine="h5netcdf")
    for name, words in masked.items():
        assert np.isnan(ds[name].values).any() and words in ds[name].attrs[UNDEFINED], (name, ds[name].attrs)


# report.html's growth per 10 000 km (railwear/report.py) overflows at these rates, with a warning
@pytest.mark.filterwarnings("ignore:overflow encountered in expm1:RuntimeWarning")
def test_a_narrow_wear_band_stops_at_the_depth_limit_with_a_finite_state(tmp_path):
    """A band of 1e-9 mm makes every rate 1e9 times faster: the first saved state after the start
    has overflowed, but the depth limit lies before it and the bisection finds it."""
    result, out = run(tmp_path, "linear-dynamics", "wear.band_width_mm=1e-9")
    assert result.exit_code == 0, result.output
    assert_finite_file(out / "result.nc")
    assert_strict_summary(out)
    ds = xr.open_dataset(out / "result.nc", engine="h5netcdf")
    assert float(ds.removed_depth[-1]) == pytest.approx(1e-3, rel=1e-6)


def test_a_fourier_forecast_that_overflows_fails(tmp_path):
    """The forecast runs to its horizon without a depth limit: the overflow is exit 1, nothing written."""
    wheel = tmp_path / "wheel.csv"
    angle = np.arange(0, 360, 5.0)
    wheel.write_text("angle_deg,deviation_um\n" + "".join(
        f"{a:g},{30 * np.cos(np.radians(11 * a)):.6g}\n" for a in angle))
    out = tmp_path / "forecast"
    result = invoke(["forecast", str(wheel), "--scenario", "linear-dynamics", "--samples", "2", "-o", str(out),
                     "--set", "wear.band_width_mm=1e-9"], out)
    assert result.exit_code == 1 and "not finite" in result.output
    assert not (out / "forecast.nc").exists()


def test_an_overflow_without_a_limit_keeps_the_last_good_state():
    """λ = 100 1/s: exp(λ t) overflows past t = 7.1 s, so the state saved at 7 s is the last good one."""
    fourier = Fourier(lambda w: np.full(np.shape(w), -100.0 + 0j), 1.0, 1.0, 1.0, 0.0, 1.0)
    u0 = 1e-5 * np.cos(3 * 2 * np.pi * np.arange(16) / 16)
    with pytest.raises(NumericalInstabilityError, match="overflowed") as caught:
        fourier.run(u0, 10.0, n_save=11)
    assert caught.value.last_time == pytest.approx(7.0)
    assert np.all(np.isfinite(caught.value.last_good)) and np.ptp(caught.value.last_good) > 1e200
    fast = Fourier(lambda w: np.full(np.shape(w), -1e3 + 0j), 1.0, 1.0, 1.0, 0.0, 1.0)
    ds = fast.run(u0, 10.0, n_save=11, peak_to_peak_limit=1e-3)  # overflowed at the first saved time
    assert np.all(np.isfinite(ds.u.values)) and np.ptp(ds.u.values[-1]) == pytest.approx(1e-3, rel=1e-9)


@pytest.mark.parametrize("deviation_um, limit", [(0.0, "0.3mm"), (12.0, "20dB"), (0.0, "iso3095")])
def test_a_round_measured_wheel_forecasts_finite(tmp_path, deviation_um, limit):
    """A perfectly round wheel, and a constant file (round about another radius): no level anywhere."""
    wheel = tmp_path / "round.csv"
    wheel.write_text("angle_deg,deviation_um\n" + "".join(f"{a:g},{deviation_um:g}\n" for a in range(0, 360, 5)))
    out = tmp_path / "forecast"
    result = invoke(["forecast", str(wheel), "--scenario", "linear-dynamics", "--samples", "2", "--limit", limit,
                     "-o", str(out)], out)
    assert result.exit_code == 0, result.output
    assert_finite_file(out / "forecast.nc")
    text = (out / "forecast.txt").read_text()
    assert not re.search(r"\b(nan|inf)\b", text, flags=re.I), text
    ds = xr.open_dataset(out / "forecast.nc", engine="h5netcdf")
    assert "no out-of-round" in ds.excess.attrs[UNDEFINED] and np.all(np.isnan(ds.excess.values))
    assert "not reached" in ds.crossing_distance.attrs[UNDEFINED]
