"""The compiled integrators: order of accuracy, dense output, stiff problems, blow-up status."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from railwear.dynamics import integrators as integ
from railwear.dynamics import kernels

NO_EVAL = np.zeros(0)
NO_SURF = np.zeros(0)
# a damped oscillator coupled to a decaying mode: y' = A y
A = np.array([[0.0, 1.0, 0.0], [-4.0, -0.3, 0.5], [0.0, 0.0, -1.0]])
Y0 = np.array([1.0, 0.0, 0.5])
P_LINEAR = np.concatenate([[3.0], A.ravel()])


def _run(method, t_end, rtol, atol, t_eval=NO_EVAL, h0=0.0, h_max=np.inf, every=1, p=P_LINEAR, y0=Y0,
         kind=kernels.KIND_LINEAR, max_norm=1e300):
    return integ.integrate(kind, p, NO_SURF, y0, 0.0, t_end, rtol, atol, method, h0, h_max, 10**7, t_eval, every,
                           False, max_norm, np.zeros(0))


def _fixed_step_error(method, h):
    # a huge tolerance accepts every step, so h_max fixes the step size
    out = _run(method, 2.0, 1e12, 1e12, h0=h, h_max=h)
    assert out[3] == integ.STATUS_OK
    return np.max(np.abs(out[5] - expm(2.0 * A) @ Y0))


@pytest.mark.parametrize("method, order", [(integ.METHOD_DOPRI5, 5), (integ.METHOD_ROSENBROCK, 2)])
def test_convergence_order(method, order):
    e1 = _fixed_step_error(method, 0.04)
    e2 = _fixed_step_error(method, 0.02)
    observed = np.log2(e1 / e2)
    assert abs(observed - order) < 0.3


@pytest.mark.parametrize("method", [integ.METHOD_DOPRI5, integ.METHOD_ROSENBROCK])
def test_dense_output_and_tolerance_proportionality(method):
    t_eval = np.linspace(0.0, 5.0, 37)
    exact = np.array([expm(t * A) @ Y0 for t in t_eval])
    errors = []
    for rtol in (1e-5, 1e-8):
        ts, ys, n_out, status = _run(method, 5.0, rtol, rtol * 1e-2, t_eval=t_eval)[:4]
        assert status == integ.STATUS_OK and n_out == t_eval.size
        np.testing.assert_array_equal(ts[:n_out], t_eval)
        errors.append(np.max(np.abs(ys[:n_out] - exact)))
    # tighter tolerance, smaller error: at least a factor 30 for 1000x tighter tolerances
    assert errors[1] < errors[0] / 30.0
    assert errors[1] < (1e-5 if method == integ.METHOD_ROSENBROCK else 1e-7)


def test_output_every_n_steps():
    ts, ys, n_out, status, t_last, y_last, stats = _run(integ.METHOD_DOPRI5, 5.0, 1e-9, 1e-12, every=7)[:7]
    naccept = stats[integ.STAT_NACCEPT]
    assert n_out == 1 + naccept // 7 + (1 if naccept % 7 else 0)
    assert ts[0] == 0.0 and ts[n_out - 1] == 5.0
    assert np.all(np.diff(ts[:n_out]) > 0)
    np.testing.assert_allclose(ys[n_out - 1], expm(5.0 * A) @ Y0, rtol=0, atol=1e-8)


def test_rosenbrock_on_stiff_van_der_pol():
    mu = np.array([1000.0])
    y0 = np.array([2.0, 0.0])
    ref = solve_ivp(lambda t, y: [y[1], mu[0] * (1 - y[0] ** 2) * y[1] - y[0]], (0.0, 1500.0), y0, method="Radau",
                    rtol=1e-10, atol=1e-12)
    out = _run(integ.METHOD_ROSENBROCK, 1500.0, 1e-7, 1e-10, p=mu, y0=y0, kind=kernels.KIND_VAN_DER_POL)
    assert out[3] == integ.STATUS_OK
    assert out[5][0] == pytest.approx(ref.y[0, -1], rel=1e-4)
    # the explicit pair is stability-bound: it needs many times the Rosenbrock steps
    explicit = _run(integ.METHOD_DOPRI5, 1500.0, 1e-7, 1e-10, p=mu, y0=y0, kind=kernels.KIND_VAN_DER_POL)
    assert explicit[6][integ.STAT_NACCEPT] > 20 * out[6][integ.STAT_NACCEPT]


@pytest.mark.parametrize("method", [integ.METHOD_DOPRI5, integ.METHOD_ROSENBROCK])
def test_blow_up_is_reported_not_returned(method):
    p = np.array([1.0, 5.0])  # y' = 5 y
    out = _run(method, 100.0, 1e-8, 1e-10, p=p, y0=np.array([1.0]), max_norm=1e6)
    ts, ys, n_out, status, t_last, y_last = out[:6]
    assert status == integ.STATUS_BLOW_UP
    assert np.all(np.isfinite(y_last)) and abs(y_last[0]) <= 1e6
    assert t_last < 100.0
