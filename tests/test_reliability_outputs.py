"""What the commands write when a statistic is undefined or a run failed (issue 19, the items left):
the report says 'undefined' as the summary does, and a sweep whose every point failed is a failed
run to 'railwear plot' too (a failed forecast: tests/test_reliability_forecast.py)."""

import re
import warnings

import pytest
from typer.testing import CliRunner

from railwear import results, sweep
from railwear.cli import app

NAN_OR_INF = re.compile(r"\b(nan|inf|infinity)\b", flags=re.I)


def invoke(*args):
    return CliRunner().invoke(app, [str(a) for a in args])


def one_line_error(result):
    """The one ``railwear: error:`` line of a failed command (its warnings aside)."""
    lines = [line for line in result.stderr.splitlines() if line.startswith("railwear: error: ")]
    assert len(lines) == 1 and "Traceback" not in result.output, result.stderr
    return lines[0]


@pytest.mark.parametrize("sets, undefined", [
    (("solver.t_end=1e-300",), "growth_rate"),  # too short a run to fit any rate
    (("initial.rms_um=1e-300",), "out_of_round_growth_rate"),  # round: no out-of-round to grow
    (("wear.band_width_mm=1e-9",), "growth per 10 000 km"),  # rates so fast that the growth overflows
])
def test_the_report_says_undefined_where_the_summary_does(tmp_path, sets, undefined):
    args = ["run", "linear-dynamics", "-o", tmp_path, "--no-figures"]
    for s in sets:
        args += ["--set", s]
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)  # the report's growth computed without overflow
        result = invoke(*args)
    assert result.exit_code == 0, result.output
    html = (tmp_path / "report.html").read_text()
    assert "undefined" in html and not NAN_OR_INF.search(html), NAN_OR_INF.findall(html)
    assert "undefined" in (tmp_path / "summary.txt").read_text()
    if undefined != "growth per 10 000 km":
        assert undefined in results.read_netcdf(tmp_path / "result.nc")


def test_plot_of_a_sweep_whose_every_point_failed_is_a_failed_run(tmp_path, monkeypatch):
    """The file is railwear's own record of a failed sweep, not bad input: exit 1, as the sweep
    itself, with one line saying every point failed and the first point's error; no figure."""
    monkeypatch.setattr(sweep, "LocalExecutor", lambda workers=None: sweep.SerialExecutor())
    swept = invoke("sweep", "onset", "--vary", "wheel.radius_m=3,4", "-o", tmp_path,
                   "--set", "solver.points=64", "--set", "solver.n_save=11", "--set", "solver.t_end=0.05")
    assert swept.exit_code == 1, swept.output
    drawn = invoke("plot", tmp_path / "sweep.nc")
    assert drawn.exit_code == 1, drawn.output
    line = one_line_error(drawn)
    assert "every point failed" in line and "wheel.radius_m" in line and "nothing to draw" in line, line
    assert not list(tmp_path.glob("sweep.*g"))
