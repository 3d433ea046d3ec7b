"""Contact geometry of a wheelset on straight track and contact tables over the lateral shift.

Frames: track ``Y`` lateral (positive towards the right rail), ``Z`` downwards. The wheelset is
shifted by ``y`` and rolled by ``θ`` (positive lowers the right wheel); a point at wheelset
coordinates (lateral ``Y'``, depth below the axle ``D'``) lies at ``Y = y + Y' cos θ - D' sin θ``,
``Z = Z0 + Y' sin θ + D' cos θ``. The right wheel is the profile as given (profile ``y`` outwards,
see :mod:`railwear.geometry.profiles`) with its origin at ``Y' = back_to_back/2 +
taping_line_offset``; the left one is its mirror image. Each rail is placed so that its gauge
point (the gauge face at ``gauge_depth`` below the top, 14 mm) lies at ``±gauge/2``.

For each shift the roll is solved so that both wheels touch their rails (rigid contact): the
smallest vertical gap between wheel and rail is found on each side over the whole profile
(coarse sampling, then golden-section refinement of every local minimum), and ``θ`` makes the
two equal (Illinois regula falsi). The local minimum with zero gap is the contact point; a second
local minimum is reported with its gap, so two-point contact (tread and flange) is seen as the
second gap closing.

Per contact the table holds the rolling radius, the contact angle ``δ`` (angle of the tangent
plane to the track plane, positive when the rail normal points towards the track centre), the
profile curvatures, Hertz's curvatures ``A = cos δ / (2 r)`` (rolling direction, straight rail)
and ``B = (κ_rail + κ_wheel) / 2`` (lateral, convex positive), the normal force
``N = Q / cos δ`` (``Q`` half the axle load, creep forces neglected), Hertz's semi-axes and
Kalker's coefficients.
"""

from dataclasses import dataclass

import numpy as np
import xarray as xr
from numba import njit

from railwear.contact import hertz_contact, kalker_coefficients
from railwear.contact.multipoint import _semi_wheel
from railwear.contact.semi_hertz import patch_strips
from railwear.geometry.contact_models import CONTACT_MODELS, point_contacts, resultant
from railwear.errors import ScenarioError
from railwear.geometry.profiles import Profile
from railwear.units import MM

__all__ = ["contact_table", "equivalent_conicity", "gauge_point", "KlingelOrbit"]

_GOLDEN = 0.5 * (np.sqrt(5.0) - 1.0)
_COARSE_STEP = 0.25e-3  # sampling of the wheel profile before refinement [m]
_MAX_MINIMA = 6

# The kernels below are compiled on a command's first run. numba compiles a callee once per value
# of a constant integer or boolean argument, and each caller's machine code again includes all of
# its callees: so the wheel side is a float (+1.0 right, -1.0 left), the roll iteration's lowest
# gap and the table's local minima are two functions instead of one with a flag, and the gap is
# inlined once into the grid sampling and called from the golden section.


@njit(cache=True)
def _segment(xb, x):
    """Piece ``i`` of the breakpoints ``xb`` holding ``x`` and ``t = x - xb[i]``; ``i = -1`` outside."""
    n = xb.shape[0] - 1
    if x < xb[0] or x > xb[n]:
        return -1, 0.0
    lo, hi = 0, n + 1  # bisection: the number of breakpoints <= x (numpy's searchsorted "right")
    while lo < hi:
        mid = (lo + hi) // 2
        if xb[mid] <= x:
            lo = mid + 1
        else:
            hi = mid
    i = min(max(lo - 1, 0), n - 1)
    return i, x - xb[i]


@njit(cache=True)
def _spline(xb, c, x):
    """Piecewise cubic (scipy CubicSpline layout) at ``x``; NaN outside."""
    i, t = _segment(xb, x)
    if i < 0:
        return np.nan
    return ((c[0, i] * t + c[1, i]) * t + c[2, i]) * t + c[3, i]


@njit(cache=True)
def _spline_slopes(xb, c, x):
    """First and second derivative of the piecewise cubic at ``x``; NaN outside."""
    i, t = _segment(xb, x)
    if i < 0:
        return np.nan, np.nan
    return (3.0 * c[0, i] * t + 2.0 * c[1, i]) * t + c[2, i], 6.0 * c[0, i] * t + 2.0 * c[1, i]


@njit(cache=True)
def _contact_point(yp, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0):
    """Lowest point of the wheel circle at profile point yp over the rail.

    Returns (gap rail - wheel with Z0 = 0, rail profile coordinate, longitudinal position X of
    the point ahead of the wheel centre);
    gap = +inf off the rail. Without yaw the lowest point lies under the axle (X = 0); with yaw
    the angle round the wheel is found by Newton's method on the gap (three steps suffice, the
    angle being of the order of yaw times the rail slope).
    """
    zw = _spline(wx, wc, yp)
    rho = r0 + zw
    Yp = side * (yw0 + yp)
    alpha = 0.0
    steps = 0 if sps == 0.0 else 4
    for _ in range(steps):
        ca = np.cos(alpha)
        sa = np.sin(alpha)
        Y1 = Yp * cth - rho * ca * sth
        Y = y_ws + rho * sa * sps + Y1 * cps
        yr = side * Y - yr0
        z1, z2 = _spline_slopes(rx, rc, yr)
        if np.isnan(z1):
            return np.inf, np.nan, np.nan
        dY = rho * ca * sps + rho * sa * sth * cps
        d2Y = -rho * sa * sps + rho * ca * sth * cps
        dZ = -rho * sa * cth
        d2Z = -rho * ca * cth
        alpha -= (side * z1 * dY - dZ) / (z2 * dY * dY + side * z1 * d2Y - d2Z)
    if steps == 0:
        ca, sa = 1.0, 0.0
    else:
        ca, sa = np.cos(alpha), np.sin(alpha)
    X1 = rho * sa
    Y1 = Yp * cth - rho * ca * sth
    Zw = Yp * sth + rho * ca * cth
    Y = y_ws + X1 * sps + Y1 * cps
    yr = side * Y - yr0
    zr = _spline(rx, rc, yr)
    if np.isnan(zr):
        return np.inf, np.nan, np.nan
    # longitudinal position relative to the wheel centre (X1 = 0, Y1 = Yp cos(theta))
    return zr - Zw, yr, X1 * cps + rho * ca * sth * sps


