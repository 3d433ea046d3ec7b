"""The suspended wheelset on straight track: linearisation, Klingel, hunting (paper Fig. 1)."""

import numpy as np
import pytest

from railwear.dynamics import WheelsetModel, linear_critical_speed, max_real_part
from railwear.dynamics import kernels
from railwear.dynamics import simulate

BASE = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6, f22=5.9e6,
            half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)
NONLINEAR = dict(flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3, wheel_load=50e3)
VC = linear_critical_speed(**BASE)


def _jacobian(model, y):
    p, surf = model.params(), model.surface()
    jac = np.empty((4, 4))
    f_plus, f_minus = np.empty(4), np.empty(4)
    for j in range(4):
        h = 1e-7
        yp, ym = y.copy(), y.copy()
        yp[j] += h
        ym[j] -= h
        kernels.rhs(model.kind, 0.0, yp, p, surf, f_plus)
        kernels.rhs(model.kind, 0.0, ym, p, surf, f_minus)
        jac[:, j] = (f_plus - f_minus) / (2 * h)
    return jac


def test_rhs_linearises_to_the_state_matrix_with_spin():
    model = WheelsetModel(speed=40.0, **BASE, f23=1.5e3, f33=20.0, lateral_damping=1e3, yaw_damping=2e3,
                          friction_coefficient=np.inf)
    np.testing.assert_allclose(_jacobian(model, np.zeros(4)), model.state_matrix(), rtol=1e-6, atol=1e-6)


def test_centred_rolling_is_an_equilibrium_with_spin_and_saturation():
    model = WheelsetModel(speed=40.0, **BASE, f23=1.5e3, f33=20.0, **NONLINEAR)
    out = np.empty(4)
    kernels.rhs(model.kind, 0.0, np.zeros(4), model.params(), model.surface(), out)
    np.testing.assert_array_equal(out, 0.0)


def _zero_crossings(x, y):
    i = np.nonzero(np.sign(y[:-1]) != np.sign(y[1:]))[0]
    return x[i] - y[i] * (x[i + 1] - x[i]) / (y[i + 1] - y[i])


def test_kinematic_limit_has_klingel_wavelength():
    # no suspension, creep coefficients 1000 times the real ones, 0.1 mm amplitude
    model = WheelsetModel(speed=20.0, mass=1000.0, yaw_inertia=600.0, lateral_stiffness=0.0, yaw_stiffness=0.0,
                          f11=1e10, f22=1e10, half_gauge=0.75, rolling_radius=0.46, conicity=0.05,
                          initial_lateral_displacement=1e-4)
    ds = simulate(model, 4.0, method="rosenbrock", rtol=1e-8, n_output=40001)
    crossings = _zero_crossings(ds.distance.values, ds.lateral_displacement.values)
    assert crossings.size >= 8
    wavelength = 2.0 * np.mean(np.diff(crossings))
    assert wavelength == pytest.approx(model.klingel_wavelength(), rel=0.02)


@pytest.mark.parametrize("creep_law", ["cubic", "fastsim"])
def test_small_motion_grows_at_the_eigenvalue_rate(creep_law):
    """Just above Vc the envelope of a tiny motion grows at the largest real part (under FASTSIM,
    of the state matrix with FASTSIM's linear slope)."""
    model = WheelsetModel(speed=1.1 * VC, **BASE, **NONLINEAR, initial_lateral_displacement=1e-7, creep_law=creep_law)
    ds = simulate(model, 1.5, n_output=30001, rtol=1e-10)
    t, y = ds.time.values, ds.lateral_displacement.values
    peaks = np.nonzero((y[1:-1] > y[:-2]) & (y[1:-1] > y[2:]))[0] + 1
    late = peaks[t[peaks] > 0.5]  # past the transient of the fast mode
    rate = np.polyfit(t[late], np.log(y[late]), 1)[0]
    assert np.max(np.abs(y)) < 1e-5  # stays inside the linear range
    assert rate == pytest.approx(max_real_part(model, model.speed), rel=1e-3)


def test_hunting_below_and_above_critical_speed():
    """Paper Fig. 1: the motion dies out below Vc; above it a flange-bounded limit cycle."""
    below = simulate(WheelsetModel(speed=0.8 * VC, **BASE, **NONLINEAR), 4.0, n_output=2001)
    assert np.max(np.abs(below.lateral_displacement.values[-500:])) < 1e-6
    amplitudes = []
    for y0 in (1e-4, 12e-3):
        ds = simulate(WheelsetModel(speed=1.2 * VC, **BASE, **NONLINEAR, initial_lateral_displacement=y0), 8.0,
                      n_output=8001)
        y = ds.lateral_displacement.values
        last, before = np.max(np.abs(y[-1000:])), np.max(np.abs(y[-2000:-1000]))
        assert last == pytest.approx(before, rel=1e-3)  # periodic
        assert float(ds.flange_force.min()) < 0.0  # the flange bounds it
        assert np.all(ds.frictional_power.values >= 0.0)
        amplitudes.append(last)
    assert amplitudes[0] > NONLINEAR["flange_clearance"]
    # one attractor, reached from inside and from outside
    assert amplitudes[0] == pytest.approx(amplitudes[1], rel=1e-3)


def test_response_to_a_lateral_track_irregularity():
    """Below Vc a harmonic alignment of wavelength 25 m drives the wheelset at 2 pi V / 25 m with
    the linear frequency response; the input enters through the rolling-radius difference."""
    wavelength, speed = 25.0, 0.7 * VC
    n = 256
    alignment = 1e-3 * np.cos(2 * np.pi * np.arange(n) / n)
    model = WheelsetModel(speed=speed, **BASE, lateral_irregularity=alignment, irregularity_wavelength=wavelength,
                          initial_lateral_displacement=0.0)
    ds = simulate(model, 3.0, rtol=1e-10, n_output=6001)
    late = ds.time.values > 1.5
    t = ds.time.values[late]
    omega = 2 * np.pi * speed / wavelength
    basis = np.stack([np.cos(omega * t), np.sin(omega * t)], axis=1)

    def phasor(signal):
        c = np.linalg.lstsq(basis, signal, rcond=None)[0]
        return c[0] - 1j * c[1]

    y_hat = phasor(ds.lateral_displacement.values[late])
    track_hat = phasor(ds.track_lateral_alignment.values[late])
    b = np.zeros(4)
    b[3] = 2 * model.f11 * model.half_gauge * model.conicity / (model.rolling_radius * model.yaw_inertia)
    expected = np.linalg.solve(1j * omega * np.eye(4) - model.state_matrix(), b)[0]
    assert y_hat / track_hat == pytest.approx(expected, rel=1e-3)
    assert abs(expected) > 0.1  # a real response, not a trivially small one
