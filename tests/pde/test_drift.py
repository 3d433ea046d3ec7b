"""The drift term ``drift u_x`` of h, taken exactly in the linear part of ETDRK4."""

import numpy as np
import pytest

from railwear.errors import ScenarioError
from railwear.pde import Cubic, solve_evolution

N = 64
X = 2 * np.pi * np.arange(N) / N
U0 = 1e-5 * np.cos(3 * X) + 2e-5 * np.sin(7 * X + 0.3)


def shifted(u, angle):
    """``u(x + angle)`` spectrally (m)."""
    k = np.fft.rfftfreq(u.size, 1.0 / u.size)
    return np.fft.irfft(np.fft.rfft(u) * np.exp(1j * k * angle), u.size)


@pytest.mark.parametrize("drift", [0.7, -2.5])
def test_linear_h_with_drift_matches_the_exact_modes(drift):
    eps, nu, c1, mean_rate = 1e-4, 1e-3, -0.02, -1e-3
    ds = solve_evolution(U0, 1.0, Cubic(mean_rate, c1, 0.0), 0.0, eps, nu, drift=drift)
    k = np.fft.rfftfreq(N, 1.0 / N)
    rate = (-c1 * k**2 - eps * k**4 + 1j * drift * k) / (1 + nu * k**2)
    spectrum = np.fft.rfft(U0) * np.exp(rate)
    spectrum[0] += N * mean_rate
    exact = np.fft.irfft(spectrum, N)
    # within the step-size control's rtol (1e-4; the slope of h sits in the nonlinear part, the
    # drift in the exact linear part; a wrong sign or scale of the drift errs by O(1))
    np.testing.assert_allclose(ds.u.values[-1], exact, rtol=0, atol=1e-4 * np.ptp(exact - exact.mean()))


def test_drift_moves_the_nonlinear_solution_round_the_wheel():
    # without nu the drift is a pure travel: u(x, T) = w(x + drift T, T) with w the drift-free solution
    h, drift = Cubic(-1e-3, 0.01, -1e3), 1.3
    x = 2 * np.pi * np.arange(128) / 128  # resolves the harmonics the cubic makes
    u0 = 1e-5 * np.cos(3 * x) + 2e-5 * np.sin(7 * x + 0.3)
    still = solve_evolution(u0, 0.5, h, 0.0, 1e-4, 0.0, rtol=1e-7)
    moving = solve_evolution(u0, 0.5, h, 0.0, 1e-4, 0.0, drift=drift, rtol=1e-7)
    for j in (25, 50, 100):
        t = float(still.time[j])
        expected = shifted(still.u.values[j], drift * t)
        scale = np.ptp(expected)
        # both to the step-size control's tolerance (rtol 1e-7 each; a wrong travel errs by O(1))
        np.testing.assert_allclose(moving.u.values[j], expected, rtol=0, atol=1e-5 * scale)


def test_depth_stop_counts_the_drifted_pattern():
    h, limit = Cubic(-1e-3, 0.01, 0.0), 2e-4
    ds = solve_evolution(U0, 1.0, h, 0.0, 1e-4, 0.0, drift=3.0, depth_limit=limit)
    removed = np.max(U0 - ds.u.values[-1])
    # the crossing is interpolated linearly within a step
    assert abs(removed - limit) < 1e-3 * limit
    assert float(ds.stop_time) < 1.0


def test_drift_per_row_and_bad_drift():
    speeds = np.array([10.0, 20.0])
    ds = solve_evolution(U0, 0.2, Cubic(-1e-3, 0.01, 0.0), speeds, 1e-4, 0.0, drift=[0.0, 2.0])
    np.testing.assert_allclose(ds.u.values[-1, 1], shifted(ds.u.values[-1, 0], 0.4), atol=1e-6 * np.ptp(U0))
    with pytest.raises(ScenarioError, match="drift"):
        solve_evolution(U0, 0.2, Cubic(-1e-3, 0.01, 0.0), speeds, 1e-4, 0.0, drift=[1.0, 2.0, 3.0])
    with pytest.raises(ScenarioError, match="drift"):
        solve_evolution(U0, 0.2, Cubic(-1e-3, 0.01, 0.0), 0.0, 1e-4, 0.0, drift=np.nan)


def test_dispersion_matches_the_exact_modes():
    eps, nu, c1, disp = 1e-4, 1e-3, -0.02, 0.05
    ds = solve_evolution(U0, 1.0, Cubic(0.0, c1, 0.0), 0.0, eps, nu, drift=0.3, dispersion=disp)
    k = np.fft.rfftfreq(N, 1.0 / N)
    rate = (-c1 * k**2 - eps * k**4 + 1j * (0.3 * k - disp * k**3)) / (1 + nu * k**2)
    exact = np.fft.irfft(np.fft.rfft(U0) * np.exp(rate), N)
    # order 7 travels 2.45 rad further than order 3: a wrong sign or power errs by O(1)
    np.testing.assert_allclose(ds.u.values[-1], exact, rtol=0, atol=1e-4 * np.ptp(exact))
    with pytest.raises(ScenarioError, match="dispersion"):
        solve_evolution(U0, 0.2, Cubic(0.0, 0.01, 0.0), 0.0, 1e-4, 0.0, dispersion=np.inf)
