"""A forecast is a run like the others (issue 19). Its work is bounded: one that would take hours
(the built-in 'forecast' on a wheel of the least radius, 0.05 m, had not finished after 600 s) or
more memory than a run may save is refused before it runs, in one line naming the field and the
bound, with the longest horizon or the most samples within it. One that fails keeps its last good
state, as 'railwear run' does."""

import re

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear.cli import app
from railwear.errors import ScenarioError
from railwear.forecast import MAX_FORECAST_WORK, forecast_file
from railwear.longterm.phenomenological import Phenomenological
from railwear.scenario import load_scenario


class Ran(Exception):
    """The forecast was accepted and started its run."""


@pytest.fixture
def no_run(monkeypatch):
    """A forecast that passes its checks raises :class:`Ran` instead of running."""
    def run(self, *args, **kwargs):
        raise Ran(len(self.speed))
    monkeypatch.setattr(Phenomenological, "run", run)


@pytest.fixture
def wheel(tmp_path):
    path = tmp_path / "wheel.csv"
    angle = np.arange(0, 360, 5.0)
    path.write_text("angle_deg,deviation_um\n" + "".join(
        f"{a:g},{30 * np.cos(np.radians(11 * a)):.6g}\n" for a in angle))
    return path


def failed(status, *args):
    """Exit ``status`` with one line ``railwear: error: ...`` (warnings aside); returns the line."""
    result = CliRunner().invoke(app, ["forecast", *map(str, args)])
    lines = [line for line in result.stderr.splitlines() if not line.startswith("railwear: warning:")]
    assert result.exit_code == status, (result.output, result.exception)
    assert len(lines) == 1 and lines[0].startswith("railwear: error: "), result.stderr
    return lines[0]


def refused(*args):
    """Exit 2, one line, and nothing written; returns the line."""
    line = failed(2, *args)
    out = args[args.index("-o") + 1]
    assert not out.exists() or not any(out.iterdir()), list(out.iterdir())
    return line


def test_a_stiff_wheel_is_refused_naming_the_horizon_and_the_bound(wheel, tmp_path, no_run):
    line = refused(wheel, "--scenario", "forecast", "--set", "wheel.radius_m=0.05", "-o", tmp_path / "out")
    assert line.startswith("railwear: error: solver.t_end: 1 (50,000 km) is too far to forecast"), line
    assert "MAX_FORECAST_WORK = 2e+09" in line and "e-fold every 10 m" in line, line
    most = float(re.search(r"at most [\d.]+ \(([\d,.]+) km; --horizon-km\)", line).group(1).replace(",", ""))
    assert 0 < most < 50000
    with pytest.raises(Ran):  # the longest horizon it names is within the bound
        forecast_file(wheel, load_scenario("forecast", ["wheel.radius_m=0.05"]), horizon_km=most)
    with pytest.raises(ScenarioError, match=r"^horizon_km: [\d,]+ km is too far to forecast: .* at most [\d,]+ km"):
        forecast_file(wheel, load_scenario("forecast", ["wheel.radius_m=0.05"]), horizon_km=2 * most)


def test_the_built_in_forecast_is_within_the_bound(wheel, no_run):
    with pytest.raises(Ran):
        forecast_file(wheel, "forecast")


def test_the_work_bound_counts_steps_times_points(wheel, monkeypatch, no_run):
    """Half the bound refuses what the bound accepts: the check is the estimate against the bound."""
    with pytest.raises(Ran):
        forecast_file(wheel, load_scenario("forecast", ["wheel.radius_m=0.3"]))
    monkeypatch.setattr("railwear.forecast.MAX_FORECAST_WORK", MAX_FORECAST_WORK // 4)
    with pytest.raises(ScenarioError, match=r"^solver.t_end: .* more than MAX_FORECAST_WORK = 5e\+08"):
        forecast_file(wheel, load_scenario("forecast", ["wheel.radius_m=0.3"]))


def test_more_samples_than_a_run_may_save_are_refused_naming_the_most(wheel, tmp_path, no_run):
    """201 saved times of 1024 points: 97 samples are 2.0e7 values (MAX_SAVED_VALUES), 98 more."""
    line = refused(wheel, "--scenario", "forecast", "--samples", "98", "-o", tmp_path / "out")
    assert "service.samples: 98 samples" in line and "at most 97 samples at 1024 points" in line, line
    with pytest.raises(Ran, match="97"):
        forecast_file(wheel, "forecast", samples=97)


def test_a_forecast_that_fails_keeps_its_last_good_state(wheel, tmp_path):
    """As 'railwear run' does: exit 1, one line saying why and where the last good state is."""
    out = tmp_path / "forecast"
    line = failed(1, wheel, "--scenario", "linear-dynamics", "--samples", "2", "-o", out,
                  "--set", "wear.band_width_mm=1e-9")
    assert "not finite" in line and "last_good_state.npy" in line, line
    kept = np.load(out / "last_good_state.npy")
    assert kept.shape[-1] == 64 and np.all(np.isfinite(kept)) and np.ptp(kept) > 0  # linear-dynamics' points
    assert not (out / "forecast.nc").exists()
