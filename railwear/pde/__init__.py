"""The evolution equation of the wheel radius (layer 2).

``forms`` (wear rates and their registry), ``disk_contact`` (the rigid disk wheel's rate),
``equation`` (the problem), ``solver`` (ETDRK4 loop, guards, checkpoints), ``etdrk4`` (compiled
core), ``evolution`` (:func:`solve_evolution`), ``linear`` (dispersion relation), ``analysis``
(stability maps).
"""

from railwear import _numba_cache  # noqa: F401  (numba caches keyed on the sources)

from railwear.pde.forms import (
    BuiltinRate, CallableRate, Cubic, Pointwise, Table, as_wear_rate, rate_names, register_rate, wear_rate,
)
from railwear.pde.disk_contact import DiskContact
from railwear.pde.linear import dispersion, fastest_order, unstable_band
from railwear.pde.equation import EvolutionEquation, wavenumbers
from railwear.pde.solver import ETDRK4Solver, EvolutionCheckpoint, EvolutionRun
from railwear.pde.evolution import solve_evolution
from railwear.pde.analysis import measured_growth_map, stability_map

__all__ = [
    "BuiltinRate", "CallableRate", "Cubic", "DiskContact", "ETDRK4Solver", "EvolutionCheckpoint",
    "EvolutionEquation", "EvolutionRun", "Pointwise", "Table", "as_wear_rate", "dispersion",
    "fastest_order", "measured_growth_map", "rate_names", "register_rate", "solve_evolution",
    "stability_map", "unstable_band", "wavenumbers", "wear_rate",
]
