"""The dynamic wheel load of a bogie (railwear.maintenance.impact with several wheels on the rail,
``[body] wheel_positions_m``): far-apart wheels are the single wheel and the round wheel, the
ring must hold the wheels, and ``railwear load`` runs a bogie the way a user runs it."""

import subprocess
import sys

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.longterm.vehicle_track import METRO
from railwear.maintenance import impact
from railwear.maintenance.impact import DynamicLoad, dynamic_load
from railwear.results import read_netcdf
from railwear.scenario import load_scenario

X = 2 * np.pi * np.arange(256) / 256
SPEED = (70 / 3.6,)


def test_wheels_far_apart_load_the_rail_as_one_wheel_and_a_round_one():
    """50 um of order 8 at 70 km/h with a round wheel half a 96-bay ring (28.8 m) behind: the
    shaped wheel's peak and least force are the single wheel's within 3e-4 of the static load
    (measured 6e-5 and 3e-5; its peak is 0.24 W above the static load), and the round wheel's
    peak the single round wheel's within 3e-4 (measured 2e-5)."""
    u = 50e-6 * np.cos(8 * X)
    one = dynamic_load(DynamicLoad(METRO, u, SPEED, ring_sleepers=96, revolutions=2, transient=0.3))
    two = dynamic_load(DynamicLoad(METRO, u, SPEED, ring_sleepers=96, revolutions=2, transient=0.3,
                                   wheel_positions=(0.0, 28.8)))
    W = float(one.static_load)
    assert float(one.peak_force[0]) > 1.2 * W  # the shape loads the rail
    assert abs(float(two.peak_force[0] - one.peak_force[0])) < 3e-4 * W
    assert abs(float(two.minimum_force[0] - one.minimum_force[0])) < 3e-4 * W
    assert float(two.wheel_peak_force[0, 0]) == float(two.peak_force[0])
    assert abs(float(two.wheel_peak_force[0, 1] - one.round_peak_force[0])) < 3e-4 * W
    assert "wheel_peak_force" not in one and list(two.wheel_position.values) == [0.0, 28.8]


def test_refusals_name_the_field():
    u = 10e-6 * np.cos(8 * X)
    with pytest.raises(ScenarioError, match="^ring_sleepers: a ring of 32 bays"):
        DynamicLoad(METRO, u, SPEED, wheel_positions=(0.0, 2.5, 15.0, 17.5))
    with pytest.raises(ScenarioError, match="^wheel_positions: "):
        DynamicLoad(METRO, u, SPEED, wheel_positions=(1.0, 2.5))
    with pytest.raises(ScenarioError, match="^track.ring_sleepers: "):
        impact.wheel_load(load_scenario("metro", {"body.wheel_positions_m": [0.0, 2.5, 15.0, 17.5]}), (70.0,),
                          revolutions=1, transient=0.0)


@pytest.mark.e2e
def test_railwear_load_of_a_bogie_in_a_fresh_interpreter(tmp_path):
    """``railwear load metro --set body.wheel_positions_m=[0,2.5]`` writes the peak at each wheel;
    a car on the default ring exits 2 with one line naming track.ring_sleepers."""
    out = tmp_path / "out"
    run = subprocess.run([sys.executable, "-m", "railwear", "load", "metro", "--set", "body.wheel_positions_m=[0,2.5]",
                          "--speeds", "70", "--revolutions", "2", "--transient-s", "0.3", "-o", str(out)],
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "wheels on the rail at 0, 2.5 m, the shaped wheel first, the others round" in run.stdout
    ds = read_netcdf(out / "load.nc")
    assert ds.wheel_peak_force.dims == ("speed", "wheel") and ds.wheel_peak_force.attrs["units"] == "N"
    assert float(ds.wheel_peak_force[0, 0]) > float(ds.wheel_peak_force[0, 1]) > 0.98 * float(ds.static_load)
    car = subprocess.run([sys.executable, "-m", "railwear", "load", "metro", "--set",
                          "body.wheel_positions_m=[0,2.5,15,17.5]", "--speeds", "70", "-o", str(tmp_path / "car")],
                         capture_output=True, text=True, timeout=300)
    assert car.returncode == 2 and car.stderr.count("\n") == 1, car.stderr
    assert car.stderr.startswith("railwear: error: track.ring_sleepers: a ring of 32 bays"), car.stderr
