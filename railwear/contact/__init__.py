"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1)."""

from railwear.contact.fastsim import (
    FastsimBatchResult,
    FastsimResult,
    fastsim,
    fastsim_batch,
    flexibilities,
)
from railwear.contact.hertz import HertzContact, effective_modulus, hertz_contact, hertz_mnr
from railwear.contact.kalker import LinearCreepForces, kalker_coefficients, linear_creep_forces
from railwear.contact.saturation import (
    POLACH_DRY,
    POLACH_WET,
    SaturatedForces,
    polach,
    shen_hedrick_elkins,
)

__all__ = [
    "FastsimBatchResult",
    "FastsimResult",
    "HertzContact",
    "LinearCreepForces",
    "POLACH_DRY",
    "POLACH_WET",
    "SaturatedForces",
    "effective_modulus",
    "fastsim",
    "fastsim_batch",
    "flexibilities",
    "hertz_contact",
    "hertz_mnr",
    "kalker_coefficients",
    "linear_creep_forces",
    "polach",
    "shen_hedrick_elkins",
]
