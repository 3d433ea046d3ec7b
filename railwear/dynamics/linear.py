"""Linear stability: the wheelset's state matrix, the numerical state matrix of any compiled model
(``numerical_state_matrix``), closed-form and eigenvalue critical speeds.

The linear wheelset (lateral displacement ``y``, yaw ``psi``; Kalker's linear creep, conical wheels):

    m y''   + 2 f22 (y'/V - psi) + 2 f23 psi'/V + c_y y' + k_y y = 0
    I psi'' + 2 f11 (e^2 psi'/V + e lam y / r0) - 2 f23 (y'/V - psi) + 2 f33 psi'/V
            + c_psi psi' + k_psi psi = 0

With ``f23 = f33 = 0`` and no dampers the Routh-Hurwitz criterion gives the closed form of
``linear_critical_speed`` (see REFERENCES.md, "Dynamics").
"""

from __future__ import annotations

import math

import numpy as np

from railwear.dynamics import kernels as k

__all__ = ["linear_critical_speed", "wheelset_state_matrix", "critical_speed", "max_real_part", "numerical_state_matrix"]


def linear_critical_speed(
    mass,
    yaw_inertia,
    lateral_stiffness,
    yaw_stiffness,
    f11,
    f22,
    half_gauge,
    rolling_radius,
    conicity,
) -> float:
    """Linear critical speed of a single suspended wheelset [m/s], closed form.

    ``Vc^2 = 4 e r0 (I f22 + m e^2 f11)(e^2 f11 k_y + f22 k_psi)
    / [4 lam (I f22 + m e^2 f11)^2 - e r0 (m k_psi - I k_y)^2]``; ``inf`` where the
    denominator is not positive (stable at all speeds). Masses in kg, inertia in kg m^2,
    stiffnesses in N/m and N m/rad, creep coefficients in N, lengths in m.
    """
    m, inertia, ky, kpsi = float(mass), float(yaw_inertia), float(lateral_stiffness), float(yaw_stiffness)
    e, r0, lam = float(half_gauge), float(rolling_radius), float(conicity)
    f11, f22 = float(f11), float(f22)
    a = inertia * f22 + m * e * e * f11
    numerator = 4.0 * e * r0 * a * (e * e * f11 * ky + f22 * kpsi)
    denominator = 4.0 * lam * a * a - e * r0 * (m * kpsi - inertia * ky) ** 2
    if denominator <= 0.0:
        return math.inf
    return math.sqrt(numerator / denominator)


def wheelset_state_matrix(
    speed,
    mass,
    yaw_inertia,
    lateral_stiffness,
    yaw_stiffness,
    f11,
    f22,
    half_gauge,
    rolling_radius,
    conicity,
    f23=0.0,
    f33=0.0,
    lateral_damping=0.0,
    yaw_damping=0.0,
    spin_inertia=math.inf,
) -> np.ndarray:
    """State matrix ``A`` (4x4, state ``[y, psi, y', psi']``) of the linear wheelset at ``speed`` [m/s].

    With a finite axle ``spin_inertia`` J [kg m^2] the spin deviation ``omega`` is a fifth state
    (5x5). The spin deviation enters both wheels' longitudinal creepages alike
    (``-omega r0 / V``), so it leaves the yaw moment unchanged, and the antisymmetric creepages of
    ``y`` and ``psi'`` exert no net torque: to first order ``omega`` decouples, with the eigenvalue
    ``-2 f11 r0^2 / (J V)``, and the other four eigenvalues are those without it.
    """
    v = float(speed)
    m, inertia = float(mass), float(yaw_inertia)
    e, r0, lam = float(half_gauge), float(rolling_radius), float(conicity)
    spin = math.isfinite(spin_inertia)
    a = np.zeros((5, 5) if spin else (4, 4))
    a[0, 2] = 1.0
    a[1, 3] = 1.0
    # lateral force: -2 f22 (y'/V - psi) - 2 f23 psi'/V - c_y y' - k_y y
    a[2, 0] = -lateral_stiffness / m
    a[2, 1] = 2.0 * f22 / m
    a[2, 2] = -(2.0 * f22 / v + lateral_damping) / m
    a[2, 3] = -2.0 * f23 / (v * m)
    # yaw moment: -2 f11 (e^2 psi'/V + e lam y/r0) + 2 f23 (y'/V - psi) - 2 f33 psi'/V - c psi' - k psi
    a[3, 0] = -2.0 * f11 * e * lam / (r0 * inertia)
    a[3, 1] = -(2.0 * f23 + yaw_stiffness) / inertia
    a[3, 2] = 2.0 * f23 / (v * inertia)
    a[3, 3] = -(2.0 * f11 * e * e / v + 2.0 * f33 / v + yaw_damping) / inertia
    if spin:
        # J omega' = -r0 (Fx_L + Fx_R), Fx = f11 omega r0 / V on each wheel
        a[4, 4] = -2.0 * f11 * r0 * r0 / (spin_inertia * v)
    return a


