"""Short-time multibody dynamics: disk wheel, wheelset, bogie (layer 2)."""
