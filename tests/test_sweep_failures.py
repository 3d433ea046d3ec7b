"""A sweep of which every point fails is a failed run (exit 1) with its table; A:B for a Latin hypercube."""

import numpy as np
import pytest
from typer.testing import CliRunner

from railwear import results, sweep
from railwear.cli import app
from railwear.errors import OptionError

SMALL = ["--set", "solver.points=64", "--set", "solver.n_save=11", "--set", "solver.t_end=0.05"]


@pytest.fixture(autouse=True)
def serial(monkeypatch):
    """Points run in this process: no pool of workers to start."""
    monkeypatch.setattr(sweep, "LocalExecutor", lambda workers=None: sweep.SerialExecutor())


def invoke(*args):
    return CliRunner().invoke(app, ["sweep", *args, *SMALL])


def test_a_sweep_whose_every_point_is_refused_writes_its_table_and_exits_1(tmp_path):
    (tmp_path / "sweep.png").write_bytes(b"an earlier sweep's figure")
    r = invoke("onset", "--vary", "wheel.radius_m=3,4", "-o", str(tmp_path))
    assert r.exit_code == 1, r.output
    ds = results.read_netcdf(tmp_path / "sweep.nc")
    assert list(ds.regime.values) == ["failed", "failed"]
    assert all("wheel.radius_m" in str(e) for e in ds.error.values)
    assert "│ 3 " in r.stdout and "│ 4 " in r.stdout and "2 point(s) failed" in r.stdout
    assert r.stderr.count("\n") == 1 and "every point of the sweep failed" in r.stderr
    assert "wheel.radius_m" in r.stderr and "no figure" in r.stderr
    assert not (tmp_path / "sweep.png").exists()
    drawn = CliRunner().invoke(app, ["plot", str(tmp_path / "sweep.nc")])
    assert drawn.exception is None or isinstance(drawn.exception, SystemExit), drawn.exception
    assert drawn.stderr.count("\n") == 1 and "no point of the sweep ran" in drawn.stderr


def test_a_sweep_that_blows_up_at_every_point_exits_1(tmp_path):
    r = invoke("polygonalisation", "--vary", "operation.speed_kmh=250,300", "--set", "solver.nu=0.0",
               "--set", "solver.epsilon=0.0", "-o", str(tmp_path))
    assert r.exit_code == 1, r.output
    assert "IllPosedError" in r.stderr and "2 point(s) failed" in r.stdout
    assert len(list((tmp_path / "points").glob("*.error"))) == 2
    assert list(results.read_netcdf(tmp_path / "sweep.nc").regime.values) == ["failed", "failed"]


def test_a_partly_failed_sweep_still_succeeds(tmp_path):
    r = invoke("onset", "--vary", "wheel.radius_m=0.46,4", "-o", str(tmp_path))
    assert r.exit_code == 0, r.output
    assert "1 point(s) failed" in r.stdout and (tmp_path / "sweep.png").exists()


@pytest.mark.parametrize("vary, match", [
    ("wheel.nothing=1,2", "no such scenario field"),
    ("wheel.radius_m=0.4:0.5:0", "--vary wheel.radius_m: expected"),
    ("wheel.radius_m=0.5:0.4", "--vary wheel.radius_m: expected"),
])
def test_bad_input_that_is_not_about_the_points_stays_exit_2(tmp_path, vary, match):
    for design in ([], ["--samples", "2"]):
        r = invoke("onset", "--vary", vary, *design, "-o", str(tmp_path))
        assert r.exit_code == 2 and match in r.stderr and r.stderr.count("\n") == 1, r.output
        assert not (tmp_path / "sweep.nc").exists()


def test_a_range_without_step_is_a_latin_hypercube_range_only(tmp_path):
    v = sweep.parse_vary("wheel.static_load_kN=60:100")
    assert (v.low, v.high) == (60.0, 100.0)
    coords, points = sweep.design([v], samples=4, seed=1)
    # one sample in each quarter of [60, 100]
    assert np.all(np.floor((np.sort(coords["wheel.static_load_kN"]) - 60) / 10) == np.arange(4))
    with pytest.raises(OptionError, match="--vary wheel.static_load_kN: .*--samples"):
        sweep.design([v])
    r = invoke("onset", "--vary", "wheel.static_load_kN=60:100", "-o", str(tmp_path))
    assert r.exit_code == 2 and r.stderr.count("\n") == 1, r.output
    assert "--vary wheel.static_load_kN" in r.stderr and "--samples" in r.stderr
    r = invoke("onset", "--vary", "wheel.radius_m=3:4", "--samples", "2", "-o", str(tmp_path))
    assert r.exit_code == 1, r.output  # the design was accepted; every point is out of bounds
    radius = results.read_netcdf(tmp_path / "sweep.nc")["wheel.radius_m"].values
    assert radius.shape == (2,) and np.all((3 <= radius) & (radius <= 4))
