"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1).

``rolling_contact`` solves Kalker's exact steady-state rolling problem on the half-space grid.
``contact_constants`` gives the model constants of one contact (Hertz constant, patch, Kalker's
``f11 .. f33``); ``creep_tables`` tabulates FASTSIM's creep curve for the compiled dynamics.
"""

from railwear import _numba_cache  # noqa: F401  (first: numba caches keyed on the sources)

from railwear.contact.fastsim import (  # the function, not the module, as before
    FastsimBatchResult,
    FastsimResult,
    fastsim,
    fastsim_batch,
    flexibilities,
)


def __getattr__(name):
    """The other names imported from their modules on first use (PEP 562): a run that needs the
    Hertz and Kalker constants does not import the exact rolling contact (compiled) or the
    saturation laws with the package."""
    if name in ("contact_constants", "creep_coefficients", "shear_modulus"):
        from railwear.contact import constants as module
    elif name in ("CREEP_CURVE_POINTS", "fastsim_creep_curve", "fastsim_factor_table"):
        from railwear.contact import creep_tables as module
    elif name in ("HalfSpaceContact", "HalfSpacePatch", "halfspace_contact"):
        from railwear.contact import halfspace as module
    elif name in ("HertzContact", "effective_modulus", "hertz_contact", "hertz_mnr"):
        from railwear.contact import hertz as module
    elif name in ("LinearCreepForces", "kalker_coefficients", "linear_creep_forces"):
        from railwear.contact import kalker as module
    elif name in ("RollingContact", "rolling_contact"):
        from railwear.contact import rolling as module
    elif name in ("POLACH_DRY", "POLACH_WET", "SaturatedForces", "inverse_cubic", "polach", "shen_hedrick_elkins"):
        from railwear.contact import saturation as module
    else:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    return getattr(module, name)


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
