"""Compiled right-hand sides of the dynamics models and their dispatch (numba, ``cache=True``).

Every model is a top-level ``@njit`` function ``f(t, y, p, surf, dydt)`` taking its parameters as a
float64 array ``p`` (index constants below) and, for the disk wheel, the radius deviation grid in
``surf``. ``rhs(kind, ...)`` selects the model by an integer, so the integrators in
``railwear.dynamics.integrators`` compile the loop and the model together without closures.

Note for developers: numba's cache is keyed on the file of the cached function only. After editing
this module, delete the ``*.nbi``/``*.nbc`` files of ``railwear/dynamics/__pycache__`` so that the
cached integrators are recompiled against the new right-hand sides.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

# model kinds
KIND_LINEAR = 0  # y' = A y, A in p[1:] (n = p[0]); tests of the integrators
KIND_VAN_DER_POL = 1  # y0' = y1, y1' = mu (1 - y0^2) y1 - y0, mu = p[0]; stiff test
KIND_WHEELSET = 2
KIND_DISK_WHEEL = 3

# ---- wheelset parameters --------------------------------------------------------------------
WS_SPEED = 0
WS_MASS = 1
WS_YAW_INERTIA = 2
WS_LATERAL_STIFFNESS = 3
WS_YAW_STIFFNESS = 4
WS_LATERAL_DAMPING = 5
WS_YAW_DAMPING = 6
WS_F11 = 7
WS_F22 = 8
WS_F23 = 9
WS_F33 = 10
WS_HALF_GAUGE = 11
WS_ROLLING_RADIUS = 12
WS_CONICITY = 13
WS_WHEEL_LOAD = 14
WS_FRICTION = 15  # inf: no saturation
WS_FLANGE_CLEARANCE = 16
WS_FLANGE_STIFFNESS = 17
WS_N_PARAMS = 18
WS_N_OUTPUTS = 18  # see wheelset_outputs

# ---- disk wheel parameters ------------------------------------------------------------------
DW_SPEED = 0
DW_RADIUS = 1
DW_WHEEL_MASS = 2
DW_WHEEL_INERTIA = 3
DW_SPRUNG_MASS = 4  # 0: rigid frame (no sprung-mass motion)
DW_PRIMARY_STIFFNESS = 5
DW_PRIMARY_DAMPING = 6
DW_RAIL_MASS = 7  # 0: rigid rail
DW_PAD_STIFFNESS = 8
DW_PAD_DAMPING = 9
DW_HERTZ_CONSTANT = 10  # N = k_H delta^(3/2)
DW_STATIC_LOAD = 11
DW_STATIC_APPROACH = 12
DW_F11 = 13  # at the static load; scales with (N/W)^(2/3)
DW_FRICTION = 14
DW_TORQUE = 15
DW_PATCH_HALF_ANGLE = 16  # a / R0 [rad]; 0: point contact
DW_INITIAL_ANGLE = 17
DW_N_CELLS = 18
DW_N_PARAMS = 19
DW_N_OUTPUTS = 7  # see disk_wheel_outputs

TWO_PI = 2.0 * math.pi


@njit(cache=True, inline="always")
def saturation_factor(force, limit):
    """Johnson-Vermeulen cubic saturation (Shen, Hedrick & Elkins 1983): factor on linear forces.

    ``r = F/(mu N)``; factor ``1 - r/3 + r^2/27`` for ``r < 3``, ``1/r`` above; 0 without load.
    """
    if limit <= 0.0:
        return 0.0
    r = force / limit
    if r < 3.0:
        return 1.0 - r / 3.0 + r * r / 27.0
    return 1.0 / r


# ---- wheelset -------------------------------------------------------------------------------
@njit(cache=True, inline="always")
def _wheel(sign, y, p):
    """Creepages, forces and frictional power of one wheel (``sign`` +1 left at ``+e``, -1 right).

    ``xi = -sign (e psi'/V + lam y/r0)``, ``eta = y'/V - psi``, ``phi = psi'/V - sign lam/r0``;
    ``Fx = -f11 xi``, ``Fy = -f22 eta - f23 phi``, ``Mz = f23 eta - f33 phi``, all scaled by the
    saturation factor of ``|(Fx, Fy)|``; power ``-V (Fx xi + Fy eta + Mz phi)``.
    """
    v = p[WS_SPEED]
    r0 = p[WS_ROLLING_RADIUS]
    lam = p[WS_CONICITY]
    eta = y[2] / v - y[1]
    xi = -sign * (p[WS_HALF_GAUGE] * y[3] / v + lam * y[0] / r0)
    phi = y[3] / v - sign * lam / r0
    fx = -p[WS_F11] * xi
    fy = -p[WS_F22] * eta - p[WS_F23] * phi
    mz = p[WS_F23] * eta - p[WS_F33] * phi
    s = saturation_factor(math.sqrt(fx * fx + fy * fy), p[WS_FRICTION] * p[WS_WHEEL_LOAD])
    fx *= s
    fy *= s
    mz *= s
    return xi, eta, phi, fx, fy, mz, -v * (fx * xi + fy * eta + mz * phi)


@njit(cache=True, inline="always")
def _flange(lateral, p):
    """Flange force [N]: a linear spring outside the dead band ``|y| <= clearance``."""
    d = p[WS_FLANGE_CLEARANCE]
    if lateral > d:
        return -p[WS_FLANGE_STIFFNESS] * (lateral - d)
    if lateral < -d:
        return -p[WS_FLANGE_STIFFNESS] * (lateral + d)
    return 0.0


@njit(cache=True, inline="always")
def wheelset_rhs(t, y, p, surf, dydt):
    """Suspended wheelset on straight track: state ``[y, psi, y', psi']``.

    ``m y'' = Fy_L + Fy_R + F_flange - k_y y - c_y y'``,
    ``I psi'' = e (Fx_R - Fx_L) + Mz_L + Mz_R - k_psi psi - c_psi psi'``; Kalker's linear creep
    forces with optional spin and Johnson-Vermeulen saturation, conical wheels, flange dead band,
    small yaw angles, constant wheel spin ``V / r0``.
    """
    _, _, _, fx_l, fy_l, mz_l, _ = _wheel(1.0, y, p)
    _, _, _, fx_r, fy_r, mz_r, _ = _wheel(-1.0, y, p)
    force = fy_l + fy_r + _flange(y[0], p) - p[WS_LATERAL_STIFFNESS] * y[0] - p[WS_LATERAL_DAMPING] * y[2]
    moment = p[WS_HALF_GAUGE] * (fx_r - fx_l) + mz_l + mz_r - p[WS_YAW_STIFFNESS] * y[1] - p[WS_YAW_DAMPING] * y[3]
    dydt[0] = y[2]
    dydt[1] = y[3]
    dydt[2] = force / p[WS_MASS]
    dydt[3] = moment / p[WS_YAW_INERTIA]


@njit(cache=True)
def wheelset_outputs(t, y, p, surf, out):
    """Outputs per time: per wheel (left 0-7, right 8-15) ``xi, eta, phi, Fx, Fy, Mz, power, s``
    (``s`` the contact position on the tread towards the flange, ``+-y``); 16 flange force;
    17 contact angle on the wheel ``V t / r0 mod 2 pi``."""
    for w in range(2):
        sign = 1.0 - 2.0 * w
        vals = _wheel(sign, y, p)
        for k in range(7):
            out[8 * w + k] = vals[k]
        out[8 * w + 7] = sign * y[0]
    out[16] = _flange(y[0], p)
    out[17] = (p[WS_SPEED] * t / p[WS_ROLLING_RADIUS]) % TWO_PI


# ---- disk wheel -----------------------------------------------------------------------------
@njit(cache=True, inline="always")
def surface_primitive(surf, n, x):
    """Integral of the periodic piecewise-linear ``u`` from 0 to ``x`` [m rad].

    ``surf[:n]`` holds ``u`` at the nodes ``x_j = 2 pi j / n``, ``surf[n:2n+1]`` its cumulative
    trapezoidal integral at the nodes (``surf[2n]`` over one period).
    """
    dx = TWO_PI / n
    periods = math.floor(x / TWO_PI)
    xr = x - periods * TWO_PI
    j = int(xr / dx)
    if j >= n:
        j = n - 1
    s = xr - j * dx
    u0 = surf[j]
    u1 = surf[(j + 1) % n]
    return periods * surf[2 * n] + surf[n + j] + u0 * s + (u1 - u0) * s * s / (2.0 * dx)


@njit(cache=True, inline="always")
def surface_value(surf, n, x):
    """Piecewise-linear periodic interpolation of ``u`` at angle ``x`` [m]."""
    dx = TWO_PI / n
    xr = x - math.floor(x / TWO_PI) * TWO_PI
    j = int(xr / dx)
    if j >= n:
        j = n - 1
    s = (xr - j * dx) / dx
    return (1.0 - s) * surf[j] + s * surf[(j + 1) % n]


@njit(cache=True, inline="always")
def patch_average(surf, n, x, half_angle):
    """Contact filter: mean of ``u`` over ``[x - w, x + w]``, ``w`` the patch half-angle [m]."""
    if n == 0:
        return 0.0
    if half_angle <= 0.0:
        return surface_value(surf, n, x)
    hi = surface_primitive(surf, n, x + half_angle)
    lo = surface_primitive(surf, n, x - half_angle)
    return (hi - lo) / (2.0 * half_angle)


@njit(cache=True, inline="always")
def _disk_contact(t, y, p, surf):
    """Contact of the disk wheel: ``(N, creepage, Fx, power, x_c mod 2 pi, u_bar, delta)``.

    ``N = k_H delta_+^(3/2)``; creepage ``xi = (Omega (R0 + u_bar) - V) / V``;
    ``Fx = f11 (N/W)^(2/3) xi`` (Kalker, ``c^2 ~ N^(2/3)``) with saturation at ``mu N``;
    frictional power ``Fx xi V``.
    """
    v = p[DW_SPEED]
    r0 = p[DW_RADIUS]
    xc = p[DW_INITIAL_ANGLE] + v / r0 * t + y[0]
    ubar = patch_average(surf, int(p[DW_N_CELLS]), xc, p[DW_PATCH_HALF_ANGLE])
    delta = p[DW_STATIC_APPROACH] + y[6] - y[2] + ubar
    normal = 0.0
    if delta > 0.0:
        normal = p[DW_HERTZ_CONSTANT] * delta * math.sqrt(delta)
    creepage = (y[1] * (r0 + ubar) - v) / v
    force = 0.0
    if normal > 0.0:
        f11 = p[DW_F11] * (normal / p[DW_STATIC_LOAD]) ** (2.0 / 3.0)
        force = f11 * creepage
        force *= saturation_factor(abs(force), p[DW_FRICTION] * normal)
    return normal, creepage, force, force * creepage * v, xc - math.floor(xc / TWO_PI) * TWO_PI, ubar, delta


@njit(cache=True, inline="always")
def disk_wheel_rhs(t, y, p, surf, dydt):
    """Disk wheel (paper Fig. 5), state ``[phi, Omega, z_w, z_w', z_s, z_s', z_r, z_r']``.

    Wheel angle ``theta = V t / R0 + phi``; contact angle ``x_c = x0 + theta``; vertical
    displacements upward from static equilibrium. ``J Omega' = T - (R0 + u_bar) Fx``,
    ``m_w z_w'' = -P + N - W``, ``m_s z_s'' = P``, ``m_r z_r'' = -k_p z_r - c_p z_r' - (N - W)``,
    ``P = k_1 (z_w - z_s) + c_1 (z_w' - z_s')``, ``delta = delta_0 + z_r - z_w + u_bar(x_c)``.
    The sprung mass carries a dead load (the car body), so the static load ``W`` is a parameter.
    """
    normal, _, force, _, _, ubar, _ = _disk_contact(t, y, p, surf)
    r0 = p[DW_RADIUS]
    dydt[0] = y[1] - p[DW_SPEED] / r0
    dydt[1] = (p[DW_TORQUE] - (r0 + ubar) * force) / p[DW_WHEEL_INERTIA]
    if p[DW_SPRUNG_MASS] > 0.0:
        primary = p[DW_PRIMARY_STIFFNESS] * (y[2] - y[4]) + p[DW_PRIMARY_DAMPING] * (y[3] - y[5])
        dydt[4] = y[5]
        dydt[5] = primary / p[DW_SPRUNG_MASS]
    else:
        primary = p[DW_PRIMARY_STIFFNESS] * y[2] + p[DW_PRIMARY_DAMPING] * y[3]
        dydt[4] = 0.0
        dydt[5] = 0.0
    dydt[2] = y[3]
    dydt[3] = (normal - p[DW_STATIC_LOAD] - primary) / p[DW_WHEEL_MASS]
    if p[DW_RAIL_MASS] > 0.0:
        dydt[6] = y[7]
        dydt[7] = (-p[DW_PAD_STIFFNESS] * y[6] - p[DW_PAD_DAMPING] * y[7] - (normal - p[DW_STATIC_LOAD])) / p[DW_RAIL_MASS]
    else:
        dydt[6] = 0.0
        dydt[7] = 0.0


@njit(cache=True)
def disk_wheel_outputs(t, y, p, surf, out):
    """Outputs per time: ``N, creepage, Fx, power, x_c, u_bar, delta`` (see ``_disk_contact``)."""
    vals = _disk_contact(t, y, p, surf)
    for k in range(DW_N_OUTPUTS):
        out[k] = vals[k]


@njit(cache=True, inline="always")
def disk_wheel_event(t, y, p, surf):
    """Contact event function: the approach ``delta`` [m]; zero at contact loss and regain."""
    return _disk_contact(t, y, p, surf)[6]


# ---- test systems ---------------------------------------------------------------------------
@njit(cache=True, inline="always")
def linear_rhs(t, y, p, surf, dydt):
    """``y' = A y`` with ``n = p[0]`` and ``A = p[1:1+n*n]`` row by row."""
    n = int(p[0])
    for i in range(n):
        acc = 0.0
        for j in range(n):
            acc += p[1 + i * n + j] * y[j]
        dydt[i] = acc


@njit(cache=True, inline="always")
def van_der_pol_rhs(t, y, p, surf, dydt):
    """Van der Pol oscillator ``y'' = mu (1 - y^2) y' - y`` (stiff for large ``mu = p[0]``)."""
    dydt[0] = y[1]
    dydt[1] = p[0] * (1.0 - y[0] * y[0]) * y[1] - y[0]


# ---- dispatch -------------------------------------------------------------------------------
@njit(cache=True)
def rhs(kind, t, y, p, surf, dydt):
    """Right-hand side of model ``kind`` into ``dydt``."""
    if kind == KIND_WHEELSET:
        wheelset_rhs(t, y, p, surf, dydt)
    elif kind == KIND_DISK_WHEEL:
        disk_wheel_rhs(t, y, p, surf, dydt)
    elif kind == KIND_LINEAR:
        linear_rhs(t, y, p, surf, dydt)
    elif kind == KIND_VAN_DER_POL:
        van_der_pol_rhs(t, y, p, surf, dydt)


@njit(cache=True)
def event(kind, t, y, p, surf):
    """Event function of model ``kind`` (sign changes are events); 1 where a model has none."""
    if kind == KIND_DISK_WHEEL:
        return disk_wheel_event(t, y, p, surf)
    return 1.0


@njit(cache=True)
def outputs(kind, ts, ys, p, surf, n_out):
    """Derived quantities at every output time: array ``(len(ts), n_out)``."""
    res = np.zeros((ts.shape[0], n_out))
    for i in range(ts.shape[0]):
        if kind == KIND_WHEELSET:
            wheelset_outputs(ts[i], ys[i], p, surf, res[i])
        elif kind == KIND_DISK_WHEEL:
            disk_wheel_outputs(ts[i], ys[i], p, surf, res[i])
    return res
