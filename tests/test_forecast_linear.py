"""The forecast's samples on a linear strategy: their states without each sample's result Dataset."""

import numpy as np
import pytest

from railwear import forecast
from railwear.errors import NumericalInstabilityError
from railwear.scenario import build, load_scenario

N = 512


def wheel():
    x = 2 * np.pi * np.arange(N) / N
    return 20e-6 * np.cos(8 * x + 0.3) + 5e-6 * np.cos(3 * x)


def samples(scenario, speeds_kmh):
    return [scenario.model_copy(update={
        "operation": scenario.operation.model_copy(update={"speed_kmh": float(v), "speed_m_s": None}),
        "solver": scenario.solver.model_copy(update={"n_save": 21, "peak_to_peak_limit_mm": None})})
        for v in speeds_kmh]


@pytest.mark.parametrize("changes", [{}, {"strategy.kind": "multiplier"}])
def test_the_states_are_the_runs_bit_for_bit(changes):
    """Each sample's states (Fourier technique: its exact solution without the Dataset; the
    multiplier: its run) equal the sample's full run, every saved time and value, and the batch
    takes the first run's times."""
    u0 = wheel()
    runs = samples(load_scenario("metro", changes), [40.0, 63.0, 95.0])
    ds = forecast._linear_runs(runs, u0, 0.5)
    for k, sample in enumerate(runs):
        full = build.strategy(sample).run(u0, until=0.5).u.transpose("time", "angle")
        assert np.array_equal(ds.u.values[k], full.values)
        if k == 0:
            assert np.array_equal(ds.time.values, full.time.values)
            assert np.array_equal(ds.angle.values, full.angle.values)


def test_a_state_that_is_not_finite_is_reported_by_the_run():
    """A harmonic that overflows is the run's NumericalInstabilityError, in normed time."""
    sc = load_scenario("metro", {"operation.life_distance_km": 1e8})
    with pytest.raises(NumericalInstabilityError, match="not finite") as e:
        forecast._linear_runs(samples(sc, [70.0]), wheel(), 1.0)
    assert 0 <= e.value.last_time < 1.0
