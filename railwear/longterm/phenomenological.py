"""Strategy 4 of the paper: the phenomenological evolution equation ``u_T = h(u_xx; u, u_x, v)``,
here ``h(u_xx; v) + drift(v) u_x + dispersion(v) u_xxx`` (as fitted by :mod:`railwear.longterm.fitting`)."""

from dataclasses import dataclass, field, fields

import numpy as np

from railwear.longterm.base import Checkpoint, Strategy
from railwear.longterm.spectra import describe
from railwear.pde import as_wear_rate, solve_evolution
from railwear.units import KM


@dataclass(frozen=True)
class Phenomenological(Strategy, name="phenomenological"):
    """Evolve a wheel's radius deviation under a wear-rate form ``h`` at one or more speeds (m/s),
    with the odd terms ``drift u_x + dispersion u_xxx`` (rad and rad³ per unit normed time; one
    value or one per speed); ``life_distance`` (m) is one unit of normed time; ``radius`` (m) the
    wheel's nominal radius, for the band levels in wavelength (``None``: none)."""

    checkpoint_format = "evolution"

    h: object
    speed: float | np.ndarray
    epsilon: float = 0.0
    nu: float = 0.0
    drift: float | np.ndarray = 0.0
    dispersion: float | np.ndarray = 0.0
    options: dict = field(default_factory=dict)
    life_distance: float = 5e7
    radius: float | None = None

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """Solve to normed time ``until`` or removed depth ``depth_limit`` (m); add the wheel's spectrum.

        ``checkpoint`` is called with a :class:`~railwear.longterm.base.Checkpoint` of the PDE
        solver's state after each output interval; ``resume`` continues from one.
        """
        save, resume = solver_checkpoints(self.name, checkpoint, resume)
        ds = solve_evolution(u0, until, as_wear_rate(self.h), self.speed, self.epsilon, self.nu,
                             depth_limit=depth_limit, progress=progress, checkpoint=save,
                             resume=resume, drift=self.drift, dispersion=self.dispersion, **self.options)
        return finish(ds, self.name, self.life_distance, "phenomenological evolution equation", self.radius)


def solver_checkpoints(name, checkpoint, resume):
    """The PDE solver's ``(checkpoint, resume)`` for a strategy's: its states wrapped in and
    unwrapped from a :class:`~railwear.longterm.base.Checkpoint` of kind ``name``."""
    from railwear.pde.evolution import EvolutionCheckpoint

    save = None
    if checkpoint is not None:
        def save(cp):
            checkpoint(Checkpoint(name, cp.fingerprint, {f.name: getattr(cp, f.name) for f in fields(cp)}))
        save.due = getattr(checkpoint, "due", lambda: True)
    if resume is not None:
        resume.check(name, resume.fingerprint)
        resume = EvolutionCheckpoint(**resume.fields)
    return save, resume


def finish(ds, name, life_distance, description, radius=None):
    """A solved evolution equation as a strategy's result: the cost in ETDRK4 steps, the distance
    (km at ``life_distance`` m per unit normed time), the contract's attributes and the spectra
    (with the wheel's ``radius`` in m, the band levels in wavelength)."""
    steps = np.round(np.asarray(ds.stop_time) / np.asarray(ds.time_step))
    ds["cost_time_steps"] = (ds.stop_time.dims, steps,
                             {"units": "1", "long_name": "ETDRK4 steps at the final step size"})
    ds = ds.assign_coords(distance=("time", ds.time.values * life_distance / KM,
                                    {"units": "km", "long_name": "distance run"}))
    ds.attrs.update(strategy=name, body="disk_wheel", scenario_hash="", strategy_description=description)
    return describe(ds, radius)
