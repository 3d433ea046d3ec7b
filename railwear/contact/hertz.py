"""Hertz's normal contact of two elastic bodies with an elliptic patch.

The undeformed gap is ``h = A x² + B y²`` with ``x`` along rolling. The patch is an ellipse with
semi-axes ``a`` (along ``x``) and ``b``; the larger semi-axis lies along the smaller curvature.
With ``F`` the normal force and ``1/E* = (1-ν1²)/E1 + (1-ν2²)/E2`` (Johnson, Contact Mechanics,
ch. 4):

    major = m [3F / (4 E* (A+B))]^(1/3),  minor = n [...]^(1/3),
    approach δ = r [(3F / (4E*))² (A+B)]^(1/3),  p0 = 3F / (2π a b).

With ``g = minor/major`` and ``K, E`` the complete elliptic integrals of modulus ``k² = 1 - g²``:
``m³ = 2E / (π g²)``, ``n = g m``, ``r = 2K / (π m)``, and ``g`` solves

    min(A,B) / max(A,B) = g² D / B_,   D = (K - E) / k²,  B_ = K - D

(``D`` and ``B_`` are the associate integrals, evaluated through Carlson's symmetric forms
``K = R_F(0, g², 1)``, ``D = R_D(0, g², 1) / 3`` so that nothing cancels near the circle).
"""

from dataclasses import dataclass

import numpy as np

from railwear.contact._checks import as_float_array, non_negative, poisson_ratio, positive
from railwear.contact._checks import scalar_or_array
from railwear.errors import ScenarioError

__all__ = ["HertzContact", "hertz_contact", "hertz_mnr", "effective_modulus"]

# smallest g² the solver resolves: beyond it the ellipse is a line for every practical purpose
_MC_MIN = 1e-300
_BISECTION_STEPS = 70


def _associate_integrals(mc):
    """K, D = (K-E)/k², B = K - D for complementary parameter ``mc = 1 - k²`` (Carlson forms)."""
    from scipy.special import elliprd, elliprf  # here, not at import (0.1-0.3 s)

    zero = np.zeros_like(mc)
    one = np.ones_like(mc)
    K = elliprf(zero, mc, one)
    D = elliprd(zero, mc, one) / 3.0
    return K, D, K - D


def _curvature_ratio(mc):
    """min(A,B)/max(A,B) of the gap that gives an ellipse with (minor/major)² = mc."""
    _, D, B = _associate_integrals(mc)
    return mc * D / B


def _solve_mc(ratio):
    """Solve ``_curvature_ratio(mc) = ratio`` for mc in (0, 1] by bisection on log(mc).

    The ratio is monotone increasing in mc (0 at a line contact, 1 at the circle), so bisection
    on the bracket [log 1e-300, 0] always converges; 70 halvings reach the double-precision
    resolution of log(mc).
    """
    lo = np.full(ratio.shape, np.log(_MC_MIN))
    hi = np.zeros(ratio.shape)
    for _ in range(_BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        too_small = _curvature_ratio(np.exp(mid)) < ratio
        lo = np.where(too_small, mid, lo)
        hi = np.where(too_small, hi, mid)
    mc = np.exp(0.5 * (lo + hi))
    return np.where(ratio >= 1.0, 1.0, mc)


def _mnr_from_ratio(ratio):
    mc = _solve_mc(ratio)
    K, D, B = _associate_integrals(mc)
    E = B + mc * D
    m = np.cbrt(2.0 * E / (np.pi * mc))
    n = np.sqrt(mc) * m
    r = 2.0 * K / (np.pi * m)
    return m, n, r


def hertz_mnr(theta):
    """Hertz's coefficients (m, n, r) for the auxiliary angle ``theta`` [rad].

    ``cos θ = |B - A| / (A + B)``; θ = π/2 is the circle (m = n = r = 1).
    """
    theta = as_float_array(theta, "theta")
    if np.any(theta <= 0.0) or np.any(theta > 0.5 * np.pi):
        raise ScenarioError("theta must lie in (0, pi/2]")
    c = np.cos(theta)
    ratio = (1.0 - c) / (1.0 + c)
    m, n, r = _mnr_from_ratio(ratio)
    return scalar_or_array(m), scalar_or_array(n), scalar_or_array(r)


def effective_modulus(youngs_modulus, poisson, youngs_modulus_2=None, poisson_2=None):
    """Contact modulus E* [Pa]: ``1/E* = (1-ν1²)/E1 + (1-ν2²)/E2``; body 2 defaults to body 1."""
    E1 = positive(youngs_modulus, "youngs_modulus")
    nu1 = poisson_ratio(poisson, "poisson")
    E2 = E1 if youngs_modulus_2 is None else positive(youngs_modulus_2, "youngs_modulus_2")
    nu2 = nu1 if poisson_2 is None else poisson_ratio(poisson_2, "poisson_2")
    return 1.0 / ((1.0 - nu1**2) / E1 + (1.0 - nu2**2) / E2)


@dataclass(frozen=True)
class HertzContact:
    """Hertz solution, SI units; arrays when the input was an array.

    a: semi-axis along rolling [m]; b: lateral semi-axis [m]; p0: peak pressure [Pa];
    approach: mutual approach of distant points δ [m].
    """

    a: np.ndarray
    b: np.ndarray
    p0: np.ndarray
    approach: np.ndarray

    @property
    def c(self):
        """Radius of the circle of equal area, ``c = sqrt(a b)`` [m]."""
        return np.sqrt(self.a * self.b)

    @property
    def a_over_b(self):
        """Ratio of the semi-axes a/b [-] (the argument of the Kalker coefficients)."""
        return self.a / self.b


def hertz_contact(normal_force, A, B, youngs_modulus, poisson, youngs_modulus_2=None, poisson_2=None):
    """Semi-axes, peak pressure and approach of a Hertz contact (vectorised, broadcasting).

    normal_force [N] >= 0; A, B [1/m] > 0 the gap curvatures ``h = A x² + B y²`` (x along
    rolling, ``A = (1/R1x + 1/R2x)/2``); youngs_modulus [Pa]; poisson [-] in [0, 0.5); the second
    body's material defaults to the first's. A zero force gives a zero patch.
    """
    F = non_negative(normal_force, "normal_force")
    A = positive(A, "A")
    B = positive(B, "B")
    e_star = effective_modulus(youngs_modulus, poisson, youngs_modulus_2, poisson_2)
    F, A, B, e_star = np.broadcast_arrays(F, A, B, e_star)

    ratio = np.minimum(A, B) / np.maximum(A, B)
    m, n, r = _mnr_from_ratio(ratio)
    scale = np.cbrt(3.0 * F / (4.0 * e_star * (A + B)))
    major, minor = m * scale, n * scale
    a = np.where(A <= B, major, minor)
    b = np.where(A <= B, minor, major)
    area = np.pi * a * b
    with np.errstate(divide="ignore", invalid="ignore"):
        p0 = np.where(area > 0.0, 1.5 * F / np.where(area > 0.0, area, 1.0), 0.0)
    approach = r * np.cbrt((3.0 * F / (4.0 * e_star)) ** 2 * (A + B))
    return HertzContact(
        a=scalar_or_array(a), b=scalar_or_array(b), p0=scalar_or_array(p0),
        approach=scalar_or_array(approach),
    )
