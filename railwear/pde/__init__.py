"""The evolution equation of the wheel radius: forms of h and their registry, ETDRK4 solver, dispersion relation, stability maps (layer 2)."""

from railwear.pde.evolution import solve_evolution, wavenumbers
from railwear.pde.linear import dispersion, fastest_order, unstable_band
from railwear.pde.analysis import measured_growth_map, stability_map
from railwear.pde.disk_contact import DiskContact
from railwear.pde.forms import (
    BuiltinRate, CallableRate, Cubic, Pointwise, Table, as_wear_rate, rate_names, register_rate, wear_rate,
)

__all__ = [
    "BuiltinRate", "CallableRate", "Cubic", "DiskContact", "Pointwise", "Table", "as_wear_rate", "dispersion",
    "fastest_order", "measured_growth_map", "rate_names", "register_rate", "solve_evolution", "stability_map",
    "unstable_band", "wavenumbers", "wear_rate",
]
