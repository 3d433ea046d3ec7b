"""Profiles, contact geometry tables and the wear surface u(x, s); out-of-roundness analysis (layer 1)."""

from railwear.geometry.profiles import (  # noqa: E402
    Profile,
    circular_profile,
    conical_profile,
    load_profile,
    read_simpack_profile,
    worn_profile,
)
