"""Strategy 1 of the paper: direct coupled integration (eq. 3) with an acceleration factor on β.

The disk wheel's dynamics and the wear surface advance together. The dynamics run on the
compiled integrator in segments of ``1 / updates_per_revolution`` of a wheel revolution; after
each segment the frictional energy swept onto each cell is worn off with ``A β`` in place of ``β``,

    u_j ← u_j - A β E_j / (R0 Δx w),

and the next segment runs over the new surface from the dynamic state where the last one ended.
The dynamics API takes ``u`` as frozen within one integrator call, so the surface is updated
segment by segment: revolution by revolution by default, finer with ``updates_per_revolution``.
Finer is not better at large ``A``: each update wears the cells just passed at once, a step of
``A`` times the wear of the segment right behind the patch that kicks the vertical dynamics;
per revolution the step is spread round the whole wheel and only its uneven part is felt.
Each simulated second stands for ``A`` seconds of service, so normed time advances by
``A V Δt / life_distance``. The error is first order in ``A`` (the wear of a segment acts only
from the next one on, and the dynamics lag the faster-changing surface); ``A = 1`` is the coupled
system itself.
"""

import time as _time
from dataclasses import dataclass, field, replace

import numpy as np

from railwear.errors import ScenarioError
from railwear.longterm.wheel_runs import (Integration, WheelWear, advance, checked_start,
                                          result, depth_per_energy, fingerprint, start_lift,
                                          stop_fraction, wheel_turn, fraction_done)


@dataclass(frozen=True)
class DirectCheckpoint:
    """State of a direct run after ``intervals`` segments (plain values and arrays, for ``.npz``)."""

    fingerprint: str
    intervals: int
    seconds: float
    state: np.ndarray
    time: float
    u: np.ndarray
    next_save: int
    saved: np.ndarray
    times: np.ndarray
    rhs_evaluations: int