def max_real_part(model, speed) -> float:
    """Largest real part [1/s] of the eigenvalues of ``model.state_matrix(speed)``."""
    return float(np.max(np.linalg.eigvals(model.state_matrix(speed)).real))


def critical_speed(model, v_min=0.5, v_max=1.0e4, n_scan=400) -> float:
    """Linear critical speed [m/s] of ``model`` from the eigenvalue crossing.

    Scans ``speed`` on a geometric grid in ``[v_min, v_max]`` for the first sign change of the
    largest real part of the state matrix's eigenvalues and refines it with Brent's method.
    Returns ``inf`` if the model is stable over the whole range. ``model`` is any object with a
    ``state_matrix(speed)`` method (the wheelset, the disk wheel, the bogie).
    """
    if not callable(getattr(model, "state_matrix", None)):
        raise TypeError(f"critical_speed: {type(model).__name__} has no linear state matrix (no hunting mode)")
    speeds = np.geomspace(v_min, v_max, n_scan)
    g_prev = max_real_part(model, speeds[0])
    lower = v_min
    while g_prev >= 0.0 and lower > 1e-6:
        # unstable already at the bottom of the scan: look lower
        upper, lower = lower, lower / 4.0
        g_low = max_real_part(model, lower)
        if g_low < 0.0:
            return _refine(model, lower, upper)
        g_prev = g_low
    if g_prev >= 0.0:
        return 0.0
    for v_lo, v_hi in zip(speeds[:-1], speeds[1:]):
        g = max_real_part(model, v_hi)
        if g >= 0.0:
            return _refine(model, v_lo, v_hi)
        g_prev = g
    return math.inf


def _refine(model, v_lo, v_hi):
    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs 0.2-0.6 s

    return brentq(lambda v: max_real_part(model, v), v_lo, v_hi, xtol=1e-14 * v_hi, rtol=4 * np.finfo(float).eps,
                  maxiter=200)


def numerical_state_matrix(kind, params, n_states, surf=None, step=1e-7) -> np.ndarray:
    """Central-difference Jacobian of the compiled right-hand side at the zero state.

    Exact to round-off where the right-hand side is linear about zero (saturation off, flange
    dead band wider than ``step``), which is how the models call it; ``surf`` is the model's
    table or surface array."""
    jac = np.empty((n_states, n_states))
    f_plus, f_minus = np.empty(n_states), np.empty(n_states)
    surf = np.zeros(0) if surf is None else surf
    rhs = k.rhs.bind(kind, 0.0, np.zeros(n_states), params, surf, f_plus)  # the entry point, no look-up per call
    for j in range(n_states):
        y = np.zeros(n_states)
        y[j] = step
        rhs(kind, 0.0, y, params, surf, f_plus)
        y[j] = -step
        rhs(kind, 0.0, y, params, surf, f_minus)
        jac[:, j] = (f_plus - f_minus) / (2.0 * step)
    return jac
