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

Several wheels on one rail (``wheel_positions``, m behind the first: ``(0, 2.5)`` a bogie):
:class:`~railwear.dynamics.wheels_track.WheelsOnRing` runs every wheel of a draw (or of a coupled
segment) together over the ring, each over its own radius deviation ``u_a`` (the wear variable is
``(wheels, angle)``) and each sweeping its frictional energy onto its own cells. A draw takes one
speed, one position of the first wheel and one phase for all wheels: the wheels of a vehicle roll
the same distance, so their polygons keep their relative angles, as in the linear model
:class:`~railwear.longterm.vehicle_track.WheelsOnRail`, whose fastest combination of each wheel's
dominant order the result carries beside the measured one. One wheel is the one-wheel body bit
for bit.

Laws proportional to the frictional power (``law.beta``, the energy law) only.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from railwear.dynamics.disk_wheel_track import WheelOnRing
from railwear.dynamics.wheels_track import WheelsOnRing
from railwear.errors import ScenarioError
from railwear.longterm.disk_wheel import DiskWheel, DutyService, depth_per_energy, start_lift, wheel_turn
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
    updates per revolution); ``integration`` and ``outputs_per_revolution`` are not used.
    ``wheel_positions`` (m behind the first, ``None`` or one: one wheel): several identical
    wheels on the rail, each with its own radius deviation."""

    ring: RingTrack | None = None
    dt: float = 1e-4
    wheel_positions: tuple | None = None

    label = "disk wheel on the discrete track"

    def __post_init__(self):
        super().__post_init__()
        if not isinstance(self.ring, RingTrack):
            raise ScenarioError("ring: must be a railwear.track.modal.RingTrack (vehicle_track_body.ring_for(track))")
        if self.law.beta is None:
            raise ScenarioError(f"law: the vehicle-track body takes laws proportional to the frictional power "
                                f"(the energy law), not {type(self.law).__name__}")
        WheelOnRing(self.model, self.ring, self.dt)  # validates the wheel and the step
        if self.several:
            object.__setattr__(self, "wheel_positions", tuple(float(x) for x in self.wheel_positions))
            try:  # the wheels' spacing on the ring
                WheelsOnRing(self.model, self.ring, self.dt, positions=self.wheel_positions)
            except ScenarioError as e:
                raise ScenarioError(f"wheel_{e}") from None

    @property
    def several(self) -> bool:
        """More than one wheel on the rail."""
        return self.wheel_positions is not None and len(self.wheel_positions) > 1

    @property
    def n_wheels(self) -> int:
        return len(self.wheel_positions) if self.several else 1

    def dynamics(self, model) -> WheelOnRing:
        """The compiled wheel-on-track model of the disk wheel ``model`` at its speed (with several
        wheels, :class:`WheelsOnRing` of them), its step the largest ``<= dt`` that divides a
        revolution into whole steps."""
        turn = wheel_turn(model)
        dt = turn / math.ceil(turn / self.dt - 1e-9)
        if self.several:
            return WheelsOnRing(model, self.ring, dt, positions=self.wheel_positions)
        return WheelOnRing(model, self.ring, dt)

    def start(self, u0):
        """``u0`` (m): over the angle, or with several wheels one row per wheel (``(wheels,
        angle)``); one row alone is the first wheel's, the others start round."""
        if u0 is None:
            raise ScenarioError("u0: the vehicle-track body needs the radius deviation on its grid (m)")
        if not self.several:
            return super().start(u0)
        u0 = np.asarray(u0, float)
        if u0.ndim == 1:
            u0 = np.vstack([u0] + [np.zeros_like(u0)] * (self.n_wheels - 1))
        if u0.ndim != 2 or u0.shape[0] != self.n_wheels:
            raise ScenarioError(f"u0: one radius deviation per wheel ({self.n_wheels} rows), or the first wheel's "
                                f"alone, not shape {u0.shape}")
        return np.array([super(VehicleTrackBody, self).start(row) for row in u0])

    def limited(self, rate, on="u"):
        """As :meth:`Body.limited`; with several wheels the shape is each wheel's own."""
        if np.ndim(rate) < 2 or on == "u":
            return super().limited(rate, on)
        return rate - rate.mean(-1, keepdims=True)

    def draw(self, u, rng):
        """One Monte Carlo set (:meth:`DiskWheel.draw`); with several wheels ``u`` and each draw's
        rates are ``(wheels, angle)``: all wheels run together over their frozen shapes."""
        if not self.several:
            return super().draw(u, rng)
        u = np.asarray(u, float)
        shapes = u - u.mean(-1, keepdims=True)
        rates = np.empty((self.samples,) + u.shape)
        wheel_turns = self.n_wheels * (self.revolutions + self.transient_revolutions)
        cost = {"revolutions": self.samples * wheel_turns, "rhs_evaluations": 0}
        speeds, peaks = self.service.draw(rng, self.samples)
        phases = rng.uniform(0.0, 2.0 * np.pi, self.samples)
        for i, (v, k, phase, where) in enumerate(zip(speeds, peaks, phases, self.positions(rng, self.samples))):
            models = [self.drawn(shape, v, k, phase) for shape in shapes]
            model, dyn = models[0], self.dynamics(models[0])
            p, surf = [m.params() for m in models], [m.surface() for m in models]
            y, t0 = dyn.static_state(where, [m.initial_lift for m in models], models), 0.0
            if self.transient_revolutions > 0:
                y, where, t0, n = self.run(model, dyn, p, surf, y, where, 0.0, np.zeros(0), self.transient_revolutions)
                cost["rhs_evaluations"] += n
            energy = np.zeros(u.shape)
            _, _, seconds, n = self.run(model, dyn, p, surf, y, where, t0, energy, self.revolutions)
            cost["rhs_evaluations"] += n
            depth = energy * depth_per_energy(model, u.shape[-1], self.beta, self.band_width)
            rates[i] = depth / (seconds * model.speed) * self.life_distance
        return rates, cost

    # coupled: with several wheels every segment runs all wheels on from where the last ended
    def couple(self, u, rng, acceleration, cost):
        if not self.several:
            return super().couple(u, rng, acceleration, cost)
        shape = u - u.mean(-1, keepdims=True)
        models, dyn, p, _, _ = self._derived(shape, acceleration)
        where = self.positions(rng, 1)[0]
        y, t = dyn.static_state(where, [m.initial_lift for m in models], models), 0.0
        if self.transient_revolutions > 0:
            y, where, t, n = self.run(models[0], dyn, p, [m.surface() for m in models], y, where, 0.0, np.zeros(0),
                                      self.transient_revolutions)
            cost["rhs_evaluations"] += n
        cost["revolutions"] += self.n_wheels * self.transient_revolutions
        return {"shape": shape, "seconds": t, "state": y, **self.carried(where)}

    def _derived(self, shape, acceleration):
        """:meth:`DiskWheel._derived`; with several wheels each wheel's model over its row of
        ``shape`` (a list), the dynamics of them all and their parameters (a list)."""
        if not self.several:
            return super()._derived(shape, acceleration)
        key = (np.asarray(shape, float).tobytes(), acceleration)
        if self._coupled.get("key") != key:
            models = [replace(self.model, radius_deviation=row,
                              initial_lift=start_lift(self.model, row, self.model.initial_angle)) for row in shape]
            dyn = self.dynamics(models[0])
            gain = acceleration * depth_per_energy(models[0], shape.shape[-1], self.beta, self.band_width)
            dT = acceleration * self.model.speed * self.seconds(models[0], dyn, 1, self.updates_per_revolution) \
                / self.life_distance
            self._coupled.clear()
            self._coupled.update(key=key, derived=(models, dyn, [m.params() for m in models], gain, dT))
        return self._coupled["derived"]

    def segment(self, u, carry, acceleration, remaining, cost):
        """:meth:`DiskWheel.segment`; with several wheels all of them over their current surfaces,
        each wheel's frictional energy worn off its own cells with ``A β``."""
        if not self.several:
            return super().segment(u, carry, acceleration, remaining, cost)
        models, dyn, p, gain, dT = self._derived(carry["shape"], acceleration)
        surf = [m.surface_for(row - row.mean()) for m, row in zip(models, u)]
        energy = np.zeros(u.shape)
        y, where, seconds, n = self.run(models[0], dyn, p, surf, carry["state"], carry["position"], carry["seconds"],
                                        energy, 1, self.updates_per_revolution)
        cost["rhs_evaluations"] += n
        cost["revolutions"] += self.n_wheels / self.updates_per_revolution
        carry = {"shape": carry["shape"], "seconds": carry["seconds"] + seconds, "state": y, **self.carried(where)}
        return gain * energy, dT, False, acceleration * self.beta * float(energy.sum()), None, carry

    def batch_coordinates(self):
        """With several wheels the ``wheel`` coordinate: each wheel's distance behind the first (m)."""
        if not self.several:
            return {}
        return {"wheel": ("wheel", np.asarray(self.wheel_positions, float),
                          {"units": "m", "long_name": "wheel's distance behind the first on the rail"})}

    def result(self, records, times, cost, error, attrs):
        """:meth:`DiskWheel.result`; with several wheels also :meth:`linear_comparison`."""
        ds = super().result(records, times, cost, error, attrs)
        return self.linear_comparison(ds) if self.several else ds

    def linear_comparison(self, ds):
        """Per wheel, at its dominant order ``n`` at the end: the fastest growth rate of
        :class:`~railwear.longterm.vehicle_track.WheelsOnRail` (``Re λ`` per unit normed time,
        ``λ L / V``, with the grid's filter ``sinc³(n / cells)``: the rate the cells can show)
        and each wheel's share of that combination (``|v_a| / max |v|``) and phase against the
        first wheel (``arg v_a / v_0``, rad), beside the same of the wheels' order-``n``
        harmonics at the end (``rfft`` coefficients, the linear model's convention). The linear
        model only where the service is one speed (no duty cycle), at that speed (a scatter about
        it is not averaged over): NaN elsewhere."""
        from railwear.longterm.vehicle_track import VehicleTrackModel, WheelsOnRail, growing_combinations

        service = self.service
        linear = not isinstance(service, DutyService) and len(service.peaks) == 1
        wheels = WheelsOnRail(VehicleTrackModel(self.model, self.ring.track), self.wheel_positions) if linear else None
        u_end = ds.u.isel(time=-1).values
        cells = u_end.shape[-1]
        harmonics = np.fft.rfft(u_end, axis=-1)
        nw = self.n_wheels
        out = {name: np.full(nw, np.nan) for name in ("rate", "share", "phase", "measured_share", "measured_phase")}
        for a, n in enumerate(np.asarray(ds.dominant_order.values, float)):
            if not (np.isfinite(n) and 1 <= n < cells // 2):
                continue
            n, h = int(n), harmonics[:, int(n)]
            if abs(h[0]) > 0:
                out["measured_share"][a] = abs(h[a]) / np.max(np.abs(h))
                out["measured_phase"][a] = np.angle(h[a] / h[0])
            if linear:
                lam, modes = growing_combinations(wheels.rate_matrix([n], self.law, self.band_width))
                v = modes[0, :, 0]
                out["rate"][a] = lam[0, 0].real * self.life_distance / self.model.speed * np.sinc(n / cells) ** 3
                out["share"][a] = abs(v[a]) / np.max(np.abs(v))
                out["phase"][a] = np.angle(v[a] / v[0])
        words = "at the wheel's dominant order at the end"
        ds["linear_growth_rate"] = ("wheel", out["rate"], {
            "units": "1", "long_name": f"fastest growth rate of the linear several-wheel model {words}, per unit "
                                       "normed time (grid filter on it)"})
        for key, kind in (("share", "linear model's fastest combination"), ("measured_share", "wheels' harmonics")):
            ds[f"linear_{key}" if key == "share" else key] = ("wheel", out[key], {
                "units": "1", "long_name": f"the wheel's amplitude in the {kind} {words}, over the largest"})
        for key, kind in (("phase", "linear model's fastest combination"), ("measured_phase", "wheels' harmonics")):
            ds[f"linear_{key}" if key == "phase" else key] = ("wheel", out[key], {
                "units": "rad", "long_name": f"the wheel's phase in the {kind} {words}, against the first wheel"})
        return ds

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
                ring.n_near, self.dt) + ((self.wheel_positions,) if self.several else ())
