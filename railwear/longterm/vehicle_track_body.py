"""The disk wheel on the time-domain track as a long-term body: strategies 1 and 3 on it.

The dynamics are :class:`railwear.dynamics.disk_wheel_track.WheelOnRing`: the rigid-rail disk
wheel (its contact filter over ``u``, Hertz contact, Kalker creep under the traction torque,
frictional power ``π = Fx ξ V``) rolling over the rail of a :class:`~railwear.track.modal.RingTrack`
(a periodic discrete track closed into a ring; pads, sleepers and ballast; the modes left out as
residual flexibility), wheel and track in one compiled RK4 loop. Everything else is the disk
wheel's (:class:`~railwear.longterm.disk_wheel.DiskWheel`): the wear of a cell is
``Δu_j = -β E_j / (R0 Δx w)`` from the frictional energy ``E_j`` swept onto it, frozen-geometry
draws of phase and speed with their Monte Carlo error, coupled segments with ``A β``. What is
new is where the wheel is on the track: each draw starts at a uniformly random position along
the ring (so over a random offset in the sleeper bay) with the track at rest under the static
load there, and the coupled run carries the position on.

Laws proportional to the frictional power (``law.beta``, the energy law) only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.errors import ScenarioError
from railwear.longterm.disk_wheel import DiskWheel, depth_per_energy, start_lift, wheel_turn
from railwear.track.modal import RingTrack

__all__ = ["VehicleTrackBody", "ring_for"]


def ring_for(track, n_sleepers=32, max_frequency_hz=3000.0, reference_frequency_hz=60.0):
    """The :class:`RingTrack` of ``track`` the body runs on by default: 32 bays, rail modes to
    3 kHz, loss factors viscous at 60 Hz (about the metro case's P2 resonance)."""
    return RingTrack(track, n_sleepers, max_frequency_hz, reference_frequency_hz)


@dataclass(frozen=True)
class VehicleTrackBody(DiskWheel, name="vehicle_track"):
    """The disk wheel ``model`` (a rigid-rail :class:`~railwear.dynamics.DiskWheelModel`,
    ``rail_mass=None``) on ``ring`` (a :class:`RingTrack`), RK4 steps of at most ``dt`` [s]
    (each run takes the largest step that fits a whole number in a revolution). The other
    fields are :class:`DiskWheel`'s (``law`` with a ``beta``, ``band_width`` [m],
    ``life_distance`` [m] per unit normed time, ``service`` speeds, revolutions, draws,
    updates per revolution); ``integration`` and ``outputs_per_revolution`` are not used."""

    ring: RingTrack | None = None
    dt: float = 1e-4

    label = "disk wheel on the discrete track"

    def __post_init__(self):
        super().__post_init__()
        if not isinstance(self.ring, RingTrack):
            raise ScenarioError("ring: must be a railwear.track.modal.RingTrack (vehicle_track_body.ring_for(track))")
        if self.law.beta is None:
            raise ScenarioError(f"law: the vehicle-track body takes laws proportional to the frictional power "
                                f"(the energy law), not {type(self.law).__name__}")
        WheelOnRing(self.model, self.ring, self.dt)  # validates the wheel and the step

    def dynamics(self, model) -> WheelOnRing:
        """The compiled wheel-on-track model of the disk wheel ``model`` at its speed, its step
        the largest ``<= dt`` that divides a revolution into whole steps."""
        turn = wheel_turn(model)
        return WheelOnRing(model, self.ring, turn / math.ceil(turn / self.dt - 1e-9))

    def start(self, u0):
        if u0 is None:
            raise ScenarioError("u0: the vehicle-track body needs the radius deviation on its grid (m)")
        return super().start(u0)

    def _draw_runs(self, shape, rng, cost):
        """The Monte Carlo draws over the frozen ``shape`` (m): the dynamics at the drawn speed
        and phase, the parameters, surface, state after the transient, its time (s) and track
        position (m), the steps per revolution."""
        speeds = self.service.sample(rng, self.samples)
        phases = rng.uniform(0.0, 2.0 * np.pi, self.samples)
        positions = rng.uniform(0.0, self.ring.length, self.samples)
        for v, phase, x in zip(speeds, phases, positions):
            model = replace(self.model, speed=float(v), radius_deviation=shape, initial_angle=float(phase),
                            initial_lift=start_lift(self.model, shape, phase))
            dyn = self.dynamics(model)
            p, surf = model.params(), model.surface()
            per_turn = int(round(wheel_turn(model) / dyn.dt))
            y = dyn.static_state(x, model.initial_lift)
            t0 = 0.0
            if self.transient_revolutions > 0:
                n = self.transient_revolutions * per_turn
                y, _ = dyn.run(y, 0.0, n, x, p, surf)
                cost["rhs_evaluations"] += 4 * n
                t0, x = n * dyn.dt, x + model.speed * n * dyn.dt
            yield model, dyn, p, surf, y, t0, x, per_turn

    def draw(self, u, rng):
        """One Monte Carlo set over the frozen ``u`` (m): ``(rates, cost)``, ``rates`` the depth
        per unit normed time of each draw and cell (m), ``(samples, n)``."""
        u = np.asarray(u, float)
        rates = np.empty((self.samples, u.size))
        cost = {"revolutions": self.samples * (self.revolutions + self.transient_revolutions), "rhs_evaluations": 0}
        for i, (model, dyn, p, surf, y, t0, x, per_turn) in enumerate(self._draw_runs(u - u.mean(), rng, cost)):
            energy = np.zeros(u.size)
            n = self.revolutions * per_turn
            dyn.run(y, t0, n, x, p, surf, energy)
            cost["rhs_evaluations"] += 4 * n
            distance = n * dyn.dt * model.speed
            rates[i] = energy * depth_per_energy(model, u.size, self.beta, self.band_width) / distance * self.life_distance
        return rates, cost

    def couple(self, u, rng, acceleration, cost):
        shape = u - u.mean()
        model, dyn, p, per_turn, gain, dT = self._derived(shape, acceleration)
        x = float(rng.uniform(0.0, self.ring.length))
        y, t = dyn.static_state(x, model.initial_lift), 0.0
        if self.transient_revolutions > 0:
            n = self.transient_revolutions * per_turn
            y, _ = dyn.run(y, 0.0, n, x, p, model.surface())
            cost["rhs_evaluations"] += 4 * n
            t, x = n * dyn.dt, x + model.speed * n * dyn.dt
        cost["revolutions"] += self.transient_revolutions
        return {"shape": shape, "seconds": t, "state": y, "position": x % self.ring.length}

    def _derived(self, shape, acceleration):
        """The model over the start's ``shape`` (m), its dynamics and parameters, the steps per
        revolution, the depth per joule times ``A`` and the normed time per segment."""
        key = (np.asarray(shape, float).tobytes(), acceleration)
        if self._coupled.get("key") != key:
            model = replace(self.model, radius_deviation=shape,
                            initial_lift=start_lift(self.model, shape, self.model.initial_angle))
            dyn = self.dynamics(model)
            per_turn = int(round(wheel_turn(model) / dyn.dt))
            if per_turn % self.updates_per_revolution:
                raise ScenarioError(f"updates_per_revolution: must divide the {per_turn} steps of a revolution")
            gain = acceleration * depth_per_energy(model, shape.size, self.beta, self.band_width)
            segment = per_turn // self.updates_per_revolution * dyn.dt
            dT = acceleration * model.speed * segment / self.life_distance
            self._coupled.clear()
            self._coupled.update(key=key, derived=(model, dyn, model.params(), per_turn, gain, dT))
        return self._coupled["derived"]

    def segment(self, u, carry, acceleration, remaining, cost):
        model, dyn, p, per_turn, gain, dT = self._derived(carry["shape"], acceleration)
        n = per_turn // self.updates_per_revolution
        t, x, surf = float(carry["seconds"]), float(carry["position"]), model.surface_for(u - u.mean())
        energy = np.zeros(u.size)
        y, _ = dyn.run(carry["state"], t, n, x, p, surf, energy)
        cost["rhs_evaluations"] += 4 * n
        cost["revolutions"] += 1 / self.updates_per_revolution
        carry = {"shape": carry["shape"], "seconds": t + n * dyn.dt, "state": y,
                 "position": (x + model.speed * n * dyn.dt) % self.ring.length}
        return gain * energy, dT, False, acceleration * self.beta * float(energy.sum()), None, carry

    def fingerprint_parts(self):
        ring = self.ring
        return (repr(self.law), self.band_width, self.life_distance, self.service, self.revolutions,
                self.transient_revolutions, self.samples, self.updates_per_revolution, repr(self.model),
                repr(ring.track), ring.n_sleepers, ring.max_frequency_hz, ring.reference_frequency_hz, ring.residual,
                ring.n_near, self.dt)
