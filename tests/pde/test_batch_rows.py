"""A batch of rows is its rows solved apart: bit for bit, and at no more ETDRK4 steps.

The step control retakes only the rows that fail their Richardson check or their guard, and the
weights are kept per row, so no row's result or cost depends on the others.
"""

import numpy as np
import pytest

import railwear.pde.solver as solver_module
from railwear.geometry import roundness
from railwear.pde import Cubic, DiskContact, solve_evolution

SPEEDS = np.linspace(150.0, 280.0, 6) / 3.6  # m/s


@pytest.fixture
def row_steps(monkeypatch):
    """Counts the passes over an interval (full or half steps, some rows or all) and the ETDRK4
    steps the compiled loop's active rows take."""
    record = {"passes": 0, "steps": 0}
    loop, attempt = solver_module.advance_compiled, solver_module._Loop._attempt

    def counted(*args):
        row_steps, active = args[15], args[18]
        record["steps"] += int(np.sum(row_steps[active]))
        return loop(*args)

    def passed(self, *args):
        record["passes"] += 1
        return attempt(self, *args)

    monkeypatch.setattr(solver_module, "advance_compiled", counted)
    monkeypatch.setattr(solver_module._Loop, "_attempt", passed)
    return record


def assert_rows_equal(batch, singles):
    """Each row of ``batch`` is its single solve: saved states (frozen after the row's stop),
    stop time and last time step, all bit for bit."""
    for i, single in enumerate(singles):
        m = single.sizes["time"]
        assert np.array_equal(batch.u.values[:m, i], single.u.values)
        assert np.all(batch.u.values[m:, i] == single.u.values[-1])
        assert batch.stop_time.values[i] == float(single.stop_time)
        assert batch.time_step.values[i] == float(single.time_step)


@pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")
def test_adaptive_batch_over_speed_is_its_rows_bit_for_bit_at_their_cost(row_steps):
    """The Fig. 11 physics (disk contact, epsilon 1e-4, nu 1e-3) at six speeds on 128 points to
    0.5 mm removed: the rows stop at different times with different steps, and single rows fail
    the step control (at rtol 1e-5: one row in the second interval, one in the last)."""
    u0 = roundness.random_perturbation(128, 40e-6, 2, 16, np.random.default_rng(1))

    def solve(speed):
        return solve_evolution(u0, 1.0, DiskContact(), speed, 1e-4, 1e-3, n_save=21, depth_limit=0.5e-3,
                              rtol=1e-5)

    batch = solve(SPEEDS)
    batch_passes, batch_steps = row_steps["passes"], row_steps["steps"]
    row_steps["steps"] = 0
    singles = [solve(float(v)) for v in SPEEDS]
    assert_rows_equal(batch, singles)
    assert len(set(batch.stop_time.values)) == len(SPEEDS)
    assert len(set(batch.time_step.values)) > 1
    assert batch_passes > 2 * (batch.sizes["time"] - 1)  # some rows took an interval again
    assert batch_steps == row_steps["steps"]  # and no row paid for another's retake


@pytest.mark.parametrize("rtol", [None, 1e-4])
def test_a_row_that_blows_up_halves_its_own_step(rtol):
    """Row 0 (h = u_xx without stabilisation, explicit diffusion) blows up at dt = 0.05 and needs
    three halvings; row 1 (h = 0.01 u_xx + u_xx³) keeps dt = 0.05, as alone. With ``rtol`` the
    first step is the growth bound's, and the control does the rest."""
    x = 2 * np.pi * np.arange(64) / 64
    u0 = 1e-3 * np.cos(3 * x) + 5e-4 * np.sin(5 * x) + 1e-5 * np.cos(20 * x)
    forms = [Cubic(c1=1.0), Cubic(c1=0.01, c3=1.0)]
    options = dict(n_save=3, stabilisation=0.0, dt=0.05 if rtol is None else None, rtol=rtol)
    batch = solve_evolution(u0, 0.5, forms, 0.0, 0.0, **options)
    singles = [solve_evolution(u0, 0.5, f, 0.0, 0.0, **options) for f in forms]
    assert_rows_equal(batch, singles)
    if rtol is None:
        assert list(batch.time_step.values) == [0.05 / 8, 0.05]


@pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")
def test_rows_with_and_without_drift_are_their_single_solves():
    """A drift on one row makes the batch's linear part complex; the row without drift still
    takes the real weights it takes alone."""
    u0 = roundness.random_perturbation(64, 40e-6, 2, 12, np.random.default_rng(2))
    drift = np.array([0.0, 2e-5])
    batch = solve_evolution(u0, 0.2, DiskContact(), SPEEDS[[0, 5]], 1e-4, 1e-3, n_save=5, drift=drift)
    singles = [solve_evolution(u0, 0.2, DiskContact(), v, 1e-4, 1e-3, n_save=5, drift=d)
               for v, d in zip(SPEEDS[[0, 5]], drift)]
    assert_rows_equal(batch, singles)