@njit(cache=True, inline="always")
def _gap(yp, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0):
    """Vertical gap rail - wheel (Z0 = 0) under wheel profile point yp; +inf off the rail."""
    if sps != 0.0:
        return _contact_point(yp, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)[0]
    D = r0 + _spline(wx, wc, yp)
    Yp = side * (yw0 + yp)
    zr = _spline(rx, rc, side * (y_ws + Yp * cth - D * sth) - yr0)
    if np.isnan(zr):
        return np.inf
    return zr - (Yp * sth + D * cth)


@njit(cache=True)
def _gap_at(yp, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0):
    """``_gap`` as a compiled call: the golden section's three calls share one copy."""
    return _gap(yp, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)


@njit(cache=True)
def _refine(lo, hi, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0):
    """Golden-section minimum of the gap on [lo, hi]: (gap, yp)."""
    a, b = lo, hi
    x1 = b - _GOLDEN * (b - a)
    x2 = a + _GOLDEN * (b - a)
    f1 = _gap_at(x1, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
    f2 = _gap_at(x2, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
    for _ in range(60):
        if f1 < f2:
            b = x2
            x2 = x1
            f2 = f1
            x1 = b - _GOLDEN * (b - a)
            f1 = _gap_at(x1, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
        else:
            a = x1
            x1 = x2
            f1 = f2
            x2 = a + _GOLDEN * (b - a)
            f2 = _gap_at(x2, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
        if b - a < 1e-12:
            break
    if f1 < f2:
        return f1, x1
    return f2, x2


@njit(cache=True)
def _sample(side, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0):
    """The gap at every point of the coarse ``grid`` of the wheel profile (``side`` +1.0 right,
    -1.0 left, a float so that one compiled copy serves both wheels)."""
    cth = np.cos(theta)
    sth = np.sin(theta)
    cps = np.cos(psi)
    sps = np.sin(psi)
    n = grid.shape[0]
    g = np.empty(n)
    for k in range(n):
        g[k] = _gap(grid[k], side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
    return g


@njit(cache=True)
def _lowest(side, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0):
    """The smallest gap along the wheel profile, refined around the lowest grid point (+inf off
    the rail); used inside the roll iteration."""
    g = _sample(side, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0)
    k = 0
    for j in range(1, g.shape[0]):  # the first smallest, as np.argmin (off the rail the gap is +inf, not NaN)
        if g[j] < g[k]:
            k = j
    if not np.isfinite(g[k]):
        return np.inf
    n = grid.shape[0]
    return _refine(grid[max(k - 1, 0)], grid[min(k + 1, n - 1)], side, y_ws, np.cos(theta), np.sin(theta),
                   np.cos(psi), np.sin(psi), wx, wc, rx, rc, yw0, yr0, r0)[0]


@njit(cache=True)
def _minima(side, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0, gaps, where):
    """Local minima of the gap along the wheel profile, refined, into ``gaps`` and ``where``;
    returns their number."""
    cth = np.cos(theta)
    sth = np.sin(theta)
    cps = np.cos(psi)
    sps = np.sin(psi)
    g = _sample(side, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0)
    n = grid.shape[0]
    count = 0
    for k in range(n):
        if not np.isfinite(g[k]):
            continue
        left = g[k - 1] if k > 0 else np.inf
        right = g[k + 1] if k < n - 1 else np.inf
        if g[k] <= left and g[k] < right:
            lo = grid[max(k - 1, 0)]
            hi = grid[min(k + 1, n - 1)]
            gk, yk = _refine(lo, hi, side, y_ws, cth, sth, cps, sps, wx, wc, rx, rc, yw0, yr0, r0)
            duplicate = False
            for m in range(count):
                if abs(where[m] - yk) < 0.5e-3:
                    duplicate = True
                    if gk < gaps[m]:
                        gaps[m] = gk
                        where[m] = yk
            if not duplicate and count < gaps.shape[0]:
                gaps[count] = gk
                where[count] = yk
                count += 1
    return count


@njit(cache=True)
def _roll_residual(y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0):
    gr = _lowest(1.0, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0)
    gl = _lowest(-1.0, y_ws, psi, theta, grid, wx, wc, rx, rc, yw0, yr0, r0)
    return gr - gl, gr


@njit(cache=True)
def _solve_roll(y_ws, psi, theta0, grid, wx, wc, rx, rc, yw0, yr0, r0):
    """Roll angle with equal minimum gaps on both sides: (theta, z_drop, ok)."""
    a = theta0
    fa, _ = _roll_residual(y_ws, psi, a, grid, wx, wc, rx, rc, yw0, yr0, r0)
    if not np.isfinite(fa):
        return np.nan, np.nan, False
    step = 1e-3
    b = a - step if fa < 0.0 else a + step
    fb, _ = _roll_residual(y_ws, psi, b, grid, wx, wc, rx, rc, yw0, yr0, r0)
    tries = 0
    while fa * fb > 0.0 and tries < 40:
        step *= 2.0
        a, fa = b, fb
        b = a - step if fa < 0.0 else a + step
        if abs(b) > 0.5:
            return np.nan, np.nan, False
        fb, _ = _roll_residual(y_ws, psi, b, grid, wx, wc, rx, rc, yw0, yr0, r0)
        if not np.isfinite(fb):
            return np.nan, np.nan, False
        tries += 1
    if fa * fb > 0.0:
        return np.nan, np.nan, False
    # Illinois regula falsi on the bracket [a, b]
    side_kept = 0
    c = a
    for _ in range(200):
        c = b - fb * (b - a) / (fb - fa)
        fc, _ = _roll_residual(y_ws, psi, c, grid, wx, wc, rx, rc, yw0, yr0, r0)
        if fc == 0.0 or abs(b - a) < 1e-14:
            break
        if fc * fb < 0.0:
            a, fa = b, fb
            side_kept = 0
        else:
            if side_kept == 1:
                fa *= 0.5
            side_kept = 1
        b, fb = c, fc
        if abs(fc) < 1e-15:
            break
    _, gr = _roll_residual(y_ws, psi, c, grid, wx, wc, rx, rc, yw0, yr0, r0)
    return c, gr, True


@njit(cache=True)
def _table_core(shifts, yaws, grid, wx, wc, rx, rc, yw0, yr0, r0, out_theta, out_drop, out_ok,
                gaps_r, where_r, count_r, gaps_l, where_l, count_l, rail_r, x_r, rail_l, x_l):
    """Solve every shift, continuing the roll angle from the previous (sorted) shift; for every
    local contact also its rail profile coordinate and longitudinal position."""
    theta = 0.0
    for k in range(shifts.shape[0]):
        th, drop, ok = _solve_roll(shifts[k], yaws[k], theta, grid, wx, wc, rx, rc, yw0, yr0, r0)
        out_ok[k] = ok
        if not ok:
            out_theta[k] = np.nan
            out_drop[k] = np.nan
            continue
        theta = th
        out_theta[k] = th
        out_drop[k] = drop
        count_r[k] = _minima(1.0, shifts[k], yaws[k], th, grid, wx, wc, rx, rc, yw0, yr0, r0, gaps_r[k], where_r[k])
        count_l[k] = _minima(-1.0, shifts[k], yaws[k], th, grid, wx, wc, rx, rc, yw0, yr0, r0, gaps_l[k], where_l[k])
        cth, sth, cps, sps = np.cos(th), np.sin(th), np.cos(yaws[k]), np.sin(yaws[k])
        for m in range(count_r[k]):
            _, rail_r[k, m], x_r[k, m] = _contact_point(where_r[k, m], 1.0, shifts[k], cth, sth, cps, sps,
                                                        wx, wc, rx, rc, yw0, yr0, r0)
        for m in range(count_l[k]):
            _, rail_l[k, m], x_l[k, m] = _contact_point(where_l[k, m], -1.0, shifts[k], cth, sth, cps, sps,
                                                        wx, wc, rx, rc, yw0, yr0, r0)


_CAP = 4.0  # semi-hertzian: the approach is sought below _CAP times the primary point's alone


@njit(cache=True)
def _semi_table(shifts, yaws, theta, drop, G, yp, cosg, A, K0, Q, estar, wx, wc, rx, rc, yw0, yr0, r0, h, J,
                u, eps_t, ap_t, out, delta, strips):
    """Semi-Hertzian patches for every shift and wheel (``railwear.geometry.contact_models``):
    the gap sampled on ``h`` around every minimum of gap ``G`` below the bound, solved by
    ``multipoint._semi_wheel``; fills ``out``
    (n, 2, P, fields), ``delta`` (n, 2) and the loaded patches' strip half-lengths ``strips``
    (n, 2, P, strips; ``semi_hertz.patch_strips``, zero for a patch without load)."""
    n, _, P = G.shape
    F = np.empty((P, 2 * J + 1))
    starts = np.full(P, J, dtype=np.int64)
    hs = np.empty(P)
    for k in range(n):
        cth, sth = np.cos(theta[k]), np.sin(theta[k])
        cps, sps = np.cos(yaws[k]), np.sin(yaws[k])
        for side in range(2):
            sgn = 1.0 - 2.0 * side
            first = G[k, side, 0]
            if not np.isfinite(first):
                delta[k, side] = np.nan
                continue
            # bound on the approach: the primary point alone (Hertz), times _CAP
            cap = first + _CAP * (Q / (K0[k, side] * cosg[k, side, 0] ** 2.5)) ** (2.0 / 3.0)
            base = drop[k]
            for i in range(P):
                g_i = G[k, side, i]
                c = cosg[k, side, i]
                hs[i] = h / c if np.isfinite(g_i) else h
                if not (np.isfinite(g_i) and g_i < cap):
                    for j in range(2 * J + 1):
                        F[i, j] = 1.0
                    continue
                F[i, J] = 0.0
                for direction in (-1, 1):
                    stop = False
                    for j in range(1, J + 1):
                        idx = J + direction * j
                        if stop:
                            F[i, idx] = 1.0
                            continue
                        gap = _gap(yp[k, side, i] + direction * j * h, sgn, shifts[k], cth, sth, cps, sps,
                                   wx, wc, rx, rc, yw0, yr0, r0) - base
                        if not np.isfinite(gap):
                            F[i, idx] = 1.0
                            stop = True
                            continue
                        F[i, idx] = (gap - G[k, side, i]) * c
                        if F[i, idx] > 2.0 * cap * c:
                            stop = True
            pos = np.empty(P)
            for i in range(P):
                pos[i] = yp[k, side, i] if np.isfinite(G[k, side, i]) else np.nan
            delta[k, side] = _semi_wheel(F, starts, hs, G[k, side], cosg[k, side], A[k, side], pos, h, Q, estar,
                                         u, eps_t, ap_t, cap, out[k, side])
            for i in range(P):
                if out[k, side, i, 0] > 0.0:
                    patch_strips(F[i], J, hs[i], A[k, side, i], (delta[k, side] - G[k, side, i]) * cosg[k, side, i],
                                 out[k, side, i, 7], out[k, side, i, 8], out[k, side, i, 3], out[k, side, i, 4], u,
                                 eps_t, ap_t, strips[k, side, i])


def gauge_point(rail, depth=0.014):
    """Lateral profile coordinate [m] of the rail's gauge face at ``depth`` below the top."""
    y = np.linspace(rail.span[0], rail.span[1], 4001)
    z = rail(y)
    top = int(np.argmin(z))
    below = np.nonzero(z[: top + 1] >= z[top] + depth)[0]
    if below.size == 0:
        raise ScenarioError(f"rail profile {rail.name!r} has no gauge face {depth / MM:g} mm below its top")
    k = below[-1]
    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs 0.2-0.6 s

    return brentq(lambda s: rail(s) - z[top] - depth, y[k], y[k + 1], xtol=1e-13)


def _order_contacts(gaps, where, count, rails, xs):
    """Primary (smallest gap) and secondary contact per shift:
    (gap1, wheel y1, rail y1, X1, gap2, wheel y2, rail y2)."""
    n = gaps.shape[0]
    g1, y1, r1, x1 = (np.full(n, np.nan) for _ in range(4))
    g2 = np.full(n, np.inf)
    y2, r2 = np.full(n, np.nan), np.full(n, np.nan)
    for k in range(n):
        m = count[k]
        if m == 0:
            continue
        order = np.argsort(gaps[k, :m])
        i = order[0]
        g1[k], y1[k], r1[k], x1[k] = gaps[k, i], where[k, i], rails[k, i], xs[k, i]
        if m > 1:
            i = order[1]
            g2[k], y2[k], r2[k] = gaps[k, i], where[k, i], rails[k, i]
    return g1, y1, r1, x1, g2, y2, r2


def contact_table(wheel, rail, gauge=1.435, cant=1.0 / 40.0, back_to_back=1.360, axle_load=133.4e3,
                  y=None, rolling_radius=0.46, taping_line_offset=0.070, gauge_depth=0.014,
                  youngs_modulus=2.1e11, poisson=0.28, two_point_gap=1e-5, yaw=0.0, contact_model="hertz",
                  semi_hertz_step=1e-4):
    """Contact table of a symmetric wheelset on straight track, as an ``xarray.Dataset`` over ``y``.

    wheel, rail: :class:`~railwear.geometry.profiles.Profile` (right-hand side; the left side is
    the mirror image); gauge [m]; cant: rail inclination (1/40; profiles that already carry an
    inclination are rotated only by the difference); back_to_back [m] between the wheels' inner
    faces; axle_load [N] (vertical load of the wheelset on the track); y: lateral shifts [m]
    (default -10 ... 10 mm, 0.1 mm); rolling_radius r0 [m] at the profile origin (taping line);
    taping_line_offset [m] from the inner face to the profile origin; gauge_depth [m];
    youngs_modulus [Pa], poisson [-] of both bodies; two_point_gap [m]: a secondary contact
    whose gap is below it counts as two-point contact; yaw [rad]: yaw angle of the wheelset, a
    number or one value per shift (the contact points then move off the vertical plane through
    the axle, ``contact_X`` ahead of the wheel centre); contact_model: ``"hertz"`` (one rigid
    contact point per wheel carrying ``Q / cos δ``), ``"multi-hertz"`` or ``"semi-hertzian"``
    (several contacts per wheel sharing the load, :mod:`railwear.geometry.contact_models`: the
    per-wheel variables are then the resultant the dynamics read, and ``point_*`` over ``point``
    hold every contact); semi_hertz_step [m]: sampling of the separation across the profile.

    Variables (dims y or (y, side)) carry CF ``units`` and ``long_name``; see the module
    docstring for the definitions.
    """
    if contact_model not in CONTACT_MODELS:
        raise ScenarioError(f"contact_model must be one of {', '.join(CONTACT_MODELS)}, got {contact_model!r}")
    if not (np.isfinite(semi_hertz_step) and 1e-6 <= semi_hertz_step <= 1e-3):
        raise ScenarioError(f"semi_hertz_step must lie in [1e-6, 1e-3] m, got {semi_hertz_step!r}")
    if not isinstance(wheel, Profile) or not isinstance(rail, Profile):
        raise ScenarioError("wheel and rail must be Profile objects (see load_profile)")
    if wheel.kind != "wheel" or rail.kind != "rail":
        raise ScenarioError(f"wheel/rail profile kinds are {wheel.kind!r}/{rail.kind!r}, expected 'wheel'/'rail'")
    for name, value in (("gauge", gauge), ("back_to_back", back_to_back), ("rolling_radius", rolling_radius),
                        ("axle_load", axle_load), ("youngs_modulus", youngs_modulus)):
        if not np.isfinite(value) or value <= 0:
            raise ScenarioError(f"{name} must be a positive number, got {value}")
    if y is None:
        y = np.round(np.linspace(-0.010, 0.010, 201), 12)
    shifts = np.atleast_1d(np.asarray(y, dtype=float))
    if not np.all(np.isfinite(shifts)) or shifts.ndim != 1:
        raise ScenarioError("y must be a 1-D array of finite lateral shifts")
    try:
        yaws = np.broadcast_to(np.asarray(yaw, dtype=float), shifts.shape).copy()
    except ValueError:
        raise ScenarioError(f"yaw must be a number or one value per shift ({shifts.size})") from None
    if not np.all(np.isfinite(yaws)) or np.any(np.abs(yaws) > 0.2):
        raise ScenarioError("yaw must be finite and below 0.2 rad")
    rail_c = rail.canted(cant)
    y_gauge = gauge_point(rail_c, gauge_depth)
    yr0 = 0.5 * gauge - y_gauge
    yw0 = 0.5 * back_to_back + taping_line_offset
    wx, wc = (np.ascontiguousarray(a, dtype=float) for a in wheel.spline_coefficients())
    rx, rc = (np.ascontiguousarray(a, dtype=float) for a in rail_c.spline_coefficients())
    lo, hi = wheel.span
    grid = np.arange(lo, hi + 0.5 * _COARSE_STEP, _COARSE_STEP)
    grid = grid[grid <= hi]

    # solve outwards from the shift nearest zero, so that the roll angle is continued smoothly
    order = np.argsort(np.abs(shifts), kind="stable")
    n = shifts.size
    theta = np.empty(n)
    drop = np.empty(n)
    ok = np.zeros(n, dtype=np.bool_)
    gaps_r = np.full((n, _MAX_MINIMA), np.inf)
    where_r = np.full((n, _MAX_MINIMA), np.nan)
    gaps_l = np.full((n, _MAX_MINIMA), np.inf)
    where_l = np.full((n, _MAX_MINIMA), np.nan)
    count_r = np.zeros(n, dtype=np.int64)
    count_l = np.zeros(n, dtype=np.int64)
    rail_r, x_r = np.full((n, _MAX_MINIMA), np.nan), np.full((n, _MAX_MINIMA), np.nan)
    rail_l, x_l = np.full((n, _MAX_MINIMA), np.nan), np.full((n, _MAX_MINIMA), np.nan)
    for sign in (1.0, -1.0):
        sel = order[(np.sign(shifts[order]) == sign) | ((shifts[order] == 0.0) & (sign > 0))]
        if sel.size == 0:
            continue
        th, dr, okk = np.empty(sel.size), np.empty(sel.size), np.zeros(sel.size, dtype=np.bool_)
        gr, wr = np.full((sel.size, _MAX_MINIMA), np.inf), np.full((sel.size, _MAX_MINIMA), np.nan)
        gl, wl = np.full((sel.size, _MAX_MINIMA), np.inf), np.full((sel.size, _MAX_MINIMA), np.nan)
        cr, cl = np.zeros(sel.size, dtype=np.int64), np.zeros(sel.size, dtype=np.int64)
        sel_rail_r, sel_x_r, sel_rail_l, sel_x_l = (np.full((sel.size, _MAX_MINIMA), np.nan) for _ in range(4))
        _table_core(np.ascontiguousarray(shifts[sel]), np.ascontiguousarray(yaws[sel]), grid, wx, wc, rx, rc,
                    yw0, yr0, rolling_radius, th, dr, okk, gr, wr, cr, gl, wl, cl,
                    sel_rail_r, sel_x_r, sel_rail_l, sel_x_l)
        theta[sel], drop[sel], ok[sel] = th, dr, okk
        gaps_r[sel], where_r[sel], count_r[sel] = gr, wr, cr
        gaps_l[sel], where_l[sel], count_l[sel] = gl, wl, cl
        rail_r[sel], x_r[sel], rail_l[sel], x_l[sel] = sel_rail_r, sel_x_r, sel_rail_l, sel_x_l
    if not np.all(ok):
        bad = shifts[~ok][0]
        raise ScenarioError(
            f"wheel and rail profiles never touch at y = {bad / MM:.3g} mm (check gauge, back_to_back, cant)"
        )

    sides = []
    for side, gaps, where, count, rails, xs in ((1.0, gaps_r, where_r, count_r, rail_r, x_r),
                                                (-1.0, gaps_l, where_l, count_l, rail_l, x_l)):
        g1, yp1, yr1, x1, g2, yp2, yr2 = _order_contacts(gaps, where, count, rails, xs)
        sides.append(dict(g1=g1 - drop, yp1=yp1, yr1=yr1, X=x1, Y=side * (yr1 + yr0), g2=g2 - drop,
                          yp2=yp2, yr2=yr2))

    def stack(key):
        return np.stack([s[key] for s in sides], axis=1)

    yp1, yr1 = stack("yp1"), stack("yr1")
    radius = rolling_radius + wheel(yp1)
    slope = rail_c.slope(yr1)
    delta = -np.arctan(slope)
    kappa_rail = rail_c.curvature(yr1)
    kappa_wheel = -wheel.curvature(yp1)
    A = 0.5 * np.cos(delta) / radius
    B = 0.5 * (kappa_rail + kappa_wheel)
    conformal = B <= 0.0
    Q = 0.5 * axle_load
    N = Q / np.cos(delta)
    h = hertz_contact(N, A, np.where(conformal, A, B), youngs_modulus, poisson)
    a = np.where(conformal, np.nan, h.a)
    b = np.where(conformal, np.nan, h.b)
    c11, c22, c23, c33 = kalker_coefficients(np.where(conformal, 1.0, h.a / h.b), poisson)
    yp2, yr2, g2 = stack("yp2"), stack("yr2"), stack("g2")
    delta2 = np.where(np.isfinite(yr2), -np.arctan(rail_c.slope(np.where(np.isfinite(yr2), yr2, 0.0))), np.nan)
    two_point = g2 < two_point_gap
    dr = radius[:, 0] - radius[:, 1]

    points = None
    if contact_model != "hertz":
        def both(right, left):
            return np.stack([right, left], axis=1)

        points, approach = point_contacts(
            contact_model, shifts, yaws, theta, drop, both(gaps_r, gaps_l), both(where_r, where_l),
            both(rail_r, rail_l), both(x_r, x_l), wheel, rail_c, (wx, wc, rx, rc), yw0, yr0, rolling_radius,
            axle_load, youngs_modulus, poisson, semi_hertz_step, _semi_table)
        eq = resultant(points, poisson, youngs_modulus, yr0)
        radius, delta, N = eq["rolling_radius"], eq["contact_angle"], eq["normal_force"]
        yp1, yr1, a, b = eq["wheel_contact_y"], eq["rail_contact_y"], eq["a"], eq["b"]
        c11, c22, c23, c33 = eq["c11"], eq["c22"], eq["c23"], eq["c33"]
        for s_, k in zip(sides, range(2)):
            s_["Y"], s_["X"] = eq["contact_Y"][:, k], eq["contact_X"][:, k]
        dr = radius[:, 0] - radius[:, 1]

    dims = ("y", "side")
    ds = xr.Dataset(
        data_vars=dict(
            yaw_angle=("y", yaws, dict(units="rad", long_name="wheelset yaw angle (prescribed)")),
            roll_angle=("y", theta, dict(units="rad", long_name="wheelset roll angle (positive lowers the right wheel)")),
            axle_z=("y", drop, dict(units="m", long_name="vertical position of the axle (downwards), relative to the reference placement")),
            rolling_radius_difference=("y", dr, dict(units="m", long_name="rolling radius difference right - left")),
            rolling_radius=(dims, radius, dict(units="m", long_name="rolling radius at the contact point")),
            contact_angle=(dims, delta, dict(units="rad", long_name="contact angle (positive towards the flange)")),
            wheel_contact_y=(dims, yp1, dict(units="m", long_name="contact point on the wheel profile")),
            rail_contact_y=(dims, yr1, dict(units="m", long_name="contact point on the rail profile")),
            contact_Y=(dims, stack("Y"), dict(units="m", long_name="lateral track position of the contact point")),
            contact_X=(dims, stack("X"), dict(units="m", long_name="longitudinal position of the contact point ahead of the wheel centre")),
            wheel_curvature=(dims, kappa_wheel, dict(units="1/m", long_name="lateral wheel profile curvature (convex positive)")),
            rail_curvature=(dims, kappa_rail, dict(units="1/m", long_name="lateral rail profile curvature (convex positive)")),
            A=(dims, A, dict(units="1/m", long_name="Hertz curvature in the rolling direction")),
            B=(dims, B, dict(units="1/m", long_name="Hertz curvature in the lateral direction")),
            normal_force=(dims, N, dict(units="N", long_name="normal contact force")),
            a=(dims, a, dict(units="m", long_name="contact ellipse semi-axis along rolling")),
            b=(dims, b, dict(units="m", long_name="contact ellipse lateral semi-axis")),
            c11=(dims, np.asarray(c11), dict(units="1", long_name="Kalker coefficient C11")),
            c22=(dims, np.asarray(c22), dict(units="1", long_name="Kalker coefficient C22")),
            c23=(dims, np.asarray(c23), dict(units="1", long_name="Kalker coefficient C23")),
            c33=(dims, np.asarray(c33), dict(units="1", long_name="Kalker coefficient C33")),
            second_gap=(dims, g2, dict(units="m", long_name="gap at the second-closest local contact point")),
            second_wheel_contact_y=(dims, yp2, dict(units="m", long_name="second contact point on the wheel profile")),
            second_contact_angle=(dims, delta2, dict(units="rad", long_name="contact angle at the second contact point")),
            two_point_contact=(dims, two_point, dict(long_name=f"second contact within {two_point_gap:g} m")),
        ),
        coords=dict(
            y=("y", shifts, dict(units="m", long_name="lateral shift of the wheelset (positive to the right)")),
            side=("side", ["right", "left"], dict(long_name="wheel")),
        ),
        attrs=dict(
            wheel_profile=wheel.name, rail_profile=rail.name, gauge=gauge, cant=cant, back_to_back=back_to_back,
            axle_load=axle_load, nominal_rolling_radius=rolling_radius, taping_line_offset=taping_line_offset,
            youngs_modulus=youngs_modulus, poisson=poisson, contact_model=contact_model,
        ),
    )
    if points is not None:
        ds = _add_points(ds, points, approach, contact_model)
    return ds


_POINT_VARS = {  # name: (units, long_name)
    "gap": ("m", "vertical gap at the contact before loading"),
    "wheel_y": ("m", "contact position on the wheel profile (semi-hertzian: load centroid)"),
    "rail_y": ("m", "contact position on the rail profile"),
    "contact_X": ("m", "longitudinal position of the contact ahead of the wheel centre"),
    "contact_angle": ("rad", "contact angle of the contact"),
    "rolling_radius": ("m", "rolling radius at the contact"),
    "normal_force": ("N", "normal force of the contact"),
    "a": ("m", "semi-axis along rolling (semi-hertzian: equivalent ellipse, area / (pi b))"),
    "b": ("m", "lateral semi-axis (semi-hertzian: half the patch width)"),
    "p0": ("Pa", "peak pressure (semi-hertzian: at the point of largest interpenetration)"),
    "c11": ("1", "Kalker coefficient C11 of the contact"),
    "c22": ("1", "Kalker coefficient C22 of the contact"),
    "c23": ("1", "Kalker coefficient C23 of the contact"),
    "c33": ("1", "Kalker coefficient C33 of the contact"),
    "f11": ("N", "Kalker creep coefficient G c^2 C11 of the contact"),
    "f22": ("N", "Kalker creep coefficient G c^2 C22 of the contact"),
    "f23": ("N m", "Kalker creep coefficient G c^3 C23 of the contact"),
    "f33": ("N m2", "Kalker creep coefficient G c^4 C33 of the contact"),
    "area": ("m2", "patch area"),
    "half_length": ("m", "largest half-length of the patch along rolling"),
    "lateral_min": ("m", "patch edge on the wheel profile, flange side"),
    "lateral_max": ("m", "patch edge on the wheel profile, field side"),
    "virtual_penetration_ratio": ("1", "virtual penetration over the approach"),
    "patch_curvature": ("1/m", "lateral curvature of the interpenetration region, approach / half-width^2"),
    "strip_width": ("m", "width of the patch's strips across rolling, in its contact plane"),
    "strip_wheel_y": ("m", "strip centre on the wheel profile"),
    "strip_half_length": ("m", "half-length of the strip along rolling"),
    "strip_rolling_radius": ("m", "rolling radius at the strip centre"),
}


def _add_points(ds, points, approach, model):
    """The per-point variables ``point_*`` (y, side, point), their creep shares and the
    vertical approach; the per-wheel variables are relabelled as the resultant."""
    dims = ("y", "side", "point")
    for name, value in points.items():
        units, long_name = _POINT_VARS[name]
        ds[f"point_{name}"] = (dims + ("strip",) * (value.ndim - 3), value, dict(units=units, long_name=long_name))
    share = points["f11"] / points["f11"].sum(-1, keepdims=True)
    ds["point_creep_share"] = (dims, share, dict(units="1", long_name="share f11 / sum f11 of the wheel's contacts"))
    ds["vertical_approach"] = (("y", "side"), approach, dict(units="m", long_name="vertical approach of the wheel under its load"))
    ds["contact_count"] = (("y", "side"), (points["normal_force"] > 0).sum(-1),
                           dict(units="1", long_name="contacts carrying load"))
    for name in ("normal_force", "contact_angle", "rolling_radius", "wheel_contact_y", "rail_contact_y", "contact_Y",
                 "contact_X", "a", "b", "c11", "c22", "c23", "c33"):
        ds[name].attrs["long_name"] = f"resultant of the {model} contacts: " + ds[name].attrs["long_name"]
    ds = ds.assign_coords(point=("point", np.arange(points["gap"].shape[-1]), dict(long_name="contact of the wheel, by gap")))
    if "strip_half_length" in points:
        ds = ds.assign_coords(strip=("strip", np.arange(points["strip_half_length"].shape[-1]),
                                     dict(long_name="strip of the patch across rolling, from the flange side")))
    return ds


_ORBIT_NODES = 4096  # midpoint nodes in the angle of the orbit (Gauss-Chebyshev in y)


@dataclass(frozen=True)
class KlingelOrbit:
    """Kinematic (Klingel) orbits, one per amplitude: ``conicity`` [-], ``wavelength`` [m] and
    turning points ``y_min``, ``y_max`` [m] (amplitude ``(y_max - y_min) / 2``) about the
    ``equilibrium`` y* [m] (Δr(y*) = 0). No orbit: conicity 0, NaN turning points."""

    conicity: np.ndarray
    wavelength: np.ndarray
    equilibrium: float
    y_min: np.ndarray
    y_max: np.ndarray


def _stable_equilibrium(y, dr):
    """Δr = 0 with Δr rising through it (a minimum of the potential) nearest y = 0 [m], or None.

    A run of exact zeros between a negative and a positive value is a flat well: its middle."""
    nz = np.flatnonzero(dr != 0.0)
    found = []
    for i, j in zip(nz[:-1], nz[1:]):
        if dr[i] < 0.0 < dr[j]:
            if j == i + 1:
                found.append(y[i] - dr[i] * (y[j] - y[i]) / (dr[j] - dr[i]))
            else:
                found.append(0.5 * (y[i + 1] + y[j - 1]))
    return min(found, key=abs) if found else None


def _potential_at(y, dr, w, s, x):
    """Potential ``W(x) = ∫ Δr dy`` [m²] of the linearly interpolated Δr at points ``x`` [m]."""
    k = np.clip(np.searchsorted(y, x, side="right") - 1, 0, y.size - 2)
    t = x - y[k]
    return w[k] + t * (dr[k] + 0.5 * s[k] * t)


def _crossing(y, dr, w, s, y_eq, level, side):
    """First point beyond ``y_eq`` on ``side`` (+1 right, -1 left) where ``W`` rises above
    ``level`` (the edge of the well's level set; the far end of a flat bottom at its own level),
    or NaN if it stays below within the table."""
    ahead = (y > y_eq) if side > 0 else (y < y_eq)
    beyond = np.flatnonzero(ahead & (w > level))
    if beyond.size == 0:
        beyond = np.flatnonzero(ahead & (w >= level))
        if beyond.size == 0:
            return np.nan
    k = max(beyond[0] - 1, 0) if side > 0 else min(beyond[-1], y.size - 2)
    e, d, c = level - w[k], dr[k], s[k]  # solve W_k + d t + c t²/2 = level in [y_k, y_k+1]
    root = np.sqrt(max(d * d + 2.0 * c * e, 0.0))
    if side > 0:  # W rising through the level: W' = +root
        t = (2.0 * e / (d + root) if d + root > 0.0 else 0.0) if d >= 0.0 else (root - d) / c
    else:  # W falling through the level: W' = -root
        t = (2.0 * e / (d - root) if d - root < 0.0 else 0.0) if d <= 0.0 else -(root + d) / c
    return y[k] + min(max(t, 0.0), y[k + 1] - y[k])


def _half_period(y, dr, w, s, level, y_min, y_max):
    """``∫ dy / sqrt(level - W)`` [m^0.5] between the turning points: midpoint rule in the angle
    ``θ`` of ``y = m - A cos θ``, which takes out the square-root singularities at both ends."""
    theta = (np.arange(_ORBIT_NODES) + 0.5) * np.pi / _ORBIT_NODES
    half = 0.5 * (y_max - y_min)
    x = 0.5 * (y_max + y_min) - half * np.cos(theta)
    gap = np.maximum(level - _potential_at(y, dr, w, s, x), np.finfo(float).tiny)
    return np.pi / _ORBIT_NODES * np.sum(half * np.sin(theta) / np.sqrt(gap))


def _klingel_orbits(y, dr, y_eq, amplitudes, e0r0):
    """Orbits of ``y'' = -Δr(y) / (2 e0 r0)`` about ``y_eq`` (or None) whose half peak-to-peak
    motion is each amplitude [m].

    With the potential ``W(y) = ∫ Δr dy`` the motion conserves ``y'² e0 r0 + W``; the orbit of
    level ``E`` runs between the edges ``y_min < y* < y_max`` of the well ``W < E`` around the
    stable equilibrium ``y*`` (Δr(y*) = 0). Its wavelength is ``L = 2 sqrt(e0 r0) ∫ dy / sqrt(E - W)``
    and its conicity ``(2π)² e0 r0 / L² = π² / (∫ dy / sqrt(E - W))²`` (e0 r0 cancels). The level
    whose ``(y_max - y_min) / 2`` is the amplitude is found by Brent's method (it grows with ``E``).
    """
    h = np.diff(y)
    s = np.diff(dr) / h
    w = np.concatenate(([0.0], np.cumsum(0.5 * h * (dr[:-1] + dr[1:]))))
    n = amplitudes.size
    nan = np.full(n, np.nan)
    if y_eq is None:  # no minimum of the potential: nothing restores the wheelset
        return KlingelOrbit(np.zeros(n), np.full(n, np.inf), np.nan, nan, nan.copy())
    w_eq = float(_potential_at(y, dr, w, s, np.array([y_eq]))[0])
    top = min(w[y > y_eq].max(initial=-np.inf), w[y < y_eq].max(initial=-np.inf))

    def edges(level):
        return _crossing(y, dr, w, s, y_eq, level, -1.0), _crossing(y, dr, w, s, y_eq, level, 1.0)

    def half_width(level):
        lo, hi = edges(level)
        return 0.5 * (hi - lo)

    flat = half_width(w_eq)  # half-width of a flat bottom (Δr = 0 over it), else 0
    reach = half_width(top) if top > w_eq else 0.0  # the largest orbit inside the table
    conicity, wavelength, y_min, y_max = np.zeros(n), np.full(n, np.inf), nan.copy(), nan.copy()
    for k, amp in enumerate(amplitudes):
        if not amp <= reach:
            raise ScenarioError(f"amplitude {amp:g} m needs an orbit beyond the table's y range "
                                f"(at most {reach:g} m about y* = {y_eq:g} m)")
        if amp <= flat:  # inside a flat well: no restoring motion of that amplitude
            continue
        from scipy.optimize import brentq  # here, not at import: scipy.optimize costs 0.2-0.6 s

        level = brentq(lambda e: half_width(e) - amp, w_eq, top, xtol=1e-15 * (top - w_eq),
                       rtol=4 * np.finfo(float).eps)
        lo, hi = edges(level)
        if abs(0.5 * (hi - lo) - amp) > 1e-9 * amp:  # the well widens by a jump over a barrier here
            continue
        half = _half_period(y, dr, w, s, level, lo, hi)
        conicity[k] = np.pi**2 / half**2
        wavelength[k] = 2.0 * np.sqrt(e0r0) * half
        y_min[k], y_max[k] = lo, hi
    return KlingelOrbit(conicity, wavelength, float(y_eq), y_min, y_max)


def equivalent_conicity(table, amplitude, method="integration", full_output=False):
    """Equivalent conicity [-] by EN 15302 for a wheelset amplitude ``amplitude`` [m] (scalar or array).

    method="integration" (EN 15302, Annex B): the kinematic (Klingel) oscillation
    ``y'' = -Δr(y) / (2 e0 r0)`` about the stable equilibrium ``y*`` (Δr(y*) = 0, the one nearest
    y = 0) whose amplitude, half its peak-to-peak lateral motion, is ``amplitude``; its wavelength
    ``L`` gives ``λe = (2π)² e0 r0 / L²`` (``e0`` half the distance between the contact points and
    ``r0`` the rolling radius, at ``y*``; their product cancels from λe). Zero where no orbit of
    that amplitude exists: no well in the potential ``∫ Δr dy``, an amplitude inside a flat
    bottom, or one jumped over at a barrier. method="regression" (Annex C): slope of the
    least-squares line ``Δr = 2 λe y`` over ``|y| <= amplitude``. ``Δr(y)`` is the table's
    ``rolling_radius_difference``, interpolated linearly. ``full_output=True`` (integration) also
    returns the :class:`KlingelOrbit`.
    """
    y = np.asarray(table["y"].values, dtype=float)
    dr = np.asarray(table["rolling_radius_difference"].values, dtype=float)
    order = np.argsort(y)
    y, dr = y[order], dr[order]
    amp = np.atleast_1d(np.asarray(amplitude, dtype=float))
    if method not in ("integration", "regression"):
        raise ScenarioError(f"method must be 'integration' or 'regression', got {method!r}")
    if not np.all(amp > 0):
        raise ScenarioError(f"amplitude must be positive, got {amplitude}")
    scalar = np.ndim(amplitude) == 0
    if method == "regression":
        if np.any(amp > min(-y[0], y[-1])):
            raise ScenarioError(f"amplitude must lie in (0, {min(-y[0], y[-1]):g}] m, the range of the table")
        out = np.empty(amp.size)
        for k, A in enumerate(amp):
            m = np.abs(y) <= A + 1e-15
            out[k] = np.sum(dr[m] * y[m]) / (2.0 * np.sum(y[m] ** 2))
        return out[0] if scalar else out
    y_eq = _stable_equilibrium(y, dr)
    at = table.sel(y=0.0 if y_eq is None else y_eq, method="nearest")
    e0 = 0.5 * float(at["contact_Y"].sel(side="right") - at["contact_Y"].sel(side="left"))
    r0 = float(at["rolling_radius"].mean())
    orbit = _klingel_orbits(y, dr, y_eq, amp, e0 * r0)
    lam = orbit.conicity[0] if scalar else orbit.conicity
    return (lam, orbit) if full_output else lam
