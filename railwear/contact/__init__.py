"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1).

``rolling_contact`` solves Kalker's exact steady-state rolling problem on the half-space grid.
``contact_constants`` gives the model constants of one contact (Hertz constant, patch, Kalker's
``f11 .. f33``); ``creep_tables`` tabulates FASTSIM's creep curve for the compiled dynamics.
"""

from railwear import _numba_cache  # noqa: F401  (first: numba caches keyed on the sources)

from railwear.contact.constants import contact_constants, creep_coefficients, shear_modulus
from railwear.contact.creep_tables import CREEP_CURVE_POINTS, fastsim_creep_curve, fastsim_factor_table
from railwear.contact.fastsim import (
    FastsimBatchResult,
    FastsimResult,
    fastsim,
    fastsim_batch,
    flexibilities,
)
from railwear.contact.halfspace import HalfSpaceContact, HalfSpacePatch, halfspace_contact
from railwear.contact.hertz import HertzContact, effective_modulus, hertz_contact, hertz_mnr
from railwear.contact.kalker import LinearCreepForces, kalker_coefficients, linear_creep_forces
from railwear.contact.rolling import RollingContact, rolling_contact
from railwear.contact.saturation import (
    POLACH_DRY,
    POLACH_WET,
    SaturatedForces,
    inverse_cubic,
    polach,
    shen_hedrick_elkins,
)

__all__ = [
    "CREEP_CURVE_POINTS",
    "FastsimBatchResult",
    "FastsimResult",
    "HalfSpaceContact",
    "HalfSpacePatch",
    "HertzContact",
    "LinearCreepForces",
    "POLACH_DRY",
    "POLACH_WET",
    "RollingContact",
    "SaturatedForces",
    "contact_constants",
    "creep_coefficients",
    "effective_modulus",
    "fastsim",
    "fastsim_batch",
    "fastsim_creep_curve",
    "fastsim_factor_table",
    "flexibilities",
    "halfspace_contact",
    "hertz_contact",
    "hertz_mnr",
    "kalker_coefficients",
    "linear_creep_forces",
    "polach",
    "rolling_contact",
    "shear_modulus",
    "shen_hedrick_elkins",
]
