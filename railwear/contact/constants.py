"""Model constants of one wheel-rail contact from Hertz and Kalker's linear theory.

Kalker's linear creep coefficients (Kalker 1990, App. E; see ``railwear.contact.kalker``) with
``c² = a b`` and ``G = E / (2 (1 + ν))``:

    f11 = G c² C11,   f22 = G c² C22,   f23 = G c³ C23,   f33 = G c⁴ C33

so that ``Fx = -f11 ξ``, ``Fy = -f22 η - f23 φ``, ``Mz = f23 η - f33 φ``.
"""

from __future__ import annotations

import numpy as np

from railwear.contact.hertz import hertz_contact
from railwear.contact.kalker import kalker_coefficients

__all__ = ["contact_constants", "creep_coefficients", "shear_modulus"]


def shear_modulus(youngs_modulus, poisson):
    """``G = E / (2 (1 + ν))`` [Pa] from Young's modulus [Pa] and Poisson's ratio."""
    return youngs_modulus / (2.0 * (1.0 + poisson))


def creep_coefficients(shear, a, b, c11, c22, c23, c33):
    """Kalker's ``(f11, f22, f23, f33)`` [N, N, N m, N m²] from the shear modulus [Pa], the
    semi-axes ``a`` (along rolling), ``b`` [m] and the coefficients ``C11 .. C33``; broadcasts."""
    c2 = a * b
    return shear * c2 * c11, shear * c2 * c22, shear * c2 * np.sqrt(c2) * c23, shear * c2 * c2 * c33


def contact_constants(static_load, A, B, youngs_modulus, poisson) -> dict:
    """Hertz and Kalker constants of one wheel-rail contact at ``static_load`` [N].

    ``A, B`` [1/m]: gap curvatures (``A`` along rolling), steel ``youngs_modulus`` [Pa] and
    ``poisson`` for both bodies. Returns ``hertz_constant`` [N/m^1.5] (``N = k_H δ^(3/2)``
    through the static point; exact for Hertz since ``δ ~ N^(2/3)``), ``static_approach`` [m],
    ``patch_half_length`` (``a``) [m] and ``f11, f22, f23, f33`` (``creep_coefficients``).
    """
    patch = hertz_contact(static_load, A, B, youngs_modulus, poisson)
    a, b, approach = float(patch.a), float(patch.b), float(patch.approach)
    c11, c22, c23, c33 = (float(c) for c in kalker_coefficients(a / b, poisson))
    f11, f22, f23, f33 = creep_coefficients(shear_modulus(youngs_modulus, poisson), a, b, c11, c22, c23, c33)
    return {
        "hertz_constant": static_load / approach**1.5,
        "static_approach": approach,
        "patch_half_length": a,
        "f11": f11,
        "f22": f22,
        "f23": float(f23),
        "f33": f33,
    }
