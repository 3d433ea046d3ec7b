"""The stability map draws the run's speed and the order the P2 resonance excites, n = f π D / V,
and a map of the evolution equation per 10 000 km (issue 22, item 5)."""

import numpy as np
import pytest
import xarray as xr

from railwear import plots
from railwear.cli import _map_marks
from railwear.scenario import load_scenario


def test_the_marks_of_the_metro_scenario():
    marks = _map_marks(load_scenario("metro"))
    assert marks["run_speed_kmh"] == 70.0 and marks["wheel_diameter_m"] == 0.84
    assert marks["p2_frequency_hz"] == pytest.approx(55.75, abs=0.01)  # docs/track.md
    assert marks["life_distance_km"] == 100000.0
    assert "p2_frequency_hz" not in _map_marks(load_scenario("onset"))  # a disk wheel on a rigid rail


def _map(units, **attrs):
    speed = np.linspace(30, 120, 10) / 3.6
    order = np.arange(1, 31)
    rate = np.outer(np.ones(speed.size), np.linspace(-1, 1, order.size))
    return xr.Dataset({"growth_rate": (("speed", "order"), rate, {"units": units, "long_name": "growth rate"})},
                      coords={"speed": ("speed", speed, {"units": "m s-1"}), "order": order}, attrs=attrs)


def test_the_run_and_the_p2_order_are_drawn():
    fig = plots.stability(_map("km-1", run_speed_kmh=70.0, wheel_diameter_m=0.84, p2_frequency_hz=55.75))
    ax = fig.axes[0]
    labels = [t.get_text() for t in ax.get_legend().get_texts()]
    assert labels == ["the run: 70 km/h", "n = f π D / V, P2 55.8 Hz"]
    run, p2 = ax.get_lines()
    assert list(run.get_xdata()) == [70.0, 70.0]
    at = np.argmin(np.abs(p2.get_xdata() - 70.0))
    assert p2.get_ydata()[at] == pytest.approx(55.75 * np.pi * 0.84 / (70 / 3.6), rel=0.01)  # 7.6: order 8 grows


def test_the_wheelset_modes_of_the_high_speed_case_are_drawn():
    marks = _map_marks(load_scenario("high-speed"))
    assert marks["wheel_mode_frequencies_hz"] == [590.0] and marks["wheel_diameter_m"] == 0.92
    fast = _map("km-1", wheel_diameter_m=0.92, p2_frequency_hz=40.0, wheel_mode_frequencies_hz=[590.0])
    fast = fast.assign_coords(speed=fast.speed * 3)  # 90-360 km/h, where the mode passes orders 17-68
    ax = plots.stability(fast).axes[0]
    assert [t.get_text() for t in ax.get_legend().get_texts()][-1] == "wheelset mode 590 Hz"
    mode = ax.get_lines()[-1]
    assert mode.get_ydata().max() <= 30.5 and mode.get_xdata().min() > 190  # clipped to the map's orders
    at = np.argmin(np.abs(mode.get_xdata() - 300.0))
    assert mode.get_ydata()[at] == pytest.approx(590.0 * np.pi * 0.92 / (mode.get_xdata()[at] / 3.6), rel=1e-12)


def test_a_map_per_unit_normed_time_is_drawn_per_10000_km():
    fig = plots.stability(_map("1", life_distance_km=50000.0))
    colour_bar = fig.axes[1]
    assert colour_bar.get_ylabel() == "growth per 10 000 km (ln of amplitude ratio)"
    assert colour_bar.get_ylim() == pytest.approx((-0.2, 0.2))


def test_without_marks_nothing_is_drawn():
    fig = plots.stability(_map("km-1"))
    assert fig.axes[0].get_legend() is None and not fig.axes[0].get_lines()
