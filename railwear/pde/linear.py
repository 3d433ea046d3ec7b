"""The dispersion relation of the linearised evolution equation: growth rate, unstable band, fastest order.

About a state where ``∂h/∂u_xx = -a`` (rad² per unit normed time) the harmonic ``cos(k x)`` of
``(1 - nu ∂xx) u_T = h - epsilon u_xxxx`` grows at ``σ(k) = (a k² - epsilon k⁴) / (1 + nu k²)``.
"""

import numpy as np


def dispersion(a, k, epsilon=0.0, nu=0.0):
    """Linear growth rate of ``cos(k x)`` for ``∂h/∂u_xx = -a`` (per unit normed time).

    ``σ(k) = (a k² - epsilon k⁴) / (1 + nu k²)``; ``a > 0`` is the anti-diffusive (unstable)
    case. Broadcasts over its arguments.
    """
    k2 = np.asarray(k, float) ** 2
    return (np.asarray(a, float) * k2 - epsilon * k2**2) / (1.0 + nu * k2)


def unstable_band(a, epsilon=0.0, nu=0.0):
    """``(k_max, k_fastest)``: upper edge of the unstable band and the fastest real wavenumber.

    ``σ > 0`` for ``0 < k < sqrt(a / epsilon)``; ``dσ/dk = 0`` where
    ``epsilon nu K² + 2 epsilon K - a = 0`` with ``K = k²``. Without ``epsilon`` both are infinite
    (no mode is preferred); with ``a <= 0`` the band is empty and both are 0.
    """
    if a <= 0:
        return 0.0, 0.0
    if epsilon == 0:
        return np.inf, np.inf
    if nu == 0:
        K = a / (2 * epsilon)
    else:
        K = (-epsilon + np.sqrt(epsilon**2 + epsilon * nu * a)) / (epsilon * nu)
    return float(np.sqrt(a / epsilon)), float(np.sqrt(K))


def fastest_order(a, epsilon=0.0, nu=0.0, highest=None):
    """The integer polygon order ``n >= 1`` with the largest growth rate (0 if none grows)."""
    k_edge, k_fast = unstable_band(a, epsilon, nu)
    if k_edge == 0:
        return 0
    if not np.isfinite(k_fast):
        return int(highest) if highest is not None else 0
    candidates = np.array([max(1, np.floor(k_fast)), np.ceil(k_fast)])
    return int(candidates[np.argmax(dispersion(a, candidates, epsilon, nu))])
