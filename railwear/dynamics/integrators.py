"""Compiled ODE integrators with the model's right-hand side in the loop (numba, ``cache=True``).

``integrate`` advances ``y' = f(t, y)`` of the model ``kind`` (see ``railwear.dynamics.kernels``)
with one of three embedded methods and adaptive steps (``railwear.dynamics.Integrator`` is its
Python face: the options and the result named):

- ``METHOD_DOPRI5``: Dormand-Prince 5(4) (Dormand & Prince 1980), local extrapolation, FSAL, the
  fourth-order continuous extension (Hairer, Norsett & Wanner, Solving ODE I, II.6);
- ``METHOD_DOP853``: Dormand-Prince 8(5,3) (Prince & Dormand 1981; Hairer, Norsett & Wanner,
  II.10): 12 stages of order 8, FSAL, the error estimate of order 5 corrected by the one of
  order 3, and the seventh-order continuous extension (three extra stages, evaluated only for
  steps that need dense output);
- ``METHOD_ROSENBROCK``: the linearly implicit Rosenbrock 2(3) pair with ``W = I - h d J``,
  ``d = 1/(2 + sqrt 2)`` (Shampine & Reichelt 1997, MATLAB's ode23s), L-stable, for stiff
  creep; Jacobian by forward differences, its own quadratic dense output.

Error control: weighted RMS norm ``|e_i| / (atol + rtol max(|y_i|, |y_new_i|))``. Output either at
requested times (dense output) or every ``every`` accepted steps. Sign changes of the model's
event function (contact loss and regain of the disk wheel) are located on the dense output by the
Illinois method and the step is cut there, so no step straddles the kink.

Switches (``kernels.switching``: the flange contact of the conical wheelset and bogie, where the
right-hand side has a kink): a rejected step across a sign change of the switching function is
retried up to just past the switch (located on the step's cubic Hermite interpolant; if that
retry is rejected too, once more at the switch located in it), and the step after it starts
again at the first rejected step's size. A step across a kink has a local error of
low order whatever the method, so without this each switch costs several rejections.
"""

from __future__ import annotations

import math

import numpy as np
from numba import literally, njit
from numba.core import types
from numba.extending import overload

from railwear.dynamics.kernels import (ByLiteral, contact_power, event_call, model_has, patch_half_angle, rhs_call,
                                       rhs_inline, sweep, switching_inline)

METHOD_DOPRI5 = 0
METHOD_ROSENBROCK = 1
METHOD_DOP853 = 2
# the method names of ``railwear.dynamics.simulate``
METHODS = {"dopri5": METHOD_DOPRI5, "dop853": METHOD_DOP853, "rosenbrock": METHOD_ROSENBROCK}

STATUS_OK = 0
STATUS_MAX_STEPS = 1
STATUS_STEP_TOO_SMALL = 2
STATUS_BLOW_UP = 3

# statistics array layout
STAT_NFEV = 0
STAT_NACCEPT = 1
STAT_NREJECT = 2
STAT_NJAC = 3
STAT_NEVENTS = 4

# Dormand-Prince 5(4) tableau
_C = np.array([0.0, 1 / 5, 3 / 10, 4 / 5, 8 / 9, 1.0, 1.0])
_A = np.array(
    [
        [0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
        [1 / 5, 0.0, 0.0, 0.0, 0.0, 0.0],
        [3 / 40, 9 / 40, 0.0, 0.0, 0.0, 0.0],
        [44 / 45, -56 / 15, 32 / 9, 0.0, 0.0, 0.0],
        [19372 / 6561, -25360 / 2187, 64448 / 6561, -212 / 729, 0.0, 0.0],
        [9017 / 3168, -355 / 33, 46732 / 5247, 49 / 176, -5103 / 18656, 0.0],
        [35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84],
    ]
)
_B = np.array([35 / 384, 0.0, 500 / 1113, 125 / 192, -2187 / 6784, 11 / 84, 0.0])
_E = np.array([71 / 57600, 0.0, -71 / 16695, 71 / 1920, -17253 / 339200, 22 / 525, -1 / 40])
# continuous extension: y(t + s h) = y + h sum_j (K^T P)[:, j] s^(j+1)
_P = np.array(
    [
        [1.0, -8048581381 / 2820520608, 8663915743 / 2820520608, -12715105075 / 11282082432],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, 131558114200 / 32700410799, -68118460800 / 10900136933, 87487479700 / 32700410799],
        [0.0, -1754552775 / 470086768, 14199869525 / 1410260304, -10690763975 / 1880347072],
        [0.0, 127303824393 / 49829197408, -318862633887 / 49829197408, 701980252875 / 199316789632],
        [0.0, -282668133 / 205662961, 2019193451 / 616988883, -1453857185 / 822651844],
        [0.0, 40617522 / 29380423, -110615467 / 29380423, 69997945 / 29380423],
    ]
)
# Dormand-Prince 8(5,3) (Hairer, Norsett & Wanner, Solving ODE I, 2nd ed., II.10, and their DOP853
# constants). Stages 0-11 make the step, stage 12 is f at the new point (FSAL), stages 13-15 are
# the extra stages of the continuous extension.
_D8_C = np.array([0.0, 0.05260015195876773, 0.0789002279381516, 0.1183503419072274, 0.2816496580927726,
                  1 / 3, 0.25, 4 / 13, 0.6512820512820513, 0.6, 6 / 7, 1.0, 1.0, 0.1, 0.2, 7 / 9])
