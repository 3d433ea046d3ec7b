"""Wheel-rail contact mechanics: Hertz, Kalker's linear theory, FASTSIM, saturation (layer 1)."""
