"""The compiled loop's kernels for batches: the h table's cubics, the depth bound, the row blocks.

The h table is evaluated from cubics built once per batch (``hermite_pieces``), the rows are
stepped in blocks that stay in cache, and the exact removed depth is taken only where a bound
could reach the limit. None of these may change a result: the table is checked against the cubic
Hermite basis written out, the bound against the grid values, and the batch and the depth stop
against their rows solved apart and against a depth taken at every step, bit for bit.
"""

import numpy as np
import pytest

from railwear.geometry import roundness
from railwear.pde import DiskContact, solve_evolution
from railwear.pde.etdrk4 import BLOWUP, NONFINITE, OK, _BLOCK_ROWS, _change_bound, _row_status, pointwise

SPEEDS = np.linspace(150.0, 280.0, 12) / 3.6  # m/s: more rows than a block, the last one partial


def hermite_reference(x, lo, ds, value, slope):
    """The cubic Hermite interpolant with its basis h00, h10, h01, h11 (and the linear
    continuation with the end slope outside), evaluated point by point in numpy."""
    out = np.empty_like(x)
    top = value.size - 1
    for i, xi in enumerate(x):
        t = (xi - lo) / ds
        if t <= 0:
            out[i] = value[0] + slope[0] * (xi - lo)
        elif t >= top:
            out[i] = value[top] + slope[top] * (xi - (lo + top * ds))
        else:
            j = int(np.floor(t))
            p = t - j
            h00, h10 = 2 * p**3 - 3 * p**2 + 1, p**3 - 2 * p**2 + p
            h01, h11 = -2 * p**3 + 3 * p**2, p**3 - p**2
            out[i] = (h00 * value[j] + h10 * ds * slope[j] + h01 * value[j + 1]
                      + h11 * ds * slope[j + 1])
    return out


def test_table_cubics_are_the_cubic_hermite_interpolant():
    """Two rows with different tables, polynomials and grids, at points inside, outside and on
    the ends: within 1e-13 of the tables' range of the basis written out (round-off of two
    forms of one cubic); a point that is not a number gives one that is not."""
    rng = np.random.default_rng(3)
    n_tab = 257
    lo, ds = np.array([-2.0, 0.5]), np.array([4.0 / (n_tab - 1), 1e-3])
    grids = [lo[b] + ds[b] * np.arange(n_tab) for b in range(2)]
    value = np.array([np.sin(3 * grids[0]), np.exp(-grids[1])])
    slope = np.array([3 * np.cos(3 * grids[0]), -np.exp(-grids[1])])
    poly = np.array([[0.5, -1.0, 0.0], [0.0, 2.0, 0.25]])
    x = np.empty((2, 400))
    for b in range(2):
        span = grids[b][-1] - lo[b]
        x[b] = rng.uniform(lo[b] - 0.2 * span, lo[b] + 1.2 * span, 400)
        x[b, :2] = lo[b], grids[b][-1]
    out = pointwise(x, poly, lo, ds, value, slope)
    for b in range(2):
        ref = hermite_reference(x[b], lo[b], ds[b], value[b], slope[b])
        ref += np.polynomial.polynomial.polyval(x[b], poly[b])
        scale = np.ptp(value[b])
        assert np.max(np.abs(out[b] - ref)) <= 1e-13 * scale
    x[0, 5], x[1, 7] = np.nan, np.inf
    out = pointwise(x, poly, lo, ds, value, slope)
    assert np.isnan(out[0, 5]) and not np.isfinite(out[1, 7])


@pytest.mark.parametrize("n_table", [0, 1, 2])
def test_tables_of_few_points(n_table):
    """No table leaves the polynomial; one point continues linearly from it on both sides; two
    points are one cubic (exact for a straight line)."""
    x = np.array([[-3.0, 0.0, 0.25, 0.5, 9.0]])
    poly = np.array([[1.0, 0.5]])
    ds = np.array([0.5])
    value = (2.0 + 3.0 * np.arange(n_table) * ds[0]).reshape(1, -1)
    slope = np.full((1, n_table), 3.0)
    out = pointwise(x, poly, np.array([0.0]), ds, value, slope)
    expected = 1.0 + 0.5 * x + (2.0 + 3.0 * x if n_table else 0.0)
    assert np.allclose(out, expected, rtol=1e-15, atol=1e-14)


