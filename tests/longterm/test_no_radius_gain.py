"""A removed depth is never negative: a wheel that gains radius as a whole is a wear model out of
its range, refused with ``ModelRangeError`` instead of written (issue 12, item 6)."""

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from railwear import api
from railwear.cli import app
from railwear.errors import ModelRangeError, NumericalInstabilityError
from railwear.longterm.spectra import describe
from railwear.scenario import builtin_text


def _result(gain, times=np.linspace(0.0, 1.0, 6), speeds=(20.0, 30.0)):
    """``u`` over (time, speed, angle): a fixed order-3 shape whose mean rises by ``gain(T, v)``."""
    x = 2 * np.pi * np.arange(64) / 64
    shape = 10e-6 * np.cos(3 * x)
    u = np.array([[shape + gain(t, v) for v in speeds] for t in times])
    return xr.Dataset({"u": (("time", "speed", "angle"), u, {"units": "m"})},
                      coords={"time": times, "speed": ("speed", list(speeds), {"units": "m s-1"}), "angle": x})


def test_a_wheel_that_gains_radius_is_refused_naming_when_and_where():
    gain = lambda t, v: 2e-6 * t if v == 30.0 else -1e-6 * t  # noqa: E731  (30 m/s gains, 20 m/s wears)
    with pytest.raises(ModelRangeError, match=r"^removed_depth: the wheel gained radius as a whole "
                                              r"\(speed 30 m s-1\): mean removed depth -0.4 um at T = 0.2") as e:
        describe(_result(gain))
    assert isinstance(e.value, NumericalInstabilityError)  # the command line's exit status 1
    assert e.value.last_time == 0.0 and e.value.last_good.shape == (2, 64)


def test_round_off_is_not_a_gain_and_never_a_negative_depth():
    ds = describe(_result(lambda t, v: 1e-22 * t))  # every point 1e-22 m up: round-off of 10 um
    assert float(ds.removed_depth.min()) == 0.0
    worn = describe(_result(lambda t, v: -3e-6 * t))
    assert worn.removed_depth.isel(time=-1).values == pytest.approx([3e-6, 3e-6])


def _gaining_scenario(tmp_path, c0):
    text = builtin_text("stable").replace('form = "disk_contact"', f'form = "cubic"\nc0 = {c0}')
    text = text.replace("points = 1024", "points = 64")
    path = tmp_path / "gain.toml"
    path.write_text(text)
    return path


def test_a_run_whose_wheel_gains_radius_fails_and_writes_no_result(tmp_path):
    path = _gaining_scenario(tmp_path, 1e-4)  # u_T = +1e-4: radius grows
    with pytest.raises(ModelRangeError, match="gained radius"):
        api.run(str(path))
    out = tmp_path / "out"
    r = CliRunner().invoke(app, ["run", str(path), "-o", str(out), "--no-figures"])
    errors = [line for line in r.output.splitlines() if line.startswith("railwear: error")]
    assert r.exit_code == 1 and "Traceback" not in r.output and len(errors) == 1, r.output
    assert "removed_depth: the wheel gained radius" in errors[0]
    assert not (out / "result.nc").exists() and (out / "last_good_state.npy").exists()
    ds = api.run(str(_gaining_scenario(tmp_path, -1e-4)))  # the same wheel wearing
    assert float(ds.removed_depth.min()) >= 0.0 and float(ds.mean_removed_depth[-1]) > 0.0
