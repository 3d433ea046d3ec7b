"""Wear laws with internal state and their distribution over the contact patch (layer 1)."""

from railwear.wear.laws import (STEEL_DENSITY, USFD, Archard, ContactSample, EnergyLaw, InternalStateLaw,
                                WearLaw)

__all__ = ["Archard", "ContactSample", "EnergyLaw", "InternalStateLaw", "STEEL_DENSITY", "USFD", "WearLaw"]