_D8_ROWS = (
    (0.05260015195876773,),
    (0.0197250569845379, 0.0591751709536137),
    (0.02958758547680685, 0.0, 0.08876275643042054),
    (0.2413651341592667, 0.0, -0.8845494793282861, 0.924834003261792),
    (0.037037037037037035, 0.0, 0.0, 0.17082860872947386, 0.12546768756682242),
    (0.037109375, 0.0, 0.0, 0.17025221101954405, 0.06021653898045596, -0.017578125),
    (0.03709200011850479, 0.0, 0.0, 0.17038392571223998, 0.10726203044637328, -0.015319437748624402,
     0.008273789163814023),
    (0.6241109587160757, 0.0, 0.0, -3.3608926294469414, -0.868219346841726, 27.59209969944671,
     20.154067550477894, -43.48988418106996),
    (0.47766253643826434, 0.0, 0.0, -2.4881146199716677, -0.590290826836843, 21.230051448181193,
     15.279233632882423, -33.28821096898486, -0.020331201708508627),
    (-0.9371424300859873, 0.0, 0.0, 5.186372428844064, 1.0914373489967295, -8.149787010746927,
     -18.52006565999696, 22.739487099350505, 2.4936055526796523, -3.0467644718982196),
    (2.273310147516538, 0.0, 0.0, -10.53449546673725, -2.0008720582248625, -17.9589318631188,
     27.94888452941996, -2.8589982771350235, -8.87285693353063, 12.360567175794303, 0.6433927460157636),
    # the eighth-order weights b
    (0.054293734116568765, 0.0, 0.0, 0.0, 0.0, 4.450312892752409, 1.8915178993145003, -5.801203960010585,
     0.3111643669578199, -0.1521609496625161, 0.20136540080403034, 0.04471061572777259),
    (0.056167502283047954, 0.0, 0.0, 0.0, 0.0, 0.0, 0.25350021021662483, -0.2462390374708025,
     -0.12419142326381637, 0.15329179827876568, 0.00820105229563469, 0.007567897660545699, -0.008298),
    (0.03183464816350214, 0.0, 0.0, 0.0, 0.0, 0.028300909672366776, 0.053541988307438566,
     -0.05492374857139099, 0.0, 0.0, -0.00010834732869724932, 0.0003825710908356584,
     -0.00034046500868740456, 0.1413124436746325),
    (-0.42889630158379194, 0.0, 0.0, 0.0, 0.0, -4.697621415361164, 7.683421196062599, 4.06898981839711,
     0.3567271874552811, 0.0, 0.0, 0.0, -0.0013990241651590145, 2.9475147891527724, -9.15095847217987),
)
_D8_A = np.zeros((16, 16))
for _row, _coefficients in enumerate(_D8_ROWS, start=1):
    _D8_A[_row, :_row] = _coefficients
_D8_B = _D8_A[12, :12].copy()
# fifth-order error estimate b - b^(5); third-order one b - b^(3), b^(3) = (31/127, 0.7338..., 3/136)
_D8_E5 = np.array([0.01312004499419488, 0.0, 0.0, 0.0, 0.0, -1.2251564463762044, -0.4957589496572502,
                   1.6643771824549864, -0.35032884874997366, 0.3341791187130175, 0.08192320648511571,
                   -0.022355307863886294])
_D8_E3 = _D8_B.copy()
_D8_E3[0] -= 0.2440944881889764
_D8_E3[8] -= 0.7338466882816118
_D8_E3[11] -= 0.022058823529411766
# continuous extension y + theta (r0 + (1 - theta)(r1 + theta (r2 + (1 - theta)(r3 + ...)))) with
# r0 = y_new - y, r1 = h f0 - r0, r2 = r0 - h f_new - r1 and r3..r6 = h sum_j D[:, j] k_j
_D8_D = np.array([
    [-8.428938276109013, 0.0, 0.0, 0.0, 0.0, 0.5667149535193777, -3.0689499459498917, 2.38466765651207,
     2.117034582445028, -0.871391583777973, 2.2404374302607883, 0.6315787787694688, -0.08899033645133331,
     18.148505520854727, -9.194632392478356, -4.436036387594894],
    [10.427508642579134, 0.0, 0.0, 0.0, 0.0, 242.28349177525817, 165.20045171727028, -374.5467547226902,
     -22.113666853125306, 7.733432668472264, -30.674084731089398, -9.332130526430229, 15.697238121770845,
     -31.139403219565178, -9.35292435884448, 35.81684148639408],
    [19.985053242002433, 0.0, 0.0, 0.0, 0.0, -387.0373087493518, -189.17813819516758, 527.8081592054236,
     -11.57390253995963, 6.8812326946963, -1.0006050966910838, 0.7777137798053443, -2.778205752353508,
     -60.19669523126412, 84.32040550667716, 11.99229113618279],
    [-25.69393346270375, 0.0, 0.0, 0.0, 0.0, -154.18974869023643, -231.5293791760455, 357.6391179106141,
     93.40532418362432, -37.45832313645163, 104.0996495089623, 29.8402934266605, -43.53345659001114,
     96.32455395918828, -39.17726167561544, -149.72683625798564],
])


