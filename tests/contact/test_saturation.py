import numpy as np
import pytest

from railwear.contact import (POLACH_DRY, POLACH_WET, inverse_cubic, linear_creep_forces, polach,
                              shen_hedrick_elkins)
from railwear.errors import ScenarioError

A, B, G, NU, N = 6e-3, 8e-3, 8.1e10, 0.28, 1.0e5


def test_she_limits_and_smoothness():
    mu = 0.3
    F = np.linspace(0, 5 * mu * N, 2001)
    sat = shen_hedrick_elkins(F, 0.0, N, mu).Fx
    # small forces pass unchanged to first order, large ones are capped at mu N
    assert sat[1] == pytest.approx(F[1], rel=1e-3)
    assert np.all(sat <= mu * N * (1 + 1e-15)) and sat[-1] == pytest.approx(mu * N)
    assert np.all(np.diff(sat) >= -1e-12 * mu * N)  # rounding of F * (limit / F) on the cap
    # at beta = 3 the cubic meets mu N with zero slope
    assert shen_hedrick_elkins(3 * mu * N, 0.0, N, mu).Fx == pytest.approx(mu * N, rel=1e-14)
    d = np.diff(sat) / np.diff(F)
    k = np.searchsorted(F, 3 * mu * N)
    assert abs(d[k - 1]) < 1e-3


def test_inverse_cubic_inverts_the_cubic_law():
    """The creepage ``ξ_s r`` of ``inverse_cubic`` gives back the demand through Shen-Hedrick-Elkins'
    cubic law to 1e-12 below saturation (``k ξ = 3 μN r`` linear force), except at tiny demands,
    where ``1 - (1 - q)^(1/3)`` cancels: about ``1e-16 / q`` (1e-10 measured at ``q = 1e-6``,
    1e-9 asserted); at and above ``μN`` the wheel slides at ``ξ_s`` (``q = r = 1``)."""
    mu, k = 0.3, 9e6  # -, N per unit creepage
    demand = mu * N * np.array([0.0, 1e-6, 0.1, 0.5, 0.9, 0.999999, 1.0, 1.7])
    q, r = inverse_cubic(demand, mu * N)
    xi = 3 * mu * N / k * r
    force = shen_hedrick_elkins(k * xi, 0.0, N, mu).Fx
    tiny = np.arange(demand.size) == 1
    np.testing.assert_allclose(force[~tiny], np.minimum(demand, mu * N)[~tiny], rtol=1e-12, atol=0)
    np.testing.assert_allclose(force[tiny], demand[tiny], rtol=1e-9)
    np.testing.assert_array_equal(q[-2:], 1.0)
    np.testing.assert_array_equal(r[-2:], 1.0)
    # far from saturation the creepage is Kalker's linear F / k (to first order in F/μN: 1e-6 here)
    assert xi[1] == pytest.approx(demand[1] / k, rel=1e-6)


def test_she_keeps_direction_and_scales_moment():
    s = shen_hedrick_elkins(3e4, -4e4, N, 0.3, Mz=10.0)
    assert s.Fx / s.Fy == pytest.approx(-0.75)
    assert np.hypot(s.Fx, s.Fy) == pytest.approx(0.3 * N * (5 / 3 - 25 / 27 + 125 / 729), rel=1e-12)
    assert s.Mz == pytest.approx(10.0 * np.hypot(s.Fx, s.Fy) / 5e4, rel=1e-12)


def test_polach_linear_limit_is_kalker():
    xi, eta = 1e-8, -2e-8  # one creepage at a time (Polach couples them through C otherwise)
    px = polach(A, B, N, xi, 0.0, G, NU, mu0=0.3)  # kA = kS = 1, constant friction
    py = polach(A, B, N, 0.0, eta, G, NU, mu0=0.3)
    assert px.Fx == pytest.approx(linear_creep_forces(A, B, xi, 0.0, 0.0, G, NU).Fx, rel=1e-6)
    assert py.Fy == pytest.approx(linear_creep_forces(A, B, 0.0, eta, 0.0, G, NU).Fy, rel=1e-6)


def test_polach_saturation_and_falling_friction():
    xi = np.geomspace(1e-6, 1.0, 400)
    const = polach(A, B, N, xi, 0.0, G, NU, mu0=0.3)
    assert -const.Fx[-1] == pytest.approx(0.3 * N, rel=1e-3)  # F -> mu N
    assert np.all(np.diff(-const.Fx) > 0)
    dry = polach(A, B, N, xi, 0.0, G, NU, params=POLACH_DRY, speed=20.0)
    wet = polach(A, B, N, xi, 0.0, G, NU, params=POLACH_WET, speed=20.0)
    # friction falls from mu0 to A mu0 with the slip velocity
    assert dry.mu[0] == pytest.approx(0.55, rel=1e-4) and dry.mu[-1] == pytest.approx(0.55 * 0.4, rel=1e-3)
    assert wet.mu[0] == pytest.approx(0.30, rel=1e-4)
    # a maximum of adhesion at finite creepage, then a falling branch; wet lies below dry
    kmax = np.argmax(-dry.Fx)
    assert 0 < kmax < xi.size - 1 and -dry.Fx[-1] < -dry.Fx[kmax]
    assert np.max(-wet.Fx) < np.max(-dry.Fx)
    # kA, kS < 1 reduce the initial slope by kA + kS over 2 relative to Kalker
    small = polach(A, B, N, 1e-9, 0.0, G, NU, params=POLACH_WET)
    lin = linear_creep_forces(A, B, 1e-9, 0.0, 0.0, G, NU).Fx
    assert small.Fx / lin == pytest.approx((0.3 + 0.1) / 2, rel=1e-4)


def test_polach_bad_input():
    with pytest.raises(ScenarioError, match="a"):
        polach(0.0, B, N, 1e-3, 0, G, NU, mu0=0.3)
    with pytest.raises(ScenarioError, match="normal_force"):
        polach(A, B, -N, 1e-3, 0, G, NU, mu0=0.3)
    with pytest.raises(ScenarioError, match="normal_force"):
        shen_hedrick_elkins(1.0, 0.0, -1.0, 0.3)
