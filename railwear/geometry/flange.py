"""Flange parameters of a wheel profile as EN 15313 defines them and profile gauges measure them.

On a :class:`~railwear.geometry.Profile` of a wheel (``y`` lateral, the flange at ``y < 0``; ``z``
the radius over the tape circle's at ``y = 0``), with the inner face of the wheel ``T = 70`` mm
inside the tape circle (``y = -T``):

    Sh = z(y_tip) - z(0)                                (flange height)
    Sd = y_d + T,    z(y_d) = z(0) + 10 mm on the flank (flange thickness)
    qR = y_d - y_q,  z(y_q) = z(y_tip) - 2 mm           (flange gradient)

``y_tip`` the highest point of the flange, the flank the profile between it and the tape circle.
The reference heights (70, 10 and 2 mm) are those of EN 15313 and of common profile gauges; the
new S1002 (EN 13715, designation h28 e32.5) has Sh 28 mm, Sd 32.5 mm, qR about 10.8 mm.

A turning that restores the design profile cuts the smallest radial depth ``d`` that puts the
design profile, lowered by ``d``, inside the worn one everywhere (:func:`restoring_depth`):

    d = max_y (z_design(y) - z_worn(y))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railwear.errors import ScenarioError

__all__ = ["FlangeParameters", "flange_parameters", "restoring_depth", "TAPE_CIRCLE", "THICKNESS_HEIGHT", "GRADIENT_DEPTH"]

TAPE_CIRCLE = 0.070  # m, inner face of the wheel to the tape circle
THICKNESS_HEIGHT = 0.010  # m above the tape circle, where Sd is measured
GRADIENT_DEPTH = 0.002  # m below the flange tip, the upper point of qR


@dataclass(frozen=True)
class FlangeParameters:
    """``height`` Sh, ``thickness`` Sd and ``gradient`` qR of a wheel profile (m)."""

    height: float
    thickness: float
    gradient: float


def flange_parameters(profile, resolution=1e-5) -> FlangeParameters:
    """Sh, Sd and qR (m) of a wheel ``profile``; the flange tip is found on a grid of
    ``resolution`` (m) and refined by the spline's slope, the flank crossings by root finding."""
    if profile.kind != "wheel":
        raise ScenarioError(f"profile {profile.name!r}: flange parameters are those of a wheel, not a {profile.kind}")
    lo = float(profile.y.min())
    if lo > -TAPE_CIRCLE / 2 or float(profile.y.max()) < 0.0:
        raise ScenarioError(f"profile {profile.name!r}: must reach from the flange (y < -35 mm) to the tape circle (y = 0)")
    from scipy.optimize import brentq  # here, not at import: scipy.optimize costs 0.2-0.6 s

    y = np.arange(lo, 0.0, resolution)
    z = profile(y)
    k = int(np.argmax(z))
    tip = y[k]
    if 0 < k < y.size - 1:
        slope = lambda s: float(profile.slope(s))  # noqa: E731
        if slope(y[k - 1]) > 0 > slope(y[k + 1]):
            tip = brentq(slope, y[k - 1], y[k + 1], xtol=1e-12)
    z_tip, z_tape = float(profile(tip)), float(profile(0.0))
    height = z_tip - z_tape
    if height <= THICKNESS_HEIGHT + GRADIENT_DEPTH:
        raise ScenarioError(f"profile {profile.name!r}: flange height {height * 1e3:.2f} mm leaves no flank to measure")

    def crossing(level):
        return brentq(lambda s: float(profile(s)) - level, tip, 0.0, xtol=1e-12)

    at_thickness = crossing(z_tape + THICKNESS_HEIGHT)
    return FlangeParameters(height, at_thickness + TAPE_CIRCLE, at_thickness - crossing(z_tip - GRADIENT_DEPTH))


def restoring_depth(design, worn, y=None) -> float:
    """``d = max_y (z_design(y) - z_worn(y))`` (m): the smallest radial depth by which the
    ``design`` profile is lowered to lie inside the ``worn`` one at every ``y`` (m; default the
    points of both profiles inside both spans). Both profiles ``z(y)`` are radii over the same
    reference (the new wheel's tape circle), as :func:`~railwear.geometry.worn_profile` gives
    them: a thinned flange, whose flank moved by ``t`` at a slope ``dz/dy``, costs ``|dz/dy| t``
    of radius."""
    if y is None:
        lo, hi = max(design.span[0], worn.span[0]), min(design.span[1], worn.span[1])
        y = np.union1d(design.y, worn.y)
        y = y[(y >= lo) & (y <= hi)]
    y = np.asarray(y, float)
    if y.size == 0:
        raise ScenarioError(f"profiles {design.name!r} and {worn.name!r} share no lateral position")
    return float(np.max(design(y) - worn(y)))
