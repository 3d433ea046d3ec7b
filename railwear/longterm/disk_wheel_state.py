"""The disk wheel worn by a law with an internal state (paper eq. 2): ``u' = U(t, π, u, z)``,
``z' = Z(t, π, u, z)`` on every cell round the wheel.

The wear variable has two rows, the radius deviation ``u`` (m) and the state ``z`` of each cell.
Between two dense outputs of the compiled dynamics the frictional energy of the interval is
spread over the cells as the patch sweeps them (the compiled energy sweep's spread); a cell's
power density is its share of the energy over its area ``R0 Δx w`` and the interval's length, and
``(u, z)`` of every cell advance by the law's midpoint step over the interval in service time
(``A`` times the simulated time in the coupled run), cells out of contact at ``π = 0``.
Frozen geometry: the Monte Carlo rates of both rows over the frozen ``(u, z)``, the step limit
counting ``state_scale`` metres per unit of ``z`` (a state that relaxes within a long-term step
needs small steps).
"""

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics import kernels
from railwear.errors import ScenarioError
from railwear.longterm.base import checked_start
from railwear.longterm.disk_wheel import DiskWheel, dense_contact


@dataclass(frozen=True)
class StatefulDiskWheel(DiskWheel):
    """:class:`DiskWheel` worn by a :class:`~railwear.wear.InternalStateLaw` (its ``law``);
    ``state_scale`` (m per unit of ``z``) weighs the state's change in the step limit."""

    state_scale: float = 1e-5

    def __post_init__(self):
        if not getattr(self.law, "stateful", False):
            raise ScenarioError(f"law: {type(self.law).__name__} has no internal state; use DiskWheel")
        if not (np.isfinite(self.state_scale) and self.state_scale > 0):
            raise ScenarioError(f"state_scale must be finite and > 0 (m per unit of z), got {self.state_scale}")
        super().__post_init__()

    def _evolve(self, model, p, surf, y, t0, t1, u, z, factor, revolutions):
        """Run from ``y`` at ``t0`` to ``t1`` (s) and advance the cells' ``(u, z)`` in service
        time (``factor`` times simulated time): ``(y_end, rhs_evaluations, u, z)``."""
        n_output = max(int(math.ceil(revolutions * self.outputs_per_revolution)), 2) + 1
        y, nfev, t, _, _, power, angle = dense_contact(model, p, surf, y, t0, t1, self.integration, n_output)
        area, half = self.cell_volume(u.size), model.patch_half_length / model.radius
        share = np.zeros(u.size)
        for k in range(t.size - 1):
            dt = t[k + 1] - t[k]
            share[:] = 0.0
            kernels.sweep(share, angle[k], angle[k + 1], half, 1.0)
            density = 0.5 * (power[k] + power[k + 1]) * share / area  # the interval's energy / (area dt)
            u, z = self.law.advance(factor * t[k], factor * dt, density, u, z)
        return y, nfev, u, z

    # the body protocol, over (u, z)
    def start(self, u0):
        u0 = checked_start(u0, 1.0, None)
        return np.stack([u0, np.asarray(self.law.initial_state(u0.size), float)])

    def removed(self, u, u_start):
        return u_start[0] - u[0]

    def removal(self, increment):
        return increment[0]

    def limited(self, rate, on="u"):
        return np.concatenate([super().limited(rate[0], on), rate[1] * self.state_scale])

    def rates(self, u, rng, cost):
        draws = np.empty((self.samples,) + u.shape)
        for i, (model, dyn, p, surf, y, t0, _) in enumerate(self.frozen_runs(u[0] - u[0].mean(), rng, cost)):
            window = self.seconds(model, dyn, self.revolutions)
            _, n, ue, ze = self._evolve(model, p, surf, y, t0, t0 + window, u[0], u[1], 1.0, self.revolutions)
            cost["rhs_evaluations"] += n
            draws[i] = np.stack([u[0] - ue, u[1] - ze]) * self.life_distance / (model.speed * window)
        cost["revolutions"] += self.samples * (self.revolutions + self.transient_revolutions)
        rate = draws.mean(0)
        return rate, draws.std(0, ddof=1) / np.sqrt(self.samples), float(rate[0].sum() * self.cell_volume(u.shape[1])), None

    def couple(self, u, rng, acceleration, cost):
        return super().couple(u[0], rng, acceleration, cost)

    def segment(self, u, carry, acceleration, remaining, cost):
        model, dyn, p, _, dT = self._derived(carry["shape"], acceleration)
        segment = self.seconds(model, dyn, 1, self.updates_per_revolution)
        t, surf = carry["seconds"], model.surface_for(u[0] - u[0].mean())
        y, n, ue, ze = self._evolve(model, p, surf, carry["state"], t, t + segment, u[0], u[1], acceleration,
                                    1.0 / self.updates_per_revolution)
        cost["rhs_evaluations"] += n
        cost["revolutions"] += 1 / self.updates_per_revolution
        increment = np.stack([u[0] - ue, u[1] - ze])
        carry = {"shape": carry["shape"], "seconds": t + segment, "state": y}
        return increment, dT, False, float(increment[0].sum() * self.cell_volume(u.shape[1])), None, carry

    def record(self, u, seen, law_volume):
        return {"u": u[0].copy(), "state": u[1].copy(), "law_volume": law_volume}

    def result(self, records, times, cost, error, attrs):
        ds = super().result(records, times, cost, None if error is None else np.asarray(error)[:, 0], attrs)
        ds["surface_state"] = (("time", "angle"), np.asarray(records["state"]),
                               {"units": "1", "long_name": "internal state z of the wear law per cell"})
        return ds

    def fingerprint_parts(self):
        return super().fingerprint_parts() + (self.state_scale,)
