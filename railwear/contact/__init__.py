"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1)."""

from railwear.contact.hertz import HertzContact, effective_modulus, hertz_contact, hertz_mnr

__all__ = ["HertzContact", "effective_modulus", "hertz_contact", "hertz_mnr"]