@dataclass(frozen=True)
class Direct(WheelWear):
    """Strategy 1 on a :class:`~railwear.dynamics.DiskWheelModel` at its speed.

    ``beta`` (m³/J) the energy law's volume per frictional energy, ``band_width`` (m) the wear
    band, ``life_distance`` (m) one unit of normed time, ``acceleration`` ``A >= 1`` the factor on
    β, ``transient_revolutions`` run on the initial surface without wear before the coupling
    starts, ``n_save`` outputs evenly spaced in normed time (and in removed depth when a depth
    limit is given).
    """

    acceleration: float
    updates_per_revolution: int = 1
    transient_revolutions: int = 4
    n_save: int = 101
    integration: Integration = field(default_factory=Integration)
    max_revolutions: int = 20_000_000

    def __post_init__(self):
        super().__post_init__()
        if not (np.isfinite(self.acceleration) and self.acceleration >= 1):
            raise ScenarioError(f"acceleration factor must be >= 1, got {self.acceleration}")
        if int(self.updates_per_revolution) != self.updates_per_revolution or self.updates_per_revolution < 1:
            raise ScenarioError("updates_per_revolution must be a whole number >= 1")
        if int(self.transient_revolutions) != self.transient_revolutions or self.transient_revolutions < 0:
            raise ScenarioError("transient_revolutions must be a whole number >= 0")
        if int(self.n_save) != self.n_save or self.n_save < 2:
            raise ScenarioError("n_save must be a whole number >= 2")

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """``u`` (m) over normed time from ``u0`` until ``until`` or the removed ``depth_limit`` (m).
        ``checkpoint(DirectCheckpoint)`` is called at every output; ``resume`` continues from one
        to the same result bit for bit."""
        from railwear.longterm.phenomenological import describe

        u0 = checked_start(u0, until, depth_limit)
        key = fingerprint(u0, until, depth_limit, self.beta, self.band_width, self.life_distance,
                          self.acceleration, self.updates_per_revolution, self.transient_revolutions,
                          self.n_save, self.integration, repr(self.model))
        started = _time.perf_counter()
        shape = u0 - u0.mean()
        model = replace(self.model, radius_deviation=shape,
                        initial_lift=start_lift(self.model, shape, self.model.initial_angle))
        p = model.params()
        turn = wheel_turn(model)
        segment = turn / self.updates_per_revolution
        gain = self.acceleration * depth_per_energy(model, u0.size, self.beta, self.band_width)
        dT = self.acceleration * model.speed * segment / self.life_distance
        time_marks = np.linspace(0.0, until, self.n_save)
        depth_marks = None if depth_limit is None else np.linspace(0.0, depth_limit, self.n_save)
        if resume is not None:
            if resume.fingerprint != key:
                raise ScenarioError("resume: the checkpoint belongs to another problem")
            j, t, y, T = int(resume.intervals), float(resume.seconds), resume.state.copy(), float(resume.time)
            u, mark = resume.u.copy(), int(resume.next_save)
            saved, times, nfev = list(resume.saved), list(resume.times), int(resume.rhs_evaluations)
        else:
            j, T, u, mark = 0, 0.0, u0.copy(), 1
            y, nfev = model.initial_state(), 0
            t = self.transient_revolutions * turn
            if t > 0:
                y, nfev = advance(model, p, model.surface(), y, 0.0, t, np.zeros(0), self.integration)
            saved, times = [u0.copy()], [0.0]
        max_segments = self.max_revolutions * self.updates_per_revolution
        while T < until and (depth_limit is None or np.max(u0 - u) < depth_limit * (1 - 1e-12)):
            if j >= max_segments:
                raise ScenarioError(f"direct: {self.max_revolutions} revolutions did not reach the end; "
                                    "raise the acceleration factor")
            energy = np.zeros(u0.size)
            y, n = advance(model, p, model.surface_for(u - u.mean()), y, t, t + segment, energy, self.integration)
            nfev += n
            t += segment
            j += 1
            increment = gain * energy
            frac_time, frac = (until - T) / dT, stop_fraction(u0 - u, increment, depth_limit)
            if frac_time <= min(frac, 1.0):
                u, T = u - frac_time * increment, until
            else:
                u, T = u - frac * increment, T + frac * dT
            due = T >= time_marks[min(mark, self.n_save - 1)]
            if depth_marks is not None:
                due = due or np.max(u0 - u) >= depth_marks[min(mark, self.n_save - 1)]
            done = T >= until or (depth_limit is not None and np.max(u0 - u) >= depth_limit * (1 - 1e-12))
            if due or done:
                saved.append(u.copy())
                times.append(T)
                while mark < self.n_save and (T >= time_marks[mark] or (
                        depth_marks is not None and np.max(u0 - u) >= depth_marks[mark])):
                    mark += 1
                if progress is not None:
                    progress(fraction_done(T, until, u0 - u, depth_limit))
                if checkpoint is not None:
                    checkpoint(DirectCheckpoint(key, j, t, y.copy(), T, u.copy(), mark, np.array(saved),
                                                np.array(times), nfev))
        revolutions = self.transient_revolutions + j / self.updates_per_revolution
        ds = result(saved, times, revolutions, nfev, model.speed,
                    {"strategy": "direct coupled integration", "acceleration_factor": self.acceleration,
                     "updates_per_revolution": self.updates_per_revolution,
                     "wall_seconds": _time.perf_counter() - started})
        return describe(ds)


def surface_wear(model, u, beta, surface, turns=12, per_turn=4000, lateral_half_axis=None, footprint="hertz",
                 acceleration=1.0):
    """Wear a :class:`~railwear.geometry.wear_surface.WearSurface` (paper Fig. 4) with the disk
    wheel ``model`` running ``turns`` revolutions over the frozen ``u`` (m): the frictional energy
    of each output interval, times ``acceleration β``, is deposited with the Hertz (or another)
    footprint of half-lengths ``a`` (the model's) and ``lateral_half_axis`` ``b`` (m) at the
    contact angle, on the centre line of the tread. Returns the surface and the volume (m³)."""
    from railwear.dynamics import simulate

    u = np.asarray(u, float)
    shape = u - u.mean()
    m = replace(model, radius_deviation=shape, initial_lift=start_lift(model, shape, model.initial_angle))
    ds = simulate(m, turns * wheel_turn(m), n_output=int(turns * per_turn) + 1)
    t, xc, power = ds.time.values, ds.contact_angle.values, ds.frictional_power.values
    energy = 0.5 * (power[1:] + power[:-1]) * np.diff(t)
    angle = 0.5 * (xc[1:] + xc[:-1])
    b = m.patch_half_length if lateral_half_axis is None else lateral_half_axis
    volume = acceleration * beta * energy
    surface.deposit(volume, angle, 0.0, m.patch_half_length, b, footprint=footprint)
    return surface, float(volume.sum())
