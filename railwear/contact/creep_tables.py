"""FASTSIM's creep curve and creep-force factor, tabulated once for the compiled dynamics.

With the elliptic traction bound and no spin, FASTSIM's traction keeps the direction of
``(f11 ξ, f22 η)`` and its size ``F / (μ N)`` depends on ``s = |(f11 ξ, f22 η)| / (μ N)`` alone,
whatever the load, friction, modulus or patch shape. Both tables are on ``CREEP_CURVE_POINTS``
equal steps of ``r = s / (1 + s)`` in ``[0, 1]`` (``r = 1``: full slip) and are read by
``railwear.dynamics.kernels.creep_curve`` / ``creep_factor``.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from railwear.contact.fastsim import fastsim
from railwear.contact.kalker import kalker_coefficients

__all__ = ["CREEP_CURVE_POINTS", "fastsim_creep_curve", "fastsim_factor_table", "fastsim_ratio"]

CREEP_CURVE_POINTS = 257


def fastsim_ratio(s) -> float:
    """FASTSIM's ``F / (μ N)`` for pure longitudinal creepage at ``s = f11 ξ / (μ N)`` (elliptic
    traction bound, the default 40 x 40 grid, on a fixed patch: the ratio depends on ``s`` only)."""
    a, b, normal, mu, shear, poisson = 6e-3, 6e-3, 1e5, 0.3, 8e10, 0.28
    f11 = shear * a * b * float(kalker_coefficients(a / b, poisson)[0])
    return -fastsim(a, b, normal, s * mu * normal / f11, 0.0, 0.0, mu, shear, poisson).Fx / (mu * normal)


@lru_cache(maxsize=None)
def fastsim_creep_curve() -> np.ndarray:
    """``F / (μ N)`` at ``r = s / (1 + s)`` (read-only, computed once): pure longitudinal creep."""
    r = np.linspace(0.0, 1.0, CREEP_CURVE_POINTS)
    curve = np.ones_like(r)
    for i, ri in enumerate(r[:-1]):
        curve[i] = fastsim_ratio(ri / (1.0 - ri))
    curve.setflags(write=False)
    return curve


@lru_cache(maxsize=None)
def fastsim_factor_table() -> np.ndarray:
    """FASTSIM as a factor on Kalker's linear forces, ``F / F_lin = (F / (μ N)) / s``, on the grid
    of ``fastsim_creep_curve`` (read-only); exact for combined ``ξ, η`` without spin. At ``s = 0``
    it is FASTSIM's discretised linear slope, ``1 + 1 / (2 ny²)`` for ``ny`` strips."""
    r = np.linspace(0.0, 1.0, CREEP_CURVE_POINTS)
    factor = np.zeros_like(r)
    inner = slice(1, -1)
    factor[inner] = fastsim_creep_curve()[inner] * (1.0 - r[inner]) / r[inner]
    tiny = 1e-9
    factor[0] = fastsim_ratio(tiny) / tiny
    factor.setflags(write=False)
    return factor
