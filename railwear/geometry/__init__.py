"""Profiles, contact geometry tables and the wear surface u(x, s); out-of-roundness analysis (layer 1)."""
