"""Creep-force saturation laws: Shen-Hedrick-Elkins and Polach.

Shen, Hedrick & Elkins (1983): the resultant of Kalker's linear forces ``F = |(Fx, Fy)|`` is
replaced by ``μN (β - β²/3 + β³/27)`` for ``β = F/(μN) <= 3`` and by ``μN`` above; every
component (and the spin moment) is scaled by the same factor.

Polach (Vehicle System Dynamics 33 suppl. (1999) 728; Wear 258 (2005) 992): with the creepage
``s = |(ξ, η)|`` and the gradient of the tangential stress ``ε = (1/4) G π a b C s / (μ N)``,
``C = sqrt((C11 ξ/s)² + (C22 η/s)²)``,

    F = (2 μ N / π) [kA ε / (1 + (kA ε)²) + arctan(kS ε)],

and friction falling with the slip velocity ``w = s V``: ``μ = μ0 ((1 - A) exp(-B w) + A)``.
At small creepage and ``kA = kS = 1`` this is Kalker's linear theory. Spin is not included here.

The inverse of the cubic law for a longitudinal force demand (:func:`inverse_cubic`): with
``β = k ξ / (μN)`` (``k`` Kalker's creep stiffness) the law reads ``F/(μN) = 1 - (1 - ξ/ξ_s)³``,
``ξ_s = 3 μN / k`` the saturation creepage, so ``ξ = ξ_s (1 - (1 - F/(μN))^(1/3))``.
"""

from dataclasses import dataclass

import numpy as np

from railwear.contact._checks import as_float_array, non_negative, positive, scalar_or_array
from railwear.contact.kalker import kalker_coefficients

__all__ = ["SaturatedForces", "shen_hedrick_elkins", "inverse_cubic", "polach", "POLACH_DRY", "POLACH_WET"]

# Polach (2005), parameters fitted to locomotive measurements, dry and wet rail. B in s/m.
POLACH_DRY = {"kA": 1.00, "kS": 0.40, "mu0": 0.55, "A": 0.40, "B": 0.60}
POLACH_WET = {"kA": 0.30, "kS": 0.10, "mu0": 0.30, "A": 0.40, "B": 0.20}


@dataclass(frozen=True)
class SaturatedForces:
    """Saturated creep forces Fx, Fy [N], Mz [N m] and the friction coefficient used [-]."""

    Fx: np.ndarray
    Fy: np.ndarray
    Mz: np.ndarray
    mu: np.ndarray


def shen_hedrick_elkins(Fx, Fy, normal_force, mu, Mz=0.0):
    """Shen-Hedrick-Elkins saturation of linear creep forces Fx, Fy [N] (and Mz [N m]).

    normal_force [N] >= 0, mu [-] >= 0. Vectorised. The resultant never exceeds ``μN``.
    """
    Fx = as_float_array(Fx, "Fx")
    Fy = as_float_array(Fy, "Fy")
    Mz = as_float_array(Mz, "Mz")
    N = non_negative(normal_force, "normal_force")
    mu = non_negative(mu, "mu")
    F = np.hypot(Fx, Fy)
    limit = mu * N
    with np.errstate(divide="ignore", invalid="ignore"):
        beta = np.where(limit > 0.0, F / np.where(limit > 0.0, limit, 1.0), np.inf)
        sat = np.where(beta <= 3.0, limit * (beta - beta**2 / 3.0 + beta**3 / 27.0), limit)
        scale = np.where(F > 0.0, sat / np.where(F > 0.0, F, 1.0), 1.0)
    scale = np.where(limit > 0.0, scale, 0.0)
    return SaturatedForces(
        Fx=scalar_or_array(Fx * scale), Fy=scalar_or_array(Fy * scale), Mz=scalar_or_array(Mz * scale),
        mu=scalar_or_array(mu + 0.0 * F),
    )


def inverse_cubic(force, limit):
    """The creepage at which the cubic law's force reaches the demand ``force`` (N, >= 0) under
    ``limit = μN`` (N, > 0), as a fraction of the saturation creepage ``ξ_s = 3 μN / k``:
    ``(q, r)`` with ``q = min(F/(μN), 1)`` and ``r = ξ/ξ_s = 1 - (1 - q)^(1/3)``. At ``q = 1`` (a
    demand at or above ``μN``) the wheel slides at ``ξ_s`` under ``μN`` (``r = 1``). Vectorised;
    the caller multiplies by its ``ξ_s``."""
    q = np.minimum(force / limit, 1.0)
    return q, 1 - np.cbrt(1 - q)


def polach(a, b, normal_force, xi, eta, shear_modulus, poisson, mu0=None, speed=0.0,
           kA=1.0, kS=1.0, A=1.0, B=0.0, params=None):
    """Polach's creep forces for semi-axes a (rolling), b [m], creepages ξ, η [-].

    normal_force [N]; shear_modulus [Pa]; poisson [-]; speed V [m/s] (only for falling
    friction); kA, kS reduction factors [-]; A = μ∞/μ0 [-]; B [s/m]. ``params`` may be
    :data:`POLACH_DRY` or :data:`POLACH_WET` (or any dict with these keys); explicit keyword
    values are overridden by it. Returns :class:`SaturatedForces` (Mz = 0). Vectorised.
    """
    if params is not None:
        kA, kS, mu0, A, B = params["kA"], params["kS"], params["mu0"], params["A"], params["B"]
    if mu0 is None:
        raise TypeError("polach() needs mu0 or params")
    a = positive(a, "a")
    b = positive(b, "b")
    N = non_negative(normal_force, "normal_force")
    G = positive(shear_modulus, "shear_modulus")
    xi = as_float_array(xi, "xi")
    eta = as_float_array(eta, "eta")
    mu0 = non_negative(mu0, "mu0")
    V = non_negative(speed, "speed")
    kA = positive(kA, "kA")
    kS = positive(kS, "kS")
    A = non_negative(A, "A")
    B = non_negative(B, "B")
    c11, c22, _, _ = (np.asarray(c) for c in kalker_coefficients(a / b, poisson))
    s = np.hypot(xi, eta)
    mu = mu0 * ((1.0 - A) * np.exp(-B * s * V) + A)
    with np.errstate(divide="ignore", invalid="ignore"):
        safe_s = np.where(s > 0.0, s, 1.0)
        C = np.where(s > 0.0, np.hypot(c11 * xi / safe_s, c22 * eta / safe_s), c11)
        limit = mu * N
        eps = np.where(limit > 0.0, 0.25 * G * np.pi * a * b * C * s / np.where(limit > 0.0, limit, 1.0), 0.0)
    F = 2.0 * limit / np.pi * (kA * eps / (1.0 + (kA * eps) ** 2) + np.arctan(kS * eps))
    Fx = -F * xi / safe_s
    Fy = -F * eta / safe_s
    return SaturatedForces(Fx=scalar_or_array(Fx), Fy=scalar_or_array(Fy),
                           Mz=scalar_or_array(0.0 * F), mu=scalar_or_array(mu))
