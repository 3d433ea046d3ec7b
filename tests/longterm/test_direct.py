"""Strategy 1, direct coupled integration: convergence in the acceleration factor, agreement with
the stepwise strategy, resume, input checks."""

import numpy as np
import pytest
from helpers import Killed, killed_after

from railwear.errors import ScenarioError
from railwear.wear import EnergyLaw
from railwear.longterm.direct import Direct
from railwear.longterm.disk_wheel import DiskWheel, ServiceSpeeds
from railwear.longterm.stepwise import Stepwise

BETA = 5.3e-9 / 7850.0  # m³/J, the energy law of EnergyLaw(5.3e-9, 7850)
WEAR = {"law": EnergyLaw(5.3e-9, 7850.0), "band_width": 0.01, "life_distance": 5e7}


def shape_error(u, ref):
    d, r = u - u.mean(), ref - ref.mean()
    return float(np.sqrt(np.mean((d - r) ** 2) / np.mean(r**2)))


@pytest.fixture(scope="module")
def runs(wheel_220, rough_u0):
    return {a: Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=a).run(rough_u0, until=1.0, depth_limit=40e-6)
            for a in (2e4, 1e4, 5e3, 2.5e3)}


def test_converges_as_the_acceleration_factor_falls(runs):
    ref = runs[2.5e3]
    stops = [abs(float(runs[a].stop_time - ref.stop_time)) for a in (2e4, 1e4, 5e3)]
    errors = [shape_error(runs[a].u.values[-1], ref.u.values[-1]) for a in (2e4, 1e4, 5e3)]
    # first order in A: the distance to the 40 um depth halves with A
    assert stops[0] > 1.6 * stops[1] > 1.6**2 * stops[2] > 0
    assert errors[0] > errors[1] > errors[2] > 0
    assert errors[-1] < 2e-3
    for ds in runs.values():
        assert float(ds.removed_depth[-1]) == pytest.approx(40e-6, rel=1e-9)


def test_agrees_with_the_stepwise_strategy(runs, wheel_220, rough_u0):
    frozen = DiskWheel(wheel_220, **WEAR, service=ServiceSpeeds((wheel_220.speed,)), revolutions=4,
                            transient_revolutions=4, samples=2)
    step = Stepwise(frozen, 2e-6).run(rough_u0, until=1.0, depth_limit=40e-6)
    ref = runs[2.5e3]
    assert shape_error(step.u.values[-1], ref.u.values[-1]) < 3e-3
    assert float(step.stop_time) == pytest.approx(float(ref.stop_time), rel=3e-3)


def test_finer_surface_updates_converge_too(wheel_220, rough_u0):
    """Four surface updates per revolution: also first order in A, towards the same limit."""
    fine = {a: Direct(DiskWheel(wheel_220, **WEAR, updates_per_revolution=4), acceleration_factor=a).run(
        rough_u0, until=1.0, depth_limit=20e-6) for a in (1e4, 5e3)}
    coarse = Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=2.5e3).run(rough_u0, until=1.0, depth_limit=20e-6)
    errors = [shape_error(fine[a].u.values[-1], coarse.u.values[-1]) for a in (1e4, 5e3)]
    assert errors[0] > 1.5 * errors[1]


def test_a_killed_run_resumes_bit_for_bit(wheel_220, rough_u0, runs):
    strategy = Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=2e4, n_save=11)
    whole = strategy.run(rough_u0, until=1.0, depth_limit=40e-6)
    saved = []

    with pytest.raises(Killed):
        strategy.run(rough_u0, until=1.0, depth_limit=40e-6, checkpoint=killed_after(3, saved))
    resumed = strategy.run(rough_u0, until=1.0, depth_limit=40e-6, resume=saved[-1])
    np.testing.assert_array_equal(resumed.u.values, whole.u.values)
    np.testing.assert_array_equal(resumed.time.values, whole.time.values)


@pytest.mark.parametrize("factor", [0.5, 0.0, -3.0, float("nan")])
def test_an_acceleration_factor_below_one_is_an_error(wheel_220, factor):
    with pytest.raises(ScenarioError, match="acceleration factor"):
        Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=factor)


def test_stops_at_the_normed_time(wheel_220, rough_u0):
    ds = Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=2e4, n_save=5).run(rough_u0, until=0.01)
    assert float(ds.time[-1]) == 0.01
    assert ds.sizes["time"] == 5


def test_checkpoint_survives_an_npz_file(wheel_220, rough_u0, tmp_path):
    from railwear.longterm.base import Checkpoint

    strategy = Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=2e4, n_save=6)
    saved = []
    whole = strategy.run(rough_u0, until=1.0, depth_limit=20e-6, checkpoint=saved.append)
    np.savez(tmp_path / "cp.npz", **saved[2].plain())
    with np.load(tmp_path / "cp.npz") as data:
        back = Checkpoint.from_plain({k: data[k] for k in data.files})
    assert back.kind == "direct"
    resumed = strategy.run(rough_u0, until=1.0, depth_limit=20e-6, resume=back)
    np.testing.assert_array_equal(resumed.u.values, whole.u.values)


def test_the_fastsim_creep_law_is_carried_through_the_surface_updates(wheel_220, rough_u0):
    """With FASTSIM's creep curve in the kernel's surface array, the direct run's updated
    surfaces keep it: direct and stepwise agree as they do for the cubic law."""
    from dataclasses import replace

    wheel = replace(wheel_220, creep_law="fastsim")
    direct = Direct(DiskWheel(wheel, **WEAR), acceleration_factor=5e3).run(rough_u0, until=1.0, depth_limit=20e-6)
    frozen = DiskWheel(wheel, **WEAR, service=ServiceSpeeds((wheel.speed,)), revolutions=4,
                            transient_revolutions=4, samples=2)
    step = Stepwise(frozen, 2e-6).run(rough_u0, until=1.0, depth_limit=20e-6)
    assert shape_error(step.u.values[-1], direct.u.values[-1]) < 3e-3
    cubic = Direct(DiskWheel(wheel_220, **WEAR), acceleration_factor=5e3).run(rough_u0, until=1.0, depth_limit=20e-6)
    # the creep law matters: the life to the depth differs from the cubic law's
    assert abs(float(direct.stop_time) / float(cubic.stop_time) - 1) > 1e-3
