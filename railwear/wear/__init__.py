"""Wear laws with internal state and their distribution over the contact patch (layer 1)."""

from railwear.wear.laws import STEEL_DENSITY, USFD, Archard, EnergyLaw, InternalStateLaw

__all__ = ["Archard", "EnergyLaw", "InternalStateLaw", "STEEL_DENSITY", "USFD"]
