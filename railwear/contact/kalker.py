"""Kalker's creepage coefficients and the linear theory of rolling contact.

Linear theory (Kalker 1967; 1990, App. E), creepages ξ (longitudinal), η (lateral), φ (spin,
1/m), shear modulus G, ``c = sqrt(a b)``:

    Fx = -G c² C11 ξ
    Fy = -G c² C22 η - G c³ C23 φ
    Mz =  G c³ C23 η - G c⁴ C33 φ

Coefficients: Kalker's table (1990, Table E.3) at a/b and b/a = 0.1, 0.2, ..., 1 and Poisson
ratios 0, 0.25, 0.5. Between rows the table is interpolated linearly in ``g = min(a/b, b/a)``
from g = 0.2 up (CONTACT's scheme; the columns are nearly straight there: within 5.4 % of a
smooth curve through the nodes on 0.2-0.3, 2.5 % on 0.3-0.4, 1.4 % above), and by a monotone cubic Hermite between
g = 0.1 and 0.2, where linear interpolation lies up to 17 % above that curve (C23 of long
patches), exact at the nodes and with a continuous slope at both ends (``_first_interval_slopes``).
Between Poisson ratios: the parabola through ``1/C`` at the three tabulated ratios (CONTACT's
scheme). Below g = 0.1 Kalker's slender-ellipse asymptotes are used, scaled by a constant so that
they meet the table at g = 0.1: the raw asymptotes differ from the tabulated g = 0.1 values by up
to 5 %, and railwear keeps the coefficients continuous (CONTACT jumps).

C33 is not in CONTACT's table; railwear carries Kalker's C33 column as reproduced in the
literature (not checked against Kalker's book here). It agrees with Kalker's asymptote
``π²/(16(1-ν)g)`` for a/b = g -> 0 within 6 % at g = 0.1, and with the limit
``π/4 (1-2ν)/(1-ν)`` for b/a -> 0 within 1.3 % at b/a = 0.1 for ν <= 0.25. Its Poisson interpolation is the parabola through C itself: for
patches long in the rolling direction C33 tends to ``π/4 (1-2ν)/(1-ν)``, which vanishes at
ν = 0.5, so 1/C33 is singular there and the parabola through 1/C overshoots (non-monotone in ν
by 1.3 % at b/a = 0.1); the parabola through C is monotone on every tabulated row.

C33 for b/a < 0.1 (ellipse long in the rolling direction): the coefficient tends to the limit
``π/4 (1-2ν)/(1-ν)``; railwear closes the gap between the tabulated g = 0.1 value and that limit
linearly in ``1/Λ``, ``Λ = ln(16/g²)``, the variable of Kalker's expansions. This closure is
railwear's, not Kalker's.
"""

import math
from dataclasses import dataclass

import numpy as np

from railwear.contact._checks import as_float_array, poisson_ratio, positive, scalar_or_array

__all__ = ["kalker_coefficients", "linear_creep_forces", "LinearCreepForces", "KALKER_TABLE"]

_NU_NODES_ARR = np.array([0.0, 0.25, 0.5])
_G_NODES = np.round(np.arange(1, 11) * 0.1, 12)