@pytest.mark.parametrize("n", [64, 65])
def test_change_bound_bounds_the_change_on_the_grid(n):
    """For random spectra the bound is at least the largest change of the grid values and at
    most ``sqrt(2) n / 2`` times it; for a change of the mean alone it is that change."""
    rng = np.random.default_rng(n)
    nk = n // 2 + 1
    v = rng.standard_normal((3, nk)) + 1j * rng.standard_normal((3, nk))
    v_new = v + 1e-3 * (rng.standard_normal((3, nk)) + 1j * rng.standard_normal((3, nk)))
    for b in range(3):
        change = np.max(np.abs(np.fft.irfft(v_new[b], n) - np.fft.irfft(v[b], n)))
        bound = _change_bound(v, v_new, b, n)
        assert change <= bound * (1 + 1e-12) and bound <= np.sqrt(2) * n / 2 * change
    mean = v.copy()
    mean[1, 0] += 0.25
    assert _change_bound(v, mean, 1, n) == pytest.approx(0.25 / n, rel=1e-15)


def test_guard_reads_the_bits_as_the_values():
    """The guard's status, from the parts' bits first, is that of its definition (any part not
    finite: NONFINITE; else a mode other than the mean with modulus above the limit: BLOWUP) on
    3000 random rows with NaNs, infinities, a large mean and moduli near the limit."""
    rng = np.random.default_rng(0)

    def status(row, blowup):
        if not np.all(np.isfinite(row.real) & np.isfinite(row.imag)):
            return NONFINITE
        return BLOWUP if np.any(np.abs(row[1:]) > blowup) else OK

    seen = set()
    for _ in range(3000):
        row = (rng.standard_normal(33) + 1j * rng.standard_normal(33)) * rng.choice([1e-3, 1.0, 1e3])
        kind = rng.integers(0, 6)
        if kind == 1:
            row[rng.integers(33)] = complex(np.nan, 0.0)
        elif kind == 2:
            row[rng.integers(33)] = complex(0.0, -np.inf)
        elif kind == 3:
            row[0] = 1e9
        elif kind == 4:
            row[rng.integers(1, 33)] = complex(-2.9, 2.9)  # modulus 4.1: near a limit of 4
        blowup = rng.choice([1.0, 4.0, 1e-6, 1e6])
        expected = status(row, blowup)
        seen.add(expected)
        assert _row_status(row, blowup) == expected
    assert seen == {OK, NONFINITE, BLOWUP}


@pytest.mark.filterwarnings("ignore::railwear.errors.ResolutionWarning")
def test_batch_in_blocks_and_bounded_depth_are_exact():
    """Twelve speeds (blocks of ``_BLOCK_ROWS``) of the disk wheel at a fixed step to 0.2 mm
    removed: every row is its single solve (within 1e-12 of its amplitude: at a fixed step a
    batch and its rows differ at round-off, 1e-15, as they did before the blocks), and the run
    in one interval (the exact depth taken only where the bound reaches the limit) is the run in
    one-step intervals (the exact depth at every step): saved states bit for bit, stop times
    within 1e-12 (a time is the interval's start plus steps)."""
    assert SPEEDS.size > _BLOCK_ROWS and SPEEDS.size % _BLOCK_ROWS
    u0 = roundness.random_perturbation(128, 40e-6, 2, 16, np.random.default_rng(1))

    def solve(speed, n_save=2):
        return solve_evolution(u0, 0.4, DiskContact(), speed, 1e-4, 1e-3, dt=1e-3, n_save=n_save,
                               depth_limit=0.2e-3)

    batch = solve(SPEEDS)
    stop = batch.stop_time.values
    assert np.all(stop < 0.4) and np.ptp(stop) > 0.01  # every row stops, at different times
    for i, speed in enumerate(SPEEDS):
        single = solve(speed)
        scale = np.max(np.abs(single.u.values))
        assert np.max(np.abs(batch.u.values[:, i] - single.u.values)) <= 1e-12 * scale
        assert stop[i] == pytest.approx(float(single.stop_time), rel=1e-12)
    stepwise = solve(SPEEDS, n_save=401)
    assert np.array_equal(stepwise.u.values[-1], batch.u.values[-1])
    assert np.allclose(stepwise.stop_time.values, stop, rtol=1e-12, atol=0)