def _nested_to_powers(n_terms):
    """Power coefficients (theta^1 .. theta^n_terms) of the nested basis ``theta^ceil((m+1)/2)
    (1 - theta)^floor((m+1)/2)``, ``m = 0 .. n_terms - 1``, one row per basis polynomial."""
    out = np.zeros((n_terms, n_terms))
    for m in range(n_terms):
        poly = np.polynomial.polynomial.polypow([1.0, -1.0], (m + 1) // 2)
        poly = np.concatenate([np.zeros(m // 2 + 1), poly])  # times theta^(m//2 + 1)
        out[m, :poly.size - 1] = poly[1:]
    return out


_D8_POWERS = _nested_to_powers(7)
DENSE_TERMS = 7  # columns of the dense-output coefficients (the widest interpolant)
_ROS_D = 1.0 / (2.0 + math.sqrt(2.0))
_ROS_E32 = 6.0 + math.sqrt(2.0)


@njit(cache=True)
def _copy(dst, src):
    """``dst[:] = src`` element by element: numba's array assignment compiles a shape check with
    its error message, a large part of the integrator's compile."""
    for i in range(src.shape[0]):
        dst[i] = src[i]


@njit(cache=True)
def _error_norm(err, y, ynew, rtol, atol):
    acc = 0.0
    for i in range(y.shape[0]):
        scale = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        acc += (err[i] / scale) ** 2
    return math.sqrt(acc / y.shape[0])


@njit(cache=True)
def _all_finite(y):
    for i in range(y.shape[0]):
        if not math.isfinite(y[i]):
            return False
    return True


@njit(cache=True)
def _dense(y, h, q, s, out):
    """``out = y + h sum_j q[:, j] s^(j+1)`` (every method's interpolant has this form)."""
    m = q.shape[1]
    for i in range(y.shape[0]):
        acc = q[i, m - 1]
        for j in range(m - 2, -1, -1):
            acc = q[i, j] + s * acc
        out[i] = y[i] + h * s * acc


@njit(cache=True)
def _dopri_dense(k, q):
    """Dense-output coefficients ``q = K^T P`` of the last Dormand-Prince step (only when needed)."""
    for i in range(q.shape[0]):
        for c in range(4):
            acc = 0.0
            for j in range(7):
                acc += k[j, i] * _P[j, c]
            q[i, c] = acc


@njit(cache=True, inline="always")
def _stage_state(a, s, y, h, k, tmp):
    """``tmp = y + h sum_(j < s) a[s, j] k[j]``: where stage ``s`` evaluates the RHS."""
    for i in range(y.shape[0]):
        acc = 0.0
        for j in range(s):
            acc += a[s, j] * k[j, i]
        tmp[i] = y[i] + h * acc


@njit(cache=True, inline="always")
def _explicit_step(kind, p, surf, t, y, f0, h, a, c, n_stages, ynew, fnew, k, tmp):
    """Stages ``k[:n_stages]`` of an explicit FSAL pair (tableau ``a``, nodes ``c``): the last stage
    is evaluated at the new solution, which goes to ``ynew``, and its RHS to ``fnew``. The model is
    called, not inlined: inlined twice (both explicit methods) it took most of a cold compile."""
    _copy(k[0], f0)
    for s in range(1, n_stages):
        _stage_state(a, s, y, h, k, tmp)
        rhs_call(kind, t + c[s] * h, tmp, p, surf, k[s])
    _copy(ynew, tmp)
    _copy(fnew, k[n_stages - 1])


@njit(cache=True)
def _combine(weights, k, h, out):
    """``out = h sum_j weights[j] k[j]`` (an error estimate from the stages)."""
    for i in range(out.shape[0]):
        acc = 0.0
        for j in range(weights.shape[0]):
            acc += weights[j] * k[j, i]
        out[i] = h * acc


@njit(cache=True)
def _dop853_error_norm(err5, err3, y, ynew, rtol, atol):
    """Error measure of DOP853 (Hairer, Norsett & Wanner II.10): ``|e5|^2 / sqrt(n (|e5|^2 +
    0.01 |e3|^2))`` in the weighted norm; it behaves as ``h^8``."""
    a5 = 0.0
    a3 = 0.0
    for i in range(y.shape[0]):
        scale = atol + rtol * max(abs(y[i]), abs(ynew[i]))
        a5 += (err5[i] / scale) ** 2
        a3 += (err3[i] / scale) ** 2
    den = a5 + 0.01 * a3
    if den <= 0.0:
        return 0.0
    return a5 / math.sqrt(den * y.shape[0])


@njit(cache=True)
def _dop853_dense(kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    """Dense-output coefficients of the last DOP853 step from its stages ``k[:13]``: the three extra
    stages into ``k[13:16]``, then the nested interpolant ``r`` converted to powers of ``s``."""
    literally(kind)
    n = y.shape[0]
    for s in range(13, 16):
        _stage_state(_D8_A, s, y, h, k, tmp)
        rhs_call(kind, t + _D8_C[s] * h, tmp, p, surf, k[s])
    for i in range(n):
        r[0] = ynew[i] - y[i]
        r[1] = h * k[0, i] - r[0]
        r[2] = r[0] - h * k[12, i] - r[1]
        for m in range(4):
            acc = 0.0
            for j in range(16):
                acc += _D8_D[m, j] * k[j, i]
            r[3 + m] = h * acc
        for c in range(7):
            acc = 0.0
            for m in range(7):
                acc += r[m] * _D8_POWERS[m, c]
            q[i, c] = acc / h


@njit(cache=True)
def _lu_factor(a, piv):
    """In-place LU with partial pivoting; returns False if singular."""
    n = a.shape[0]
    for col in range(n):
        best = col
        for r in range(col + 1, n):
            if abs(a[r, col]) > abs(a[best, col]):
                best = r
        piv[col] = best
        if a[best, col] == 0.0:
            return False
        if best != col:
            for c in range(n):
                a[col, c], a[best, c] = a[best, c], a[col, c]
        for r in range(col + 1, n):
            a[r, col] /= a[col, col]
            for c in range(col + 1, n):
                a[r, c] -= a[r, col] * a[col, c]
    return True


@njit(cache=True)
def _lu_solve(lu, piv, b):
    """Solve in place ``lu x = b`` (``b`` overwritten by ``x``)."""
    n = lu.shape[0]
    for i in range(n):
        j = piv[i]
        if j != i:
            b[i], b[j] = b[j], b[i]
    for i in range(n):
        for j in range(i):
            b[i] -= lu[i, j] * b[j]
    for i in range(n - 1, -1, -1):
        for j in range(i + 1, n):
            b[i] -= lu[i, j] * b[j]
        b[i] /= lu[i, i]


@njit(cache=True)
def _jacobian(kind, p, surf, t, y, f0, rtol, atol, jac, dfdt, tmp, ftmp):
    """Forward-difference Jacobian ``df/dy`` and ``df/dt``; two-sided scale ``max(|y|, atol/rtol)``."""
    literally(kind)
    n = y.shape[0]
    root_eps = 1.4901161193847656e-08
    for j in range(n):
        _copy(tmp, y)
        delta = root_eps * max(abs(y[j]), atol / rtol)
        tmp[j] = y[j] + delta
        delta = tmp[j] - y[j]
        rhs_call(kind, t, tmp, p, surf, ftmp)
        for i in range(n):
            jac[i, j] = (ftmp[i] - f0[i]) / delta
    dt = root_eps * max(abs(t), 1e-3)
    rhs_call(kind, t + dt, y, p, surf, ftmp)
    for i in range(n):
        dfdt[i] = (ftmp[i] - f0[i]) / dt


@njit(cache=True)
def _rosenbrock_step(kind, p, surf, t, y, f0, h, ynew, fnew, err, q, jac, dfdt, w, piv, k1, k2, tmp, f1):
    """One step of the Rosenbrock 2(3) pair; returns False if ``W`` is singular."""
    literally(kind)
    n = y.shape[0]
    d = _ROS_D
    for i in range(n):
        for j in range(n):
            w[i, j] = -h * d * jac[i, j]
        w[i, i] += 1.0
    if not _lu_factor(w, piv):
        return False
    for i in range(n):
        k1[i] = f0[i] + h * d * dfdt[i]
    _lu_solve(w, piv, k1)
    for i in range(n):
        tmp[i] = y[i] + 0.5 * h * k1[i]
    rhs_call(kind, t + 0.5 * h, tmp, p, surf, f1)
    for i in range(n):
        k2[i] = f1[i] - k1[i]
    _lu_solve(w, piv, k2)
    for i in range(n):
        k2[i] += k1[i]
        ynew[i] = y[i] + h * k2[i]
    rhs_call(kind, t + h, ynew, p, surf, fnew)
    for i in range(n):
        tmp[i] = fnew[i] - _ROS_E32 * (k2[i] - f1[i]) - 2.0 * (k1[i] - f0[i]) + h * d * dfdt[i]
    _lu_solve(w, piv, tmp)  # tmp = k3
    c = 1.0 / (1.0 - 2.0 * d)
    for i in range(n):
        err[i] = h / 6.0 * (k1[i] - 2.0 * k2[i] + tmp[i])
        q[i, 0] = c * (k1[i] - 2.0 * d * k2[i])
        q[i, 1] = c * (k2[i] - k1[i])
        q[i, 2] = 0.0
        q[i, 3] = 0.0
    return True


# ---- the method's parts, picked when the loop is typed ------------------------------------------
# ``integrate`` takes the method as a compile-time constant (as it does the model kind). numba
# prunes no branch on the value of a constant integer argument, only on an argument that is None,
# so the loop takes ``implicit`` and ``eighth`` (None unless the method is Rosenbrock's or DOP853:
# a DOPRI5 loop compiles neither's step), and the dense output, which the loop calls for both
# explicit methods, is chosen here when the loop is typed, so a DOPRI5 run does not compile
# DOP853's three extra stages.
# The Rosenbrock arrays stay allocated in the loop: taken from a tuple, that loop ran 15 % slower.


def _by_method(method, impls):
    """The implementation in ``impls`` (method number -> function) for the constant ``method``
    (a numba integer literal type); None (no match) otherwise."""
    if not isinstance(method, types.IntegerLiteral):
        return None
    return impls[method.literal_value]


def _explicit_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    """Dense-output coefficients of the last explicit step into ``q``; returns the extra RHS
    evaluations. (The Rosenbrock step builds its own; compiled code only.)"""
    raise TypeError("_explicit_dense is for compiled code")


def _dopri5_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    _dopri_dense(k, q)
    return 0


def _dop853_dense_counted(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    _dop853_dense(kind, p, surf, t, y, h, ynew, k, q, tmp, r)
    return 3


def _rosenbrock_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    return 0  # never called: the Rosenbrock step leaves its coefficients in ``q``


@overload(_explicit_dense, inline="always", prefer_literal=True)
def _explicit_dense_of(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r):
    return _by_method(method, {METHOD_DOPRI5: _dopri5_dense, METHOD_DOP853: _dop853_dense_counted,
                               METHOD_ROSENBROCK: _rosenbrock_dense})


def _method_is(method, which):
    """True where the constant ``method`` is ``which``, None otherwise: an argument of the loop on
    which numba prunes the other methods' branches (compiled code only)."""
    raise TypeError("_method_is is for compiled code")


@overload(_method_is, inline="always", prefer_literal=True)
def _method_is_of(method, which):
    if not (isinstance(method, types.IntegerLiteral) and isinstance(which, types.IntegerLiteral)):
        return None
    if method.literal_value == which.literal_value:
        return lambda method, which: True
    return lambda method, which: None


@njit(cache=True)
def _grow(ts, ys, n_used):
    ts2 = np.empty(2 * ts.shape[0])
    ys2 = np.empty((2 * ts.shape[0], ys.shape[1]))
    for j in range(n_used):
        ts2[j] = ts[j]
        _copy(ys2[j], ys[j])
    return ts2, ys2


@njit(cache=True)
def _hermite(y, ynew, f0, fnew, h, q):
    """Cubic Hermite interpolant of a step from its end values and slopes, as ``_dense``
    coefficients (for locating a switch in a rejected step, whose own interpolant is not built)."""
    for i in range(q.shape[0]):
        for c in range(3, q.shape[1]):
            q[i, c] = 0.0
    for i in range(y.shape[0]):
        d = (ynew[i] - y[i]) / h
        q[i, 0] = f0[i]
        q[i, 1] = 3.0 * d - 2.0 * f0[i] - fnew[i]
        q[i, 2] = f0[i] + fnew[i] - 2.0 * d


@njit(cache=True)
def _locate_event(kind, p, surf, t, y, h, q, g_lo, g_hi, tmp, switch):
    """Illinois root of the event function (``switch``: of the switching function) on the step's
    interpolant; returns ``s`` in (0, 1] on the far side of the root (the new sign)."""
    literally(kind)
    s_lo, s_hi = 0.0, 1.0
    side = 0
    for _ in range(100):
        s = s_hi - g_hi * (s_hi - s_lo) / (g_hi - g_lo)
        if not (s > s_lo and s < s_hi):
            s = 0.5 * (s_lo + s_hi)
        _dense(y, h, q, s, tmp)
        if switch:
            g = switching_inline(kind, t + s * h, tmp, p, surf)
        else:
            g = event_call(kind, t + s * h, tmp, p, surf)
        if (g > 0.0) == (g_hi > 0.0) and g != 0.0:
            s_hi, g_hi = s, g
            if side == 1:
                g_lo *= 0.5
            side = 1
        else:
            s_lo, g_lo = s, g
            if side == -1:
                g_hi *= 0.5
            side = -1
        if (s_hi - s_lo) * abs(h) <= 1e-13 * max(abs(t), abs(h)) + 1e-15:
            break
    return s_hi


# three-point Gauss-Legendre rule on [0, 1]
_GAUSS_NODES = np.array([0.5 - 0.5 * math.sqrt(0.6), 0.5, 0.5 + 0.5 * math.sqrt(0.6)])
_GAUSS_WEIGHTS = np.array([5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0])


@njit(cache=True)
def _deposit_step(kind, p, surf, t, y, h, q, s_end, energy, tmp):
    """Frictional energy of the step ``[t, t + s_end h]`` onto the wheel cells. The step is cut
    into pieces in which the contact moves by at most one cell; on each, the energy is the
    three-point Gauss-Legendre integral of the power on the step's interpolant, swept over the
    cells as the patch moves linearly between the piece's end angles."""
    literally(kind)
    dx = 2.0 * math.pi / energy.shape[0]
    w = patch_half_angle(kind, p)
    _dense(y, h, q, 0.0, tmp)
    x_start, _ = contact_power(kind, t, tmp, p, surf)
    _dense(y, h, q, s_end, tmp)
    x_end, _ = contact_power(kind, t + s_end * h, tmp, p, surf)
    pieces = max(1, int(math.ceil(abs(x_end - x_start) / dx)))
    ds = s_end / pieces
    xa = x_start
    for m in range(pieces):
        s0 = m * ds
        amount = 0.0
        for g in range(3):
            s = s0 + ds * _GAUSS_NODES[g]
            _dense(y, h, q, s, tmp)
            _, power = contact_power(kind, t + s * h, tmp, p, surf)
            amount += _GAUSS_WEIGHTS[g] * power
        amount *= ds * h
        _dense(y, h, q, s0 + ds, tmp)
        xb, _ = contact_power(kind, t + (s0 + ds) * h, tmp, p, surf)
        sweep(energy, xa, xb, w, amount)
        xa = xb


@njit(cache=True, nogil=True)
def _integrate(kind, p, surf, y0, t0, t_end, rtol, atol, method, h0, h_max, max_steps, t_eval, every, use_events, max_norm,
              energy, cut_at_switches=True, clock=None):
    """Integrate model ``kind`` from ``t0`` to ``t_end``.

    ``energy`` (one value per wheel cell, or empty for none): the frictional energy of the run
    [J] is added to it, cell by cell, as the contact patch passes (disk wheel; other models leave
    it).
    Returns ``(ts, ys, n_out, status, t_last, y_last, stats, event_t, event_y, event_dir)``:
    output times and states (first ``n_out`` rows), a status code (``STATUS_*``), the last
    accepted time and state, counters (``STAT_*``) and the located events (direction +1 when
    the event function turns positive, e.g. contact regained; -1 contact lost).
    With ``t_eval`` non-empty the output is at those times (ascending, within ``[t0, t_end]``),
    otherwise at ``t0``, every ``every`` accepted steps and ``t_end``.
    ``cut_at_switches``: retry a rejected step that crosses a switch (``kernels.switching``) up to
    the switch (see the module notes); ``False`` only to measure what it saves.
    ``clock`` (a float64 array of one element, or omitted): the time of the last accepted step is
    written to ``clock[0]`` as the run goes, for a progress display; the loop runs without the GIL,
    so a Python thread can read it meanwhile. Writing it changes no number.
    ``kind`` and ``method`` are compile-time constants: a run compiles its model and its method.
    """
    literally(kind)
    literally(method)
    return _loop(kind, p, surf, y0, t0, t_end, rtol, atol, method, h0, h_max, max_steps, t_eval, every, use_events,
                 max_norm, energy, cut_at_switches, clock, _method_is(method, METHOD_ROSENBROCK),
                 _method_is(method, METHOD_DOP853), model_has(kind, "cells"),
                 model_has(kind, "events"), model_has(kind, "switches"))


@njit(cache=True, nogil=True)
def _loop(kind, p, surf, y0, t0, t_end, rtol, atol, method, h0, h_max, max_steps, t_eval, every, use_events, max_norm,
          energy, cut_at_switches, clock, implicit, eighth, cells, events, switches):
    """The loop of ``_integrate``. ``implicit``: True for the Rosenbrock method, else None;
    ``eighth``: True for DOP853, else None; ``cells``, ``events``, ``switches``: True where the
    model has a contact power on the wheel's cells, an event function, a switching function
    (``kernels.model_has``), else None: ``energy`` is then not touched, and there is no event and
    no switch to cut a step at, as with their constant functions. numba prunes a branch on an
    argument that is None when the function is typed (never on a constant's value), so a DOPRI5
    loop compiles neither the Rosenbrock step and Jacobian nor DOP853's stages and error measure,
    nor a model's missing parts."""
    literally(kind)
    literally(method)
    n = y0.shape[0]
    stats = np.zeros(5, dtype=np.int64)
    dense_mode = t_eval.shape[0] > 0
    cap = t_eval.shape[0] if dense_mode else 1024
    ts = np.empty(cap)
    ys = np.empty((cap, n))
    ev_cap = 64
    ev_t = np.empty(ev_cap)
    ev_y = np.empty((ev_cap, n))
    ev_dir = np.empty(ev_cap, dtype=np.int64)
    # counters and flags passed to compiled calls as numpy scalars, not constants: numba types a
    # callee once per constant value (``_grow`` for 0 and again for int64, ``_locate_event`` for
    # True and for False), which a cold start paid twice
    n_ev = np.int64(0)

    y = y0.copy()
    t = t0
    ynew = np.empty(n)
    f0 = np.empty(n)
    fnew = np.empty(n)
    err = np.empty(n)
    tmp = np.empty(n)
    q = np.zeros((n, DENSE_TERMS if method == METHOD_DOP853 else 4))
    k = np.empty((16 if method == METHOD_DOP853 else 7, n))
    r = np.empty(DENSE_TERMS)
    jac = np.empty((n, n))
    dfdt = np.empty(n)
    w = np.empty((n, n))
    piv = np.empty(n, dtype=np.int64)
    k1 = np.empty(n)
    k2 = np.empty(n)
    f1 = np.empty(n)

    rhs_call(kind, t, y, p, surf, f0)
    stats[STAT_NFEV] += 1
    n_out = np.int64(0)
    i_eval = 0
    if dense_mode:
        while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t0:
            ts[n_out] = t_eval[i_eval]
            _copy(ys[n_out], y)
            n_out += 1
            i_eval += 1
    else:
        ts[0] = t0
        _copy(ys[0], y)
        n_out = 1

    order = 5.0 if method == METHOD_DOPRI5 else (8.0 if method == METHOD_DOP853 else 3.0)
    span = t_end - t0
    # initial step (Hairer, Norsett & Wanner, II.4)
    h = h0
    if h <= 0.0:
        d0 = 0.0
        d1 = 0.0
        for i in range(n):
            sc = atol + rtol * abs(y[i])
            d0 += (y[i] / sc) ** 2
            d1 += (f0[i] / sc) ** 2
        d0 = math.sqrt(d0 / n)
        d1 = math.sqrt(d1 / n)
        h = 1e-6 if (d0 < 1e-5 or d1 < 1e-5) else 0.01 * d0 / d1
        h = min(h, span)
        for i in range(n):
            tmp[i] = y[i] + h * f0[i]
        rhs_call(kind, t + h, tmp, p, surf, fnew)
        stats[STAT_NFEV] += 1
        d2 = 0.0
        for i in range(n):
            sc = atol + rtol * abs(y[i])
            d2 += ((fnew[i] - f0[i]) / sc) ** 2
        d2 = math.sqrt(d2 / n) / h
        if max(d1, d2) <= 1e-15:
            h1 = max(1e-6, h * 1e-3)
        else:
            h1 = (0.01 / max(d1, d2)) ** (1.0 / order)
        h = min(100.0 * h, h1)
    h = min(h, h_max, span)

    g_old = 1.0
    if events is not None:
        if use_events:
            g_old = event_call(kind, t, y, p, surf)
    status = STATUS_OK
    jac_fresh = False
    fac_max = 5.0
    h_resume = 0.0  # after a step cut at a switch: the step size to go on with
    cuts = 0  # cuts of the current step (at most two: the second at the root of the first's retry)
    steps = 0
    while t < t_end:
        if steps >= max_steps:
            status = STATUS_MAX_STEPS
            break
        steps += 1
        last = False
        if t + h >= t_end or t + 1.01 * h >= t_end:
            h = t_end - t
            last = True
        if h <= 1e-14 * max(abs(t), abs(span)) and not last:  # a short last step is harmless
            status = STATUS_STEP_TOO_SMALL
            break
        ok = True
        if implicit is not None:
            if not jac_fresh:
                _jacobian(kind, p, surf, t, y, f0, rtol, atol, jac, dfdt, tmp, f1)
                stats[STAT_NFEV] += n + 1
                stats[STAT_NJAC] += 1
                jac_fresh = True
            ok = _rosenbrock_step(kind, p, surf, t, y, f0, h, ynew, fnew, err, q, jac, dfdt, w, piv, k1, k2, tmp, f1)
            stats[STAT_NFEV] += 2
        elif eighth is not None:
            _explicit_step(kind, p, surf, t, y, f0, h, _D8_A, _D8_C, 13, ynew, fnew, k, tmp)
            _combine(_D8_E5, k, h, err)
            _combine(_D8_E3, k, h, k1)  # the third-order estimate
            stats[STAT_NFEV] += 12
            if not _all_finite(k1):
                ok = False
        else:
            _explicit_step(kind, p, surf, t, y, f0, h, _A, _C, 7, ynew, fnew, k, tmp)
            _combine(_E, k, h, err)
            stats[STAT_NFEV] += 6
        if not ok or not _all_finite(ynew) or not _all_finite(err):
            stats[STAT_NREJECT] += 1
            h *= 0.25
            fac_max = 1.0
            continue
        if eighth is not None:
            en = _dop853_error_norm(err, k1, y, ynew, rtol, atol)
        else:
            en = _error_norm(err, y, ynew, rtol, atol)
        if en > 1.0:
            stats[STAT_NREJECT] += 1
            if switches is not None:
                if cut_at_switches and cuts < 2:
                    g_a = switching_inline(kind, t, y, p, surf)
                    g_b = switching_inline(kind, t + h, ynew, p, surf)
                    if (g_a > 0.0) != (g_b > 0.0) and g_a != 0.0 and g_b != 0.0:
                        # a kink inside: retry up to just past it, then go on with this step size
                        _hermite(y, ynew, f0, fnew, h, q)
                        s_cut = _locate_event(kind, p, surf, t, y, h, q, g_a, g_b, tmp, np.bool_(True))
                        if s_cut > 1e-3:
                            if cuts == 0:
                                h_resume = h
                            cuts += 1
                            h *= s_cut
                            continue
            h *= max(0.2, 0.9 * en ** (-1.0 / order))
            fac_max = 1.0
            continue
        # accepted
        t_new = t + h
        if last:
            t_new = t_end
        s_end = 1.0
        hit = 0
        q_ready = method == METHOD_ROSENBROCK
        if events is not None:
            if use_events:
                g_new = event_call(kind, t_new, ynew, p, surf)
                if (g_new > 0.0) != (g_old > 0.0) and g_new != 0.0:
                    if not q_ready:
                        stats[STAT_NFEV] += _explicit_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r)
                        q_ready = True
                    s_end = _locate_event(kind, p, surf, t, y, h, q, g_old, g_new, tmp, np.bool_(False))
                    hit = 1 if g_new > 0.0 else -1
                    if s_end < 1.0:
                        t_new = t + s_end * h
                        _dense(y, h, q, s_end, ynew)
                        rhs_call(kind, t_new, ynew, p, surf, fnew)
                        stats[STAT_NFEV] += 1
                        last = False
                    g_new = event_call(kind, t_new, ynew, p, surf)
                g_old = g_new
        bad = False
        for i in range(n):
            if abs(ynew[i]) > max_norm:
                bad = True
        if bad:
            status = STATUS_BLOW_UP
            break
        stats[STAT_NACCEPT] += 1
        if hit != 0:
            if n_ev == ev_cap:
                ev_t2, ev_y2 = _grow(ev_t, ev_y, n_ev)
                ev_dir2 = np.empty(2 * ev_cap, dtype=np.int64)
                for j in range(n_ev):
                    ev_dir2[j] = ev_dir[j]
                ev_t, ev_y, ev_dir = ev_t2, ev_y2, ev_dir2
                ev_cap *= 2
            ev_t[n_ev] = t_new
            _copy(ev_y[n_ev], ynew)
            ev_dir[n_ev] = hit
            n_ev += 1
        if cells is not None:
            if energy.shape[0] > 0:
                if not q_ready:
                    stats[STAT_NFEV] += _explicit_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r)
                    q_ready = True
                _deposit_step(kind, p, surf, t, y, h, q, s_end, energy, tmp)
        if dense_mode:
            if not q_ready and i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_new:
                stats[STAT_NFEV] += _explicit_dense(method, kind, p, surf, t, y, h, ynew, k, q, tmp, r)
                q_ready = True
            while i_eval < t_eval.shape[0] and t_eval[i_eval] <= t_new:
                s = (t_eval[i_eval] - t) / h
                _dense(y, h, q, s, ys[n_out])
                ts[n_out] = t_eval[i_eval]
                n_out += 1
                i_eval += 1
        elif last or stats[STAT_NACCEPT] % every == 0:
            if n_out == ts.shape[0]:
                ts, ys = _grow(ts, ys, n_out)
            ts[n_out] = t_new
            _copy(ys[n_out], ynew)
            n_out += 1
        fac = min(fac_max, max(0.2, 0.9 * max(en, 1e-10) ** (-1.0 / order)))
        fac_max = 5.0
        t = t_new
        if clock is not None:
            clock[0] = t
        _copy(y, ynew)
        _copy(f0, fnew)
        jac_fresh = False
        if last:
            break
        h = min(max(h * fac, h_resume), h_max)
        h_resume = 0.0
        cuts = 0
    stats[STAT_NEVENTS] = n_ev
    return ts, ys, n_out, status, t, y, stats, ev_t[:n_ev], ev_y[:n_ev], ev_dir[:n_ev]


# from Python: one compiled integrator per model kind and method (arguments 0 and 8, constants)
integrate = ByLiteral(_integrate, _integrate.py_func.__doc__, literal=(0, 8))