# Kalker's Table E.3. Index [case][row][coefficient][nu]: case 0 is a/b <= 1 (g = a/b), case 1
# is a/b > 1 (g = b/a); rows g = 0.1 ... 1.0; coefficients C11, C22, C23, C33; nu = 0, 0.25, 0.5.
KALKER_TABLE = np.array(
    [
        [  # a/b <= 1, g = a/b
            [[2.51, 3.31, 4.85], [2.51, 2.52, 2.53], [0.334, 0.473, 0.731], [6.42, 8.28, 11.7]],
            [[2.59, 3.37, 4.81], [2.59, 2.63, 2.66], [0.483, 0.603, 0.809], [3.46, 4.27, 5.66]],
            [[2.68, 3.44, 4.80], [2.68, 2.75, 2.81], [0.607, 0.715, 0.889], [2.49, 2.96, 3.72]],
            [[2.78, 3.53, 4.82], [2.78, 2.88, 2.98], [0.720, 0.823, 0.977], [2.02, 2.32, 2.77]],
            [[2.88, 3.62, 4.83], [2.88, 3.01, 3.14], [0.827, 0.929, 1.07], [1.74, 1.93, 2.22]],
            [[2.98, 3.72, 4.91], [2.98, 3.14, 3.31], [0.930, 1.03, 1.18], [1.56, 1.68, 1.86]],
            [[3.09, 3.81, 4.97], [3.09, 3.28, 3.48], [1.03, 1.14, 1.29], [1.43, 1.50, 1.60]],
            [[3.19, 3.91, 5.05], [3.19, 3.41, 3.65], [1.13, 1.25, 1.40], [1.34, 1.37, 1.42]],
            [[3.29, 4.01, 5.12], [3.29, 3.54, 3.82], [1.23, 1.36, 1.51], [1.27, 1.27, 1.27]],
            [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],
        ],
        [  # a/b > 1, g = b/a
            [[10.7, 11.7, 12.9], [10.7, 12.8, 16.0], [12.2, 14.6, 18.0], [0.795, 0.526, 0.228]],
            [[6.96, 7.78, 8.82], [6.96, 8.14, 9.79], [5.72, 6.63, 7.89], [0.828, 0.601, 0.341]],
            [[5.57, 6.34, 7.34], [5.57, 6.40, 7.51], [3.79, 4.32, 5.01], [0.868, 0.674, 0.446]],
            [[4.84, 5.57, 6.57], [4.84, 5.48, 6.31], [2.88, 3.24, 3.70], [0.912, 0.747, 0.549]],
            [[4.37, 5.10, 6.11], [4.37, 4.90, 5.56], [2.35, 2.62, 2.96], [0.958, 0.819, 0.650]],
            [[4.06, 4.78, 5.80], [4.06, 4.50, 5.04], [2.01, 2.23, 2.50], [1.01, 0.892, 0.751]],
            [[3.82, 4.54, 5.58], [3.82, 4.21, 4.67], [1.76, 1.95, 2.18], [1.05, 0.965, 0.852]],
            [[3.65, 4.36, 5.42], [3.65, 3.99, 4.39], [1.58, 1.75, 1.94], [1.10, 1.04, 0.954]],
            [[3.51, 4.22, 5.30], [3.51, 3.81, 4.16], [1.44, 1.59, 1.77], [1.16, 1.11, 1.06]],
            [[3.40, 4.12, 5.20], [3.40, 3.67, 3.98], [1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],
        ],
    ]
)


_LN4 = np.log(4.0)
_LAMBDA_01 = np.log(16.0 / 0.01)


def _lagrange_nu(v0, v25, v50, nu):
    """Parabola through values at nu = 0, 0.25, 0.5 (Lagrange form; exact at the nodes)."""
    return 8.0 * (nu - 0.25) * (nu - 0.5) * v0 - 16.0 * nu * (nu - 0.5) * v25 + 8.0 * nu * (nu - 0.25) * v50


def _asymptote(case, k, g, nu, log=math.log, sqrt=math.sqrt):
    """Kalker's slender-ellipse asymptote of coefficient k (0..3; case 1 only k < 3) at g, nu
    (scalars; the C library's ``log``)."""
    lam = log(16.0 / (g * g))
    if case == 0:  # a/b = g -> 0, patch short in the rolling direction
        if k == 0:
            return np.pi**2 / (4.0 * (1.0 - nu))
        if k == 1:
            return np.pi**2 / 4.0
        if k == 2:
            return np.pi * sqrt(g) / (3.0 * (1.0 - nu)) * (1.0 + nu * (0.5 * lam + _LN4 - 5.0))
        return np.pi**2 / (16.0 * (1.0 - nu) * g)
    # b/a = g -> 0, patch long in the rolling direction
    if k == 0:
        return 2.0 * np.pi / ((lam - 2.0 * nu) * g) * (1.0 + (3.0 - _LN4) / (lam - 2.0 * nu))
    if k == 1:
        d = (1.0 - nu) * lam + 2.0 * nu
        return 2.0 * np.pi / g * (1.0 + (1.0 - nu) * (3.0 - _LN4) / d) / d
    return 2.0 * np.pi / (3.0 * g**1.5 * ((1.0 - nu) * lam - 2.0 + 4.0 * nu))


def _first_interval_slopes():
    """dC/dg [-] at g = 0.1 and 0.2 of every column of the table, [case, node, k, j], for the
    cubic Hermite between them (the rows above stay linear in g).

    At g = 0.2: the secant to g = 0.3, so that C' is continuous into the linear part. At g = 0.1:
    the slope of the branch below the table, so that C' is continuous there too, except where that
    branch says nothing of the curve's shape (C11 and C22 of short patches: Kalker's constant
    limits; C33 of long patches: railwear's closure): there PCHIP's one-sided end slope
    ``(3 d01 - d12) / 2``. Both stay within [0, 3] times the secant over 0.1 ... 0.2, so the cubic
    is monotone (Fritsch & Carlson).
    """
    step = 1e-6

    def asymptote(case, k, g, nu):  # numpy's log here, as the table has always been built
        return _asymptote(case, k, g, nu, log=np.log, sqrt=np.sqrt)

    d = np.diff(KALKER_TABLE[:, :3], axis=1) / 0.1  # secants over 0.1-0.2 and 0.2-0.3
    slopes = np.empty((2, 2, 4, 3))
    slopes[:, 1] = d[:, 1]
    for case in range(2):
        for k in range(4):
            for j in range(3):
                v0, nu = KALKER_TABLE[case, 0, k, j], _NU_NODES_ARR[j]
                if (case == 0 and k < 2) or (case == 1 and k == 3):
                    slopes[case, 0, k, j] = 0.5 * (3.0 * d[case, 0, k, j] - d[case, 1, k, j])
                else:  # d/dg of C(0.1) asymptote(g) / asymptote(0.1)
                    slopes[case, 0, k, j] = v0 * (asymptote(case, k, 0.1 + step, nu) - asymptote(case, k, 0.1 - step, nu)) / (
                        2.0 * step * asymptote(case, k, 0.1, nu))
    return slopes


_SLOPES = _first_interval_slopes()


def _below_table(case, k, j, g):
    """Coefficient k at the tabulated Poisson ratio j for one g < 0.1: the asymptote matched to the
    table at g = 0.1 (C33 of long patches: the gap to its limit closed linearly in 1/Lambda)."""
    nu = float(_NU_NODES_ARR[j])
    value = float(KALKER_TABLE[case, 0, k, j])
    if case == 1 and k == 3:
        limit = np.pi / 4.0 * (1.0 - 2.0 * nu) / (1.0 - nu)
        return limit + (value - limit) * _LAMBDA_01 / math.log(16.0 / (g * g))
    return value * _asymptote(case, k, g, nu) / _asymptote(case, k, 0.1, nu)


def _node_values(case, g):
    """Coefficients ``[k, j, i]`` at the tabulated Poisson ratios j for each ``g[i]`` in (0, 1]:
    linear in g between the rows from g = 0.2, a cubic Hermite between 0.1 and 0.2, the matched
    asymptote below (numpy on the arrays; the few g < 0.1 one by one)."""
    r = np.clip(((g - 0.1) * 10.0 + 1e-9).astype(np.int64), 0, 8)  # g < 0.1 is overwritten below
    h = (_G_NODES[r + 1] - _G_NODES[r])[:, None, None]
    t = ((g - _G_NODES[r]) / h[:, 0, 0])[:, None, None]
    v0, v1 = KALKER_TABLE[case, r], KALKER_TABLE[case, r + 1]  # [i, k, j]
    m0, m1 = _SLOPES[case, 0] * h, _SLOPES[case, 1] * h
    hermite = v0 + t * t * (3.0 - 2.0 * t) * (v1 - v0) + t * (1.0 - t) * ((1.0 - t) * m0 - t * m1)
    out = np.where((r == 0)[:, None, None], hermite, (1.0 - t) * v0 + t * v1)
    for i in np.flatnonzero(g < 0.1):
        gi = float(g[i])
        for k in range(4):
            for j in range(3):
                out[i, k, j] = _below_table(case, k, j, gi)
    return out.transpose(1, 2, 0)


def _kalker_many(a_over_b, nu):
    """(C11, C22, C23, C33) as a ``(4, n)`` array for flat ``a_over_b`` (> 0) and ``nu`` (no checks)."""
    out = np.empty((4, a_over_b.size))
    short = a_over_b <= 1.0
    for case, rows in ((0, short), (1, ~short)):
        if not rows.any():
            continue
        rows = slice(None) if rows.all() else rows
        g = a_over_b[rows] if case == 0 else 1.0 / a_over_b[rows]
        c, n = _node_values(case, g), nu[rows]
        out[:3, rows] = 1.0 / _lagrange_nu(1.0 / c[:3, 0], 1.0 / c[:3, 1], 1.0 / c[:3, 2], n)  # CONTACT's: through 1/C
        out[3, rows] = _lagrange_nu(c[3, 0], c[3, 1], c[3, 2], n)  # C33: parabola through C (module docstring)
    return out


_TABLE_LISTS = KALKER_TABLE.tolist(), _SLOPES.tolist(), _G_NODES.tolist()  # Python floats, the same doubles


def _kalker_scalar(a_over_b, nu):
    """(C11, C22, C23, C33) for one ``a_over_b`` (> 0) and ``nu`` as Python floats: the operations
    of :func:`_kalker_many` in the same order on floats, so the same numbers bit for bit, without
    numpy's cost on one-element arrays (a single FASTSIM call spent two thirds of its time there)."""
    case = 0 if a_over_b <= 1.0 else 1
    g = a_over_b if case == 0 else 1.0 / a_over_b
    table, slopes, nodes = _TABLE_LISTS[0][case], _TABLE_LISTS[1][case], _TABLE_LISTS[2]
    c = [[0.0] * 3 for _ in range(4)]
    if g < 0.1:
        for k in range(4):
            for j in range(3):
                c[k][j] = _below_table(case, k, j, g)
    else:
        r = min(max(int((g - 0.1) * 10.0 + 1e-9), 0), 8)
        h = nodes[r + 1] - nodes[r]
        t = (g - nodes[r]) / h
        v0, v1 = table[r], table[r + 1]
        for k in range(4):
            for j in range(3):
                a, b = v0[k][j], v1[k][j]
                if r == 0:
                    m0, m1 = slopes[0][k][j] * h, slopes[1][k][j] * h
                    c[k][j] = a + t * t * (3.0 - 2.0 * t) * (b - a) + t * (1.0 - t) * ((1.0 - t) * m0 - t * m1)
                else:
                    c[k][j] = (1.0 - t) * a + t * b
    out = [1.0 / _lagrange_nu(1.0 / c[k][0], 1.0 / c[k][1], 1.0 / c[k][2], nu) for k in range(3)]
    return (*out, _lagrange_nu(c[3][0], c[3][1], c[3][2], nu))


def kalker_coefficients(a_over_b, poisson):
    """Kalker's creepage coefficients (C11, C22, C23, C33) [-] for semi-axis ratio a/b and ν.

    ``a`` is the semi-axis along rolling. Vectorised over broadcast ``a_over_b`` (> 0) and
    ``poisson`` (in [0, 0.5)). Reproduces Kalker's Table E.3 at its nodes; see the module
    docstring for interpolation and the asymptotic range.
    """
    aob = positive(a_over_b, "a_over_b")
    nu = poisson_ratio(poisson, "poisson")
    aob, nu = np.broadcast_arrays(aob, nu)
    shape = aob.shape
    if not shape:  # one pair: the scalar path, the same numbers
        return tuple(np.float64(c) for c in _kalker_scalar(float(aob), float(nu)))
    flat_aob = np.ascontiguousarray(aob, dtype=float).ravel()
    flat_nu = np.ascontiguousarray(nu, dtype=float).ravel()
    out = _kalker_many(flat_aob, flat_nu)
    return tuple(scalar_or_array(c.reshape(shape)) for c in out)


@dataclass(frozen=True)
class LinearCreepForces:
    """Kalker linear-theory creep forces: Fx, Fy [N], Mz [N m] (sign convention in module doc)."""

    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray


def linear_creep_forces(a, b, xi, eta, phi, shear_modulus, poisson):
    """Kalker's linear creep forces for semi-axes a (rolling), b [m] and creepages ξ, η [-], φ [1/m].

    Valid for small creepage (full adhesion); shear_modulus [Pa]. Vectorised.
    """
    a = positive(a, "a")
    b = positive(b, "b")
    G = positive(shear_modulus, "shear_modulus")
    xi = as_float_array(xi, "xi")
    eta = as_float_array(eta, "eta")
    phi = as_float_array(phi, "phi")
    c11, c22, c23, c33 = (np.asarray(c) for c in kalker_coefficients(a / b, poisson))
    c2 = a * b
    c3 = c2 * np.sqrt(c2)
    Fx = -G * c2 * c11 * xi
    Fy = -G * c2 * c22 * eta - G * c3 * c23 * phi
    Mz = G * c3 * c23 * eta - G * c2 * c2 * c33 * phi
    return LinearCreepForces(Fx=scalar_or_array(Fx), Fy=scalar_or_array(Fy), Mz=scalar_or_array(Mz))
