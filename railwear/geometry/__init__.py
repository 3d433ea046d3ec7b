"""Profiles, contact geometry tables and the wear surface u(x, s); out-of-roundness analysis (layer 1)."""

from railwear.geometry.profiles import (  # noqa: E402
    Profile,
    circular_profile,
    conical_profile,
    load_profile,
    read_simpack_profile,
    worn_profile,
)
from railwear.geometry.contact_geometry import contact_table, equivalent_conicity, gauge_point  # noqa: E402
