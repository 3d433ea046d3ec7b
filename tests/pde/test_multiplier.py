"""The multiplier law u_T = Λ u + B g(A u): the multiplier exact in ETDRK4's linear part, the local part's plumbing."""

import numpy as np
import pytest

from railwear.errors import IllPosedError, ScenarioError
from railwear.pde import Cubic, Pointwise
from railwear.pde.multiplier import Fixed, MultiplierEquation, Remainder, solve_multiplier
from railwear.pde.solver import ETDRK4Solver

N = 32
X = 2 * np.pi * np.arange(N) / N
K = np.arange(N // 2 + 1)
U0 = 1e-5 * np.cos(3 * X) + 2e-5 * np.sin(7 * X + 0.3) + 1e-5 * np.cos(12 * X)
# a band of orders round 7 grows, the rest decay, and every order travels: no local law does this
RATE = 0.8 * np.exp(-((K - 7.0) ** 2) / 4) - 0.3 + 0.4j * K
RATE[0] = 0.0


def exact(rate, mean, t, epsilon=0.0, nu=0.0):
    spectrum = np.fft.rfft(U0) * np.exp((rate - epsilon * K**4) / (1 + nu * K**2) * t)
    spectrum[0] += N * mean * t
    return np.fft.irfft(spectrum, N)


@pytest.mark.parametrize("epsilon, nu", [(0.0, 0.0), (1e-4, 1e-3)])
def test_multiplier_and_mean_rate_are_exact(epsilon, nu):
    # L = (λ_n - ε n⁴)/(1 + ν n²) in the exponential, a constant g in the mean: exact to round-off
    # (measured 2e-13 of the peak-to-peak); a wrong sign or conjugate of λ errs by O(1)
    ds = solve_multiplier(U0, 2.0, RATE, Cubic(-1e-3), 0.0, epsilon, nu)
    expected = exact(RATE, -1e-3, 2.0, epsilon, nu)
    np.testing.assert_allclose(ds.u.values[-1], expected, rtol=0, atol=1e-10 * np.ptp(expected))


def test_remainder_does_not_count_the_linear_part_twice():
    # h = c0 + c1 u_xx: its remainder is the constant alone, so the run is the multiplier's exactly
    h = Cubic(-2e-3, 0.05, 0.0)
    ds = solve_multiplier(U0, 1.0, RATE, Remainder(h, -1e-3))
    expected = exact(RATE, -1e-3, 1.0)
    np.testing.assert_allclose(ds.u.values[-1], expected, rtol=0, atol=1e-10 * np.ptp(expected))
    # with a cubic term the remainder is that term plus the constant
    p = Remainder(Cubic(-2e-3, 0.05, 7.0), -1e-3).at_speed(0.0)
    np.testing.assert_allclose(p.poly, [-1e-3, 0.0, 0.0, 7.0], rtol=0, atol=1e-15)
    # and of a table: value and slope at 0 removed, to the table's interpolation (1e-9 of its range)
    table = Pointwise.from_samples(-1.0, 1.0, lambda s: np.exp(s), lambda s: np.exp(s))
    r = Remainder(Fixed(table)).at_speed(0.0)
    s = np.linspace(-0.5, 0.5, 11)
    np.testing.assert_allclose(r(s), np.exp(s) - 1 - s, rtol=0, atol=1e-9)


def test_local_input_and_output_reach_the_point_wise_part():
    # w = A u with A only at order 3 (complex): w = |A| a cos(3x + φ); g = c w²; B only at order 0.
    # λ_3 pure imaginary keeps |û_3|, so the mean falls at exactly c |A|² a² / 2 per unit time.
    a, c = 1e-5, 2e4
    u0 = a * np.cos(3 * X)
    A = np.zeros(K.size, complex)
    A[3] = 5e3 * np.exp(0.7j)
    B = np.zeros(K.size)
    B[0] = 1.0
    rate = np.zeros(K.size, complex)
    rate[3] = 2.5j
    ds = solve_multiplier(u0, 1.0, rate, Fixed(Pointwise(np.array([0.0, 0.0, c]))),
                          local_input=A, local_output=B)
    mean = ds.u.values.mean(axis=1)
    expected = c * abs(A[3]) ** 2 * a**2 / 2 * ds.time.values
    np.testing.assert_allclose(mean, expected, rtol=1e-10, atol=1e-12 * expected[-1])
    # the order-3 harmonic only travels, at -Im λ_3 / 3 rad per unit time
    spectrum = np.fft.rfft(ds.u.values[-1])
    np.testing.assert_allclose(spectrum[3], np.fft.rfft(u0)[3] * np.exp(2.5j), rtol=1e-10)


def test_growing_orders_are_not_ill_posed_but_an_unregularised_local_law_is():
    # a bounded multiplier with growing orders solves without regularisation
    grow = np.where(K > 0, 1.0 + 0j, 0.0)
    ds = solve_multiplier(U0, 0.5, grow)
    np.testing.assert_allclose(ds.u.values[-1], exact(grow, 0.0, 0.5), rtol=0, atol=1e-10 * np.ptp(U0))
    # a local g(u_xx) decreasing in the curvature (backward parabolic) without epsilon or nu is not
    with pytest.raises(IllPosedError):
        solve_multiplier(U0, 0.5, RATE, Cubic(0.0, 0.0, -1e6))


def test_the_fingerprint_holds_the_multiplier():
    one = MultiplierEquation.from_multiplier(U0, RATE)
    other = MultiplierEquation.from_multiplier(U0, RATE * 1.01)
    solver = ETDRK4Solver()
    assert solver.fingerprint(one, 1.0) != solver.fingerprint(other, 1.0)


def test_bad_multipliers_are_refused():
    with pytest.raises(ScenarioError, match="rate"):
        solve_multiplier(U0, 1.0, RATE[:-1])
    with pytest.raises(ScenarioError, match="local_input"):
        solve_multiplier(U0, 1.0, RATE, local_input=np.full(K.size, np.nan))
