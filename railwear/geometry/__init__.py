"""Profiles, contact geometry tables and the wear surface u(x, s); out-of-roundness analysis (layer 1)."""

from railwear.geometry.profiles import (  # noqa: E402
    Profile,
    circular_profile,
    conical_profile,
    load_profile,
    read_simpack_profile,
    worn_profile,
)

_CONTACT_GEOMETRY = ("contact_table", "equivalent_conicity", "gauge_point")


def __getattr__(name):
    """The contact geometry's entry points, imported on first use: the module brings numba and the
    contact package, which a run that reads only the out-of-roundness modules (a Fourier run,
    ``railwear plot``) does not need."""
    if name in _CONTACT_GEOMETRY:
        from railwear.geometry import contact_geometry

        return getattr(contact_geometry, name)
    raise AttributeError(f"module 'railwear.geometry' has no attribute {name!r}")
