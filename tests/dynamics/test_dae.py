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


def test_wheelset_dae_matches_the_minimal_ode():
    """Vertical motion and roll restricted by the contact constraints: eliminating them leaves the
    minimal ODE with lateral mass m + I_x (lam/e)^2; without that term the runs differ."""
    import dataclasses

    from railwear.dynamics import WheelsetModel, simulate
    from railwear.dynamics.dae import wheelset_ggl_problem

    model = WheelsetModel(speed=60.0, mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6,
                          f11=6.4e6, f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.2,
                          initial_lateral_displacement=3e-3)
    roll_inertia = 700.0
    t_eval = np.linspace(0.0, 2.0, 401)
    y0 = model.initial_lateral_displacement
    q0 = np.array([y0, 0.0, model.conicity * y0 / model.half_gauge, 0.0])
    dae = solve_ggl(wheelset_ggl_problem(model, roll_inertia), t_eval, q0, np.zeros(4), rtol=1e-9, atol=1e-12)
    assert dae.constraint_drift < 1e-8
    effective = dataclasses.replace(model, mass=model.mass + roll_inertia * (model.conicity / model.half_gauge) ** 2)
    ode = simulate(effective, 2.0, t_eval=t_eval, rtol=1e-10, atol=1e-13)
    assert np.max(np.abs(dae.q[:, 0] - ode.lateral_displacement.values)) < 1e-8  # amplitude 3e-3 m
    assert np.max(np.abs(dae.q[:, 3] - ode.yaw_angle.values)) < 1e-8
    plain = simulate(model, 2.0, t_eval=t_eval, rtol=1e-10, atol=1e-13)
    assert np.max(np.abs(dae.q[:, 0] - plain.lateral_displacement.values)) > 1e-5
    # the normal forces (minus the multipliers) carry the weight; their difference moves the roll
    np.testing.assert_allclose(-dae.lam.sum(axis=1), model.mass * 9.81, rtol=1e-6)


def test_rigid_disk_wheel_dae_gives_mass_times_the_second_derivative_of_u_bar():
    """Disk wheel with rigid contact in GGL form: the free wheel must follow u_bar(t), so
    N - W = m d2(u_bar)/dt2 = m (V/R0)^2 (s(x + w) - s(x - w)) / (2 w), with s the slope of the
    piecewise-linear u in the cell under x +- w (a staircase: rigid contact feels the second
    derivative of the surface, paper section 2). Samples on the jumps of the staircase are
    ambiguous, so the check is on nearly all samples."""
    from railwear.dynamics import DiskWheelModel
    from railwear.dynamics.dae import disk_wheel_ggl_problem

    n_cells, order, amplitude = 512, 5, 1e-6
    cells = 2 * np.pi * np.arange(n_cells) / n_cells
    u = amplitude * np.cos(order * cells)
    model = DiskWheelModel(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3,
                           hertz_constant=1.05e11, primary_stiffness=0.0, f11=1.15e7, patch_half_length=6e-3,
                           radius_deviation=u)
    problem, q0, v0 = disk_wheel_ggl_problem(model)
    t_eval = np.linspace(0.0, 0.05, 501)
    sol = solve_ggl(problem, t_eval, q0, v0, rtol=1e-8, atol=1e-14)
    assert sol.constraint_drift < 1e-12  # metres, against an amplitude of 1e-6
    rate, w, dx = model.speed / model.radius, model.patch_half_length / model.radius, 2 * np.pi / n_cells

    def slope(x):
        j = np.floor(np.mod(x, 2 * np.pi) / dx).astype(int) % n_cells
        return (u[(j + 1) % n_cells] - u[j]) / dx

    x = rate * t_eval
    expected = model.static_load + model.wheel_mass * rate**2 * (slope(x + w) - slope(x - w)) / (2 * w)
    normal = model.static_load - sol.lam[:, 0]
    scale = model.wheel_mass * (order * rate) ** 2 * amplitude
    error = np.abs(normal - expected) / scale
    assert np.median(error) < 1e-9
    assert np.mean(error < 1e-6) > 0.98


def test_bogie_dae_matches_its_ode_twin():
    import dataclasses

    from railwear.dynamics import BogieModel, simulate
    from railwear.dynamics.dae import bogie_ggl_problem

    bogie = BogieModel.cooperrider(40.0, conicity=0.15, initial_lateral_displacement=3e-3)
    roll_inertia = 700.0
    q0 = np.zeros(10)
    q0[0] = bogie.initial_lateral_displacement
    q0[2] = bogie.conicity * q0[0] / bogie.half_gauge
    t_eval = np.linspace(0.0, 2.0, 401)
    dae = solve_ggl(bogie_ggl_problem(bogie, roll_inertia), t_eval, q0, np.zeros(10), rtol=1e-9, atol=1e-12)
    assert dae.constraint_drift < 1e-8
    twin = dataclasses.replace(bogie, wheelset_mass=bogie.wheelset_mass
                               + roll_inertia * (bogie.conicity / bogie.half_gauge) ** 2)
    ode = simulate(twin, 2.0, t_eval=t_eval, rtol=1e-10, atol=1e-13)
    assert np.max(np.abs(ode.lateral_displacement.values)) > bogie.flange_clearance  # into the flange
    np.testing.assert_allclose(dae.q[:, [0, 4]], ode.lateral_displacement.values, rtol=0, atol=1e-8)
    np.testing.assert_allclose(dae.q[:, 8], ode.frame_lateral_displacement.values, rtol=0, atol=1e-8)
