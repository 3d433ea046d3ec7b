"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1)."""

from railwear.contact.hertz import HertzContact, effective_modulus, hertz_contact, hertz_mnr
from railwear.contact.kalker import LinearCreepForces, kalker_coefficients, linear_creep_forces

__all__ = [
    "HertzContact",
    "LinearCreepForces",
    "effective_modulus",
    "hertz_contact",
    "hertz_mnr",
    "kalker_coefficients",
    "linear_creep_forces",
]
