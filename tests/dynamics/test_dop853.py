"""The compiled Dormand-Prince 8(5,3) pair: order, dense output, events, agreement with other solvers."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from railwear.dynamics import DiskWheelModel, WheelsetModel, kernels, linear_critical_speed, simulate
from railwear.dynamics import integrators as integ

NO_EVAL = np.zeros(0)
NO_SURF = np.zeros(0)
# a damped oscillator coupled to a decaying mode: y' = A y, y(t) = expm(t A) y0
A = np.array([[0.0, 1.0, 0.0], [-4.0, -0.3, 0.5], [0.0, 0.0, -1.0]])
Y0 = np.array([1.0, 0.0, 0.5])
P_LINEAR = np.concatenate([[3.0], A.ravel()])
WHEELSET = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6,
                f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)


def _run(method, t_end, rtol, atol, t_eval=NO_EVAL, h0=0.0, h_max=np.inf, every=1):
    return integ.integrate(kernels.KIND_LINEAR, P_LINEAR, NO_SURF, Y0, 0.0, t_end, rtol, atol, method, h0, h_max,
                           10**7, t_eval, every, False, 1e300, np.zeros(0))


def _fixed_step_errors(h, offset=None):
    """Largest error at the end (``offset`` None) or at the dense outputs ``t_k + offset h``."""
    t_eval = NO_EVAL if offset is None else np.arange(0.0, 2.0 - 0.5 * h, h) + offset * h
    out = _run(integ.METHOD_DOP853, 2.0, 1e12, 1e12, t_eval=t_eval, h0=h, h_max=h)  # every step accepted
    assert out[3] == integ.STATUS_OK
    if offset is None:
        return np.max(np.abs(out[5] - expm(2.0 * A) @ Y0))
    exact = np.array([expm(t * A) @ Y0 for t in t_eval])
    return np.max(np.abs(out[1][:out[2]] - exact))


@pytest.mark.parametrize("offset", [None, 0.37, 0.81])
def test_order_eight_at_step_ends_and_in_the_dense_output(offset):
    # steps 0.4, 0.2, 0.1: errors from about 1e-7 down to 1e-12, well above round-off
    errors = np.array([_fixed_step_errors(h, offset) for h in (0.4, 0.2, 0.1)])
    observed = np.log2(errors[:-1] / errors[1:])
    np.testing.assert_allclose(observed, 8.0, atol=0.3)


def test_tolerance_proportionality_and_dense_output_times():
    t_eval = np.linspace(0.0, 5.0, 37)
    exact = np.array([expm(t * A) @ Y0 for t in t_eval])
    errors, steps = [], []
    for rtol in (1e-6, 1e-9, 1e-12):
        ts, ys, n_out, status, _, _, stats = _run(integ.METHOD_DOP853, 5.0, rtol, rtol * 1e-2, t_eval=t_eval)[:7]
        assert status == integ.STATUS_OK and n_out == t_eval.size
        np.testing.assert_array_equal(ts[:n_out], t_eval)
        errors.append(np.max(np.abs(ys[:n_out] - exact)))
        steps.append(stats[integ.STAT_NACCEPT])
    for rtol, error in zip((1e-6, 1e-9, 1e-12), errors):
        assert error < 30.0 * rtol
    assert errors[2] < errors[0] / 1e4
    # the steps grow as tol^(-1/8): 1e6 times tighter costs about 6 times the steps, not 16 (fifth order)
    assert steps[2] / steps[0] < 10.0


def test_output_every_n_steps_and_evaluation_count():
    ts, ys, n_out, status, t_last, y_last, stats = _run(integ.METHOD_DOP853, 5.0, 1e-10, 1e-12, every=3)[:7]
    naccept, nreject = stats[integ.STAT_NACCEPT], stats[integ.STAT_NREJECT]
    assert n_out == 1 + naccept // 3 + (1 if naccept % 3 else 0)
    assert ts[0] == 0.0 and ts[n_out - 1] == 5.0 and np.all(np.diff(ts[:n_out]) > 0)
    np.testing.assert_allclose(ys[n_out - 1], expm(5.0 * A) @ Y0, rtol=0, atol=1e-9)
    # 12 evaluations per step (FSAL), 2 for the initial step size; no dense output asked
    assert stats[integ.STAT_NFEV] == 2 + 12 * (naccept + nreject)


def test_wheelset_hunting_agrees_with_scipy_dop853_and_dopri5():
    vc = linear_critical_speed(**WHEELSET)
    model = WheelsetModel(speed=1.2 * vc, **WHEELSET, flange_clearance=5e-3, flange_stiffness=1.5e7,
                          friction_coefficient=0.3, wheel_load=50e3, initial_lateral_displacement=1e-3)
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    t_end = 2.0
    t_eval = np.linspace(0.0, t_end, 401)

    def compiled(method, rtol):
        out = integ.integrate(model.kind, p, surf, y0, 0.0, t_end, rtol, rtol * 1e-2, method, 0.0, np.inf, 10**7,
                              t_eval, 1, False, 1e6, np.zeros(0))
        assert out[3] == integ.STATUS_OK
        return out[1][:out[2]]

    def f(t, y):
        out = np.empty(y.size)
        kernels.rhs(model.kind, t, y, p, surf, out)
        return out

    reference = solve_ivp(f, (0.0, t_end), y0, method="DOP853", t_eval=t_eval, rtol=1e-12, atol=1e-14).y.T
    amplitude = np.max(np.abs(reference[:, 0]))
    assert amplitude > 4e-3  # the flange is reached: the case is the non-smooth one of the benchmark
    ours = compiled(integ.METHOD_DOP853, 1e-11)
    assert np.max(np.abs(ours[:, 0] - reference[:, 0])) < 1e-9
    dopri = compiled(integ.METHOD_DOPRI5, 1e-11)
    assert np.max(np.abs(ours[:, 0] - dopri[:, 0])) < 1e-9
    # through simulate() by name, at the default tolerance
    ds = simulate(model, t_end, method="dop853", t_eval=t_eval)
    assert ds.attrs["method"] == "dop853"
    assert np.max(np.abs(ds.lateral_displacement.values - reference[:, 0])) < 1e-7


def test_events_agree_with_dopri5_and_sit_on_the_contact_boundary():
    # the disk wheel thrown upward: repeated contact loss and regain (events of the approach)
    model = DiskWheelModel(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3,
                           hertz_constant=1.05e11, primary_stiffness=1e6, primary_damping=4e4, sprung_mass=5000.0,
                           rail_mass=150.0, pad_stiffness=1e8, pad_damping=5e4, f11=1.15e7,
                           friction_coefficient=0.3, patch_half_length=6e-3, traction_torque=5e3,
                           initial_vertical_velocity=0.3)
    p, surf = model.params(), model.surface()
    runs = {}
    for method in (integ.METHOD_DOP853, integ.METHOD_DOPRI5):
        out = integ.integrate(model.kind, p, surf, model.initial_state(), 0.0, 0.1, 1e-10, 1e-13, method, 0.0,
                              np.inf, 10**6, np.linspace(0.0, 0.1, 1001), 1, True, 1e6, np.zeros(0))
        assert out[3] == integ.STATUS_OK
        runs[method] = out
    ours, theirs = runs[integ.METHOD_DOP853], runs[integ.METHOD_DOPRI5]
    ev_t, ev_y, ev_dir = ours[7], ours[8], ours[9]
    assert ev_t.size >= 4 and ev_dir[0] == -1 and np.all(ev_dir[1:] == -ev_dir[:-1])
    np.testing.assert_array_equal(ev_dir, theirs[9])
    np.testing.assert_allclose(ev_t, theirs[7], rtol=0, atol=1e-9)
    gaps = [kernels.event(model.kind, t, y, p, surf) for t, y in zip(ev_t, ev_y)]
    assert np.max(np.abs(gaps)) < 1e-9 * model.static_approach
    # dense output through the kinks of the contact loss: the same wheel motion
    assert np.max(np.abs(ours[1][:, 2] - theirs[1][:, 2])) < 1e-6 * model.static_approach


def test_blow_up_is_reported_not_returned():
    out = integ.integrate(kernels.KIND_LINEAR, np.array([1.0, 5.0]), NO_SURF, np.array([1.0]), 0.0, 100.0, 1e-8,
                          1e-10, integ.METHOD_DOP853, 0.0, np.inf, 10**7, NO_EVAL, 1, False, 1e6, np.zeros(0))
    status, t_last, y_last = out[3], out[4], out[5]
    assert status == integ.STATUS_BLOW_UP
    assert np.all(np.isfinite(y_last)) and abs(y_last[0]) <= 1e6 and t_last < 100.0
