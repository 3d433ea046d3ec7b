"""The forecast on the wheel over the track runs the scenario's own Fourier technique per sample."""

import warnings

import numpy as np
import pytest

import railwear
from railwear import forecast
from railwear.geometry import roundness
from railwear.scenario import load_scenario


def test_forecast_of_the_metro_case_is_its_fourier_run():
    """Without scatter every sample is the scenario's own run: the crossing of 0.1 mm peak to peak
    equals where the Fourier run with that limit stops (1 % asserted: the forecast interpolates
    between 201 saved distances), and the order at the crossing is the run's 8; with the built-in
    scatter (5 km/h, 10 % load, friction 0.3-0.45) the median lies within 25 % of it."""
    sc = load_scenario("metro")
    angle = roundness.grid_angles(360)
    deviation = 20e-6 * np.cos(angle) + 3e-6 * np.cos(8 * angle + 1.0)
    still = sc.model_copy(update={"service": sc.service.model_copy(update={
        "speed_scatter_kmh": 0.0, "load_scatter": 0.0, "friction_range": None, "samples": 2})})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", forecast.NoScatterWarning)
        ds = forecast.forecast(still, angle, deviation, 1e-4)
    u0 = roundness.resample_measured(angle, deviation, sc.solver.points)
    run = railwear.scenario.build.strategy(sc).run(u0, until=sc.solver.t_end)
    expected = float(run.distance[-1])
    assert float(ds.crossing_distance[0]) == pytest.approx(expected, rel=0.01)
    assert int(ds.dominant_order[0]) == 8
    scattered = forecast.forecast(sc, angle, deviation, 1e-4)
    assert scattered.attrs["crossing_median_km"] == pytest.approx(expected, rel=0.25)
    assert np.ptp(scattered.crossing_distance.values[np.isfinite(scattered.crossing_distance.values)]) > 0
    from railwear import plots

    ax = plots.forecast(scattered).axes[0]
    low, high = ax.get_ylim()
    assert ax.get_yscale() == "log" and low < 100.0 < high <= plots.FORECAST_SPAN * 100.0 * 1.01
