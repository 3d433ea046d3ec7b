"""Closed-form critical speed of the linear wheelset against the eigenvalue crossing."""

import math

import numpy as np
import pytest

from railwear.dynamics import WheelsetModel, critical_speed, linear_critical_speed, max_real_part

CLOSED_FORM_ARGS = (
    "mass", "yaw_inertia", "lateral_stiffness", "yaw_stiffness", "f11", "f22", "half_gauge", "rolling_radius", "conicity",
)

PARAMETER_SETS = [
    # mass, yaw inertia, k_y, k_psi, f11, f22, e, r0, conicity
    dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6, f22=5.9e6,
         half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05),
    dict(mass=1500.0, yaw_inertia=800.0, lateral_stiffness=0.5e6, yaw_stiffness=5.0e6, f11=9.0e6, f22=8.0e6,
         half_gauge=0.75, rolling_radius=0.46, conicity=0.2),
    dict(mass=1800.0, yaw_inertia=1100.0, lateral_stiffness=3.0e6, yaw_stiffness=0.3e6, f11=1.2e7, f22=1.0e7,
         half_gauge=0.7465, rolling_radius=0.43, conicity=0.35),
    dict(mass=900.0, yaw_inertia=500.0, lateral_stiffness=4.0e5, yaw_stiffness=4.0e5, f11=3.0e6, f22=2.5e6,
         half_gauge=0.72, rolling_radius=0.5, conicity=0.1),
]

# m k_psi far above I k_y: the Routh-Hurwitz denominator is negative, stable at all speeds
STABLE_SET = dict(mass=1000.0, yaw_inertia=600.0, lateral_stiffness=1.0e6, yaw_stiffness=6.0e7, f11=1.0e7,
                  f22=1.0e7, half_gauge=0.75, rolling_radius=0.46, conicity=0.05)


def _model(params, speed=30.0, **extra):
    return WheelsetModel(speed=speed, **params, **extra)


@pytest.mark.parametrize("params", PARAMETER_SETS)
def test_closed_form_matches_eigenvalue_crossing(params):
    closed = linear_critical_speed(**{key: params[key] for key in CLOSED_FORM_ARGS})
    assert math.isfinite(closed) and closed > 0.0
    crossing = critical_speed(_model(params))
    assert crossing == pytest.approx(closed, rel=1e-9, abs=0.0)
    # and the sign change is real: stable just below, unstable just above
    model = _model(params)
    assert max_real_part(model, 0.99 * closed) < 0.0 < max_real_part(model, 1.01 * closed)


def test_stable_at_all_speeds():
    closed = linear_critical_speed(**STABLE_SET)
    assert closed == math.inf
    assert critical_speed(_model(STABLE_SET)) == math.inf
    model = _model(STABLE_SET)
    assert all(max_real_part(model, v) < 0.0 for v in np.geomspace(1.0, 3000.0, 30))


def test_critical_speed_scales_like_routh_hurwitz():
    """Independent check of the closed form: the Hurwitz determinant of the characteristic
    quartic vanishes at the closed-form speed."""
    params = PARAMETER_SETS[1]
    closed = linear_critical_speed(**params)
    for v, sign in ((0.98 * closed, 1.0), (1.02 * closed, -1.0)):
        coeffs = np.poly(_model(params).state_matrix(v))  # s^4 + a1 s^3 + a2 s^2 + a3 s + a4
        a1, a2, a3, a4 = coeffs[1:]
        hurwitz3 = a1 * a2 * a3 - a3 * a3 - a1 * a1 * a4
        assert np.sign(hurwitz3) == sign


def test_spin_and_damping_shift_the_crossing():
    """The eigenvalue route covers what the closed form does not: yaw damping raises Vc."""
    params = PARAMETER_SETS[0]
    bare = critical_speed(_model(params))
    damped = critical_speed(_model(params, yaw_damping=2.0e4))
    assert damped > 1.05 * bare
