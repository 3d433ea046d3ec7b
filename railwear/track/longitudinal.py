"""The rail's longitudinal receptance at its running surface (layer 2).

A longitudinal force ``F`` on the rail head, at ``h`` above the section's neutral axis, stretches
the rail (an axial wave each way) and bends it (the moment ``F h`` turns the section by ``θ``,
which moves the head by ``h θ``). On the free infinite rail, ``e^{iωt}``:

    α_t(ω) = 1 / (iω Z) + h² (1 - i) / (4 E I k),   Z = 2 A sqrt(E ρ),   k⁴ = m ω² / (E I)

(the rod's two radiating waves: a dashpot of impedance ``Z``; Euler bending under a point
moment, the rotation receptance ``(1 - i) / (4 E I k)``). The support is left out: it holds the
rail longitudinally below a few tens of hertz, where the contact's own compliance dominates
(railwear's orders above 5 at 70 km/h pass above 40 Hz), and the rail's loss factor adds
``O(η)``. Valid while the head's bending is Euler's (wavelengths long against the rail's height:
below about 1.5 kHz for 60E1).
"""

from __future__ import annotations

import numpy as np

from railwear.errors import ScenarioError
from railwear.track.model import Rail

__all__ = ["HEAD_DISTANCE", "longitudinal_receptance"]

# Running surface above the neutral axis [m], I / W_head from EN 13674-1's section tables
# (60E1: Ix 3038.3 cm4, Wx head 333.6 cm3; 54E1: 2337.9 cm4, 278.7 cm3).
HEAD_DISTANCE = {"60E1": 3038.3 / 333.6 * 1e-2, "54E1": 2337.9 / 278.7 * 1e-2}


def longitudinal_receptance(rail: Rail, angular_frequency, head_distance=None) -> np.ndarray:
    """``α_t(ω)`` [m/N] of the module's equation at ``angular_frequency`` [rad/s, > 0]: the head's
    longitudinal displacement per unit longitudinal force on it. ``head_distance`` ``h`` [m]: from
    :data:`HEAD_DISTANCE` for a standard section."""
    if head_distance is None:
        if rail.name not in HEAD_DISTANCE:
            raise ScenarioError(f"head_distance: no running-surface height known for rail {rail.name!r}; give it (m)")
        head_distance = HEAD_DISTANCE[rail.name]
    if not 0 <= head_distance < 0.3:
        raise ScenarioError(f"head_distance: must be in [0, 0.3) m, got {head_distance!r}")
    omega = np.asarray(angular_frequency, float)
    if np.any(~np.isfinite(omega) | (omega <= 0)):
        raise ScenarioError("angular_frequency: must be finite and > 0 rad/s")
    youngs = rail.youngs_modulus
    impedance = 2 * rail.area * np.sqrt(youngs * rail.mass_per_metre / rail.area)
    k = (rail.mass_per_metre * omega**2 / (youngs * rail.second_moment)) ** 0.25
    return 1 / (1j * omega * impedance) + head_distance**2 * (1 - 1j) / (4 * youngs * rail.second_moment * k)
