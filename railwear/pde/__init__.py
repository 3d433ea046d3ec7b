"""The evolution equation of the wheel radius: forms of h, ETDRK4 solver, linear analysis (layer 2)."""

from railwear.pde.evolution import dispersion, solve_evolution, wavenumbers
from railwear.pde.forms import CallableRate, Cubic, Pointwise, Table, as_wear_rate

__all__ = [
    "CallableRate", "Cubic", "Pointwise", "Table", "as_wear_rate", "dispersion",
    "solve_evolution", "wavenumbers",
]
