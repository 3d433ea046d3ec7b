"""GGL index-2 DAE with IDA: the planar pendulum against the angle ODE."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from railwear.dynamics.dae import planar_pendulum, solve_ggl
from railwear.errors import ScenarioError

G, L, M = 9.81, 1.3, 2.0
THETA0, OMEGA0 = 1.2, 0.0  # a large swing, far from the linear pendulum


def _angle_reference(t_eval):
    sol = solve_ivp(lambda t, s: [s[1], -G / L * np.sin(s[0])], (t_eval[0], t_eval[-1]), [THETA0, OMEGA0],
                    method="DOP853", t_eval=t_eval, rtol=1e-13, atol=1e-13)
    return sol.y


def _start():
    q0 = L * np.array([np.sin(THETA0), -np.cos(THETA0)])
    v0 = L * OMEGA0 * np.array([np.cos(THETA0), np.sin(THETA0)])
    return q0, v0


def test_ggl_pendulum_matches_the_angle_ode_and_keeps_the_constraint():
    t_eval = np.linspace(0.0, 5.0, 201)
    sol = solve_ggl(planar_pendulum(M, L, G), t_eval, *_start(), rtol=1e-9, atol=1e-11)
    theta, omega = _angle_reference(t_eval)
    x_ref, y_ref = L * np.sin(theta), -L * np.cos(theta)
    assert np.max(np.abs(sol.q[:, 0] - x_ref)) < 1e-6
    assert np.max(np.abs(sol.q[:, 1] - y_ref)) < 1e-6
    assert sol.constraint_drift < 1e-8  # position constraint
    assert np.max(np.abs(np.sum(sol.q * sol.v, axis=1))) < 1e-6  # velocity constraint
    # the multiplier is the rod tension over the length: m (g cos(theta) + L omega^2) / L
    tension = M * (G * np.cos(theta) + L * omega**2) / L
    np.testing.assert_allclose(sol.lam[:, 0], tension, rtol=1e-4)
    assert np.max(np.abs(sol.mu)) * L < 1e-5 * np.max(np.abs(sol.v))  # mu vanishes on exact solutions


def test_error_shrinks_with_the_tolerance():
    t_eval = np.linspace(0.0, 3.0, 61)
    theta, _ = _angle_reference(t_eval)
    errors = []
    for rtol in (1e-5, 1e-9):
        sol = solve_ggl(planar_pendulum(M, L, G), t_eval, *_start(), rtol=rtol, atol=rtol * 1e-2)
        errors.append(np.max(np.abs(sol.q[:, 0] - L * np.sin(theta))))
    assert errors[1] < errors[0] / 100.0


def test_inconsistent_start_is_rejected():
    q0, v0 = _start()
    with pytest.raises(ScenarioError, match="initial_state"):
        solve_ggl(planar_pendulum(M, L, G), [0.0, 1.0], 1.01 * q0, v0)
    with pytest.raises(ScenarioError, match="initial_state"):
        solve_ggl(planar_pendulum(M, L, G), [0.0, 1.0], q0, q0)
