"""``railwear fleet`` the way a user runs it: a new interpreter, a tiny fleet of five wheels with one
broken file."""

import subprocess
import sys

import numpy as np
import pytest

from railwear.maintenance.fleet_input import write_synthetic
from railwear.results import read_netcdf


def _run(*args, cwd):
    return subprocess.run([sys.executable, "-m", "railwear", "fleet", *args], cwd=cwd, capture_output=True, text=True,
                          timeout=300)


@pytest.mark.e2e
def test_railwear_fleet_runs_the_readable_wheels_and_names_the_broken_file(tmp_path):
    manifest, _ = write_synthetic(tmp_path / "fleet", 5, np.random.default_rng(11), diameter_range_mm=(805, 815))
    broken = tmp_path / "fleet" / "wheels" / "W0004.csv"
    lines = broken.read_text().splitlines()
    lines[30] = lines[30].split(",")[0] + ",1,5"  # a decimal comma in a comma-separated file: line 31
    broken.write_text("\n".join(lines) + "\n")
    done = _run("metro", str(manifest), "--set", "solver.points=128", "--daily-km", "400", "-o", "out", cwd=tmp_path)
    assert done.returncode == 0, done.stderr
    assert "4 wheels read (4 measured lines), 1 file(s) or row(s) refused" in done.stdout
    assert "wheels/W0004.csv line 31: 3 cells where the header has 2 (a decimal comma? use '.')" in done.stdout
    out = tmp_path / "out"
    for name in ("fleet.nc", "fleet.txt", "wheels.csv", "fleet-actions.png", "fleet-cars.png", "fleet-orders.png"):
        assert (out / name).stat().st_size > 0, name
    ds = read_netcdf(out / "fleet.nc")
    assert list(ds.wheel.values) == ["W0001", "W0002", "W0003", "W0005"]
    assert [str(f) for f in ds.failed.values][0].startswith("wheels/W0004.csv line 31")
    assert ds.attrs["daily_km"] == 400 and ds.dominant_order.dtype == np.int64
    assert not list(out.glob(".*.part"))
