"""The disk wheel on the time-domain track as a long-term body: strategies 1 and 3 on it.

The dynamics are :class:`railwear.dynamics.disk_wheel_track.WheelOnRing`: the rigid-rail disk
wheel (its contact filter over ``u``, Hertz contact, Kalker creep under the traction torque,
frictional power ``π = Fx ξ V``) rolling over the rail of a :class:`~railwear.track.modal.RingTrack`
(a periodic discrete track closed into a ring; pads, sleepers and ballast; the modes left out as
residual flexibility), wheel and track in one compiled RK4 loop. Everything else is the disk
wheel's (:class:`~railwear.longterm.disk_wheel.DiskWheel`): the wear of a cell is
``Δu_j = -β E_j / (R0 Δx w)`` from the frictional energy ``E_j`` swept onto it, frozen-geometry
draws of phase and speed (over a duty cycle, of the segment with its speed and traction torque,
:class:`~railwear.longterm.disk_wheel.DutyService`) with their Monte Carlo error, coupled segments with ``A β``. What is
new is where the wheel is on the track: each draw starts at a uniformly random position along
the ring (so over a random offset in the sleeper bay) with the track at rest under the static
load there, and the coupled run carries the position on.

Laws proportional to the frictional power (``law.beta``, the energy law) only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.errors import ScenarioError
from railwear.longterm.disk_wheel import DiskWheel, wheel_turn
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

    def positions(self, rng, count):
        """Uniformly random positions (m) along the ring, one per run."""
        return rng.uniform(0.0, self.ring.length, count)

    def at_rest(self, model, dyn, where):
        return dyn.static_state(where, model.initial_lift)

    def _steps(self, model, dyn, revolutions, per):
        """RK4 steps in ``revolutions / per`` turns (``per`` must divide them)."""
        steps = revolutions * int(round(wheel_turn(model) / dyn.dt))
        if steps % per:
            raise ScenarioError(f"updates_per_revolution: must divide the {steps} steps of a revolution")
        return steps // per

    def seconds(self, model, dyn, revolutions, per=1):
        """Duration (s) of ``revolutions / per`` turns in whole RK4 steps."""
        return self._steps(model, dyn, revolutions, per) * dyn.dt

    def run(self, model, dyn, p, surf, y, where, t0, energy, revolutions, per=1):
        n = self._steps(model, dyn, revolutions, per)
        y, _ = dyn.run(y, t0, n, where, p, surf, energy)
        return y, where + model.speed * n * dyn.dt, n * dyn.dt, 4 * n

    def carried(self, where):
        return {"position": where % self.ring.length}

    def fingerprint_parts(self):
        ring = self.ring
        return (repr(self.law), self.band_width, self.life_distance, self.service, self.revolutions,
                self.transient_revolutions, self.samples, self.updates_per_revolution, repr(self.model),
                repr(ring.track), ring.n_sleepers, ring.max_frequency_hz, ring.reference_frequency_hz, ring.residual,
                ring.n_near, self.dt)
