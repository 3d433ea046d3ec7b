"""Wear laws with internal state and their distribution over the contact patch (layer 1)."""

from railwear.wear.laws import (STEEL_DENSITY, USFD, Archard, ContactSample, EnergyLaw, Hardening,
                                InternalStateLaw, StatefulLaw, WearLaw)

__all__ = ["Archard", "ContactSample", "EnergyLaw", "Hardening", "InternalStateLaw", "STEEL_DENSITY",
           "StatefulLaw", "USFD", "WearLaw"]
