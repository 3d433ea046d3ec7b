"""Strategy 3 of the paper: stepwise frozen geometry (section "Solution strategies", Fig. 7).

With the radius deviation ``u`` frozen, the disk wheel runs for ``transient_revolutions`` (thrown
away) and then ``revolutions`` more, for ``samples`` random draws of the initial phase (the contact
angle, uniform on [0, 2π)) and of the speed from the service distribution (peaks with weights and
a normal scatter). Each draw gives the depth each cell loses per metre run, the integral of the
"teeth" of Fig. 7 over the revolutions; their mean over the draws is the Monte Carlo estimate of
the wear rate ``r_j`` (m per unit normed time), with the standard error ``s_j = std / sqrt(samples)``.
The geometry is then advanced over a long-term step

    u ← u - r ΔT,   ΔT = step_limit / max_j |r_j|,

so no cell changes by more than ``step_limit`` (m); repeat. With ``limit_on="shape"`` the limit
applies to the change of ``u - mean(u)`` instead (``ΔT = step_limit / max_j |r_j - mean(r)|``): the
dynamics see only the shape (a uniformly smaller wheel only lowers the axle), so the uniform wear,
which dominates, need not shorten the steps. This is the forward Euler method in
the long-term time on the Monte Carlo rate: first order in ``step_limit``. ``scheme="adams-bashforth"``
takes the second-order Adams-Bashforth step for unequal steps instead,

    u ← u - ΔT ((1 + ω/2) r - (ω/2) r_prev),   ω = ΔT / ΔT_prev,

at the same cost per step (one set of draws), so the same error allows far larger steps (the first
step is Euler's). The standard error is carried along, ``var(u_j) += (w s_j ΔT)²`` summed over the
rates used with weights ``w``, as the run's error estimate.
"""

import time as _time
from dataclasses import dataclass, field

import numpy as np

from railwear.errors import ScenarioError
from railwear.longterm.wheel_runs import (Integration, WheelWear, advance, checked_start,
                                          result, depth_per_energy, fingerprint,
                                          rng_from_text, rng_state_text, start_lift, stop_fraction,
                                          wheel_turn, fraction_done)


@dataclass(frozen=True)
class ServiceSpeeds:
    """Speed distribution of service: ``peaks`` (m/s) drawn with ``weights`` (summing to 1), each
    with a normal ``scatter`` (m/s, standard deviation; draws are kept above 0.5 m/s)."""

    peaks: tuple
    weights: tuple | None = None
    scatter: float = 0.0

    def __post_init__(self):
        peaks = tuple(float(v) for v in np.atleast_1d(self.peaks))
        object.__setattr__(self, "peaks", peaks)
        if not peaks or not all(np.isfinite(v) and v > 0 for v in peaks):
            raise ScenarioError("service speeds: every peak must be finite and > 0 (m/s)")
        weights = (1.0 / len(peaks),) * len(peaks) if self.weights is None else tuple(float(w) for w in self.weights)
        object.__setattr__(self, "weights", weights)
        if len(weights) != len(peaks) or any(not w >= 0 for w in weights):
            raise ScenarioError("service speeds: one weight >= 0 per peak is needed")
        if abs(sum(weights) - 1) > 1e-9:
            raise ScenarioError(f"service speeds: the weights must sum to 1, not {sum(weights):g}")
        if not (np.isfinite(self.scatter) and self.scatter >= 0):
            raise ScenarioError("service speeds: scatter must be finite and >= 0 (m/s)")

    @property
    def mean(self):
        """Mean speed (m/s)."""
        return float(np.dot(self.peaks, self.weights))

    def sample(self, rng, n):
        """``n`` speeds (m/s) drawn with ``rng``."""
        peak = rng.choice(len(self.peaks), size=n, p=np.asarray(self.weights))
        v = np.asarray(self.peaks)[peak] + self.scatter * rng.standard_normal(n)
        low = v < 0.5
        while np.any(low):
            v[low] = np.asarray(self.peaks)[peak[low]] + self.scatter * rng.standard_normal(int(low.sum()))
            low = v < 0.5
        return v


@dataclass(frozen=True)
class FrozenGeometry(WheelWear):
    """Wear statistics of the disk wheel over a frozen ``u`` (paper Fig. 7).

    The dynamics see the shape ``u - mean(u)`` (a uniformly smaller wheel only lowers the axle),
    and each draw starts at the static approach under the cell it starts on.

    ``model`` a :class:`~railwear.dynamics.DiskWheelModel` (its speed, phase and ``u`` are
    replaced per draw); ``beta`` (m³/J) the energy law's volume per energy; ``band_width`` (m) the
    lateral width the wear spreads over; ``life_distance`` (m) one unit of normed time.
    """

    service: ServiceSpeeds
    revolutions: int = 4
    transient_revolutions: int = 4
    samples: int = 8
    integration: Integration = field(default_factory=Integration)

    def __post_init__(self):
        super().__post_init__()
        if int(self.revolutions) != self.revolutions or self.revolutions < 1:
            raise ScenarioError(f"revolutions must be a whole number >= 1, got {self.revolutions}")
        if int(self.transient_revolutions) != self.transient_revolutions or self.transient_revolutions < 0:
            raise ScenarioError(f"transient_revolutions must be a whole number >= 0, got {self.transient_revolutions}")
        if int(self.samples) != self.samples or self.samples < 2:
            raise ScenarioError(f"samples must be a whole number >= 2 (for a variance), got {self.samples}")

    def draw(self, u, rng):
        """One Monte Carlo set over the frozen ``u`` (m): ``(rates, speeds, cost)``, ``rates`` the
        depth per unit normed time of each draw and cell (m), ``(samples, n)``; ``cost`` a dict of
        revolutions simulated and right-hand-side evaluations."""
        from dataclasses import replace

        u = np.asarray(u, float)
        shape = u - u.mean()
        speeds = self.service.sample(rng, self.samples)
        phases = rng.uniform(0.0, 2.0 * np.pi, self.samples)
        rates = np.empty((self.samples, u.size))
        nfev = 0
        for i, (v, phase) in enumerate(zip(speeds, phases)):
            model = replace(self.model, speed=float(v), radius_deviation=shape, initial_angle=float(phase),
                            initial_lift=start_lift(self.model, shape, phase))
            p, surf, y = model.params(), model.surface(), model.initial_state()
            turn = wheel_turn(model)
            t0 = self.transient_revolutions * turn
            if t0 > 0:
                y, n = advance(model, p, surf, y, 0.0, t0, np.zeros(0), self.integration)
                nfev += n
            energy = np.zeros(u.size)
            _, n = advance(model, p, surf, y, t0, t0 + self.revolutions * turn, energy, self.integration)
            nfev += n
            distance = self.revolutions * turn * model.speed
            rates[i] = energy * depth_per_energy(model, u.size, self.beta, self.band_width) / distance * self.life_distance
        cost = {"revolutions": self.samples * (self.revolutions + self.transient_revolutions), "rhs_evaluations": nfev}
        return rates, speeds, cost

    def statistics(self, u, rng):
        """Mean wear rate per cell (m per unit normed time), its standard error and the cost."""
        rates, _, cost = self.draw(u, rng)
        return rates.mean(0), rates.std(0, ddof=1) / np.sqrt(self.samples), cost


@dataclass(frozen=True)
class StepwiseCheckpoint:
    """State of a stepwise run after ``intervals`` long-term steps (all fields plain values or
    arrays, for ``.npz``): ``u`` and its Monte Carlo variance, normed time, the generator state as
    JSON text, what was saved so far and the cost spent."""

    fingerprint: str
    intervals: int
    time: float
    u: np.ndarray
    variance: np.ndarray
    rng_state: str
    saved: np.ndarray
    saved_error: np.ndarray
    times: np.ndarray
    revolutions: int
    rhs_evaluations: int
    previous_rate: np.ndarray
    previous_error: np.ndarray
    previous_step: float


SCHEMES = ("euler", "adams-bashforth")


@dataclass(frozen=True)
class Stepwise:
    """Strategy 3: frozen-geometry statistics extrapolated over steps of at most ``step_limit``
    (m) change of ``u`` (``limit_on="u"``) or of its shape ``u - mean(u)`` (``"shape"``), by
    ``scheme`` ``"euler"`` or ``"adams-bashforth"`` (second order); ``seed`` seeds the one
    ``numpy.random.Generator`` of the run."""

    frozen: FrozenGeometry
    step_limit: float
    seed: int = 0
    limit_on: str = "u"
    scheme: str = "euler"
    max_steps: int = 100_000

    def __post_init__(self):
        if not (np.isfinite(self.step_limit) and self.step_limit > 0):
            raise ScenarioError(f"step_limit must be > 0 (m), got {self.step_limit}")
        if self.limit_on not in ("u", "shape"):
            raise ScenarioError(f"limit_on must be 'u' or 'shape', not {self.limit_on!r}")
        if self.scheme not in SCHEMES:
            raise ScenarioError(f"scheme must be one of {', '.join(SCHEMES)}, not {self.scheme!r}")
        if int(self.seed) != self.seed or self.seed < 0:
            raise ScenarioError(f"seed must be a whole number >= 0, got {self.seed}")

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """``u`` (m) over normed time from ``u0`` until ``until`` or until the most worn spot has
        lost ``depth_limit`` (m). ``checkpoint(StepwiseCheckpoint)`` is called after every step;
        ``resume`` continues from one, to the same result bit for bit."""
        from railwear.longterm.phenomenological import describe

        u0 = checked_start(u0, until, depth_limit)
        f = self.frozen
        key = fingerprint(u0, until, depth_limit, self.step_limit, self.limit_on, self.scheme, self.seed, f.beta, f.band_width,
                          f.life_distance, f.service, f.revolutions, f.transient_revolutions, f.samples,
                          f.integration, repr(f.model))
        started = _time.perf_counter()
        if resume is not None:
            if resume.fingerprint != key:
                raise ScenarioError("resume: the checkpoint belongs to another problem")
            j, T = int(resume.intervals), float(resume.time)
            u, var = resume.u.copy(), resume.variance.copy()
            rng = rng_from_text(resume.rng_state)
            saved, saved_err, times = list(resume.saved), list(resume.saved_error), list(resume.times)
            revolutions, nfev = int(resume.revolutions), int(resume.rhs_evaluations)
            previous = (resume.previous_rate.copy(), resume.previous_error.copy(), float(resume.previous_step))
        else:
            j, T, u, var = 0, 0.0, u0.copy(), np.zeros(u0.size)
            rng = np.random.default_rng(self.seed)
            saved, saved_err, times = [u0.copy()], [np.zeros(u0.size)], [0.0]
            revolutions = nfev = 0
            previous = (np.zeros(u0.size), np.zeros(u0.size), 0.0)
        while T < until and (depth_limit is None or np.max(u0 - u) < depth_limit * (1 - 1e-12)):
            if j >= self.max_steps:
                raise ScenarioError(f"step_limit: {self.max_steps} steps did not reach the end; raise step_limit")
            rate, error, cost = f.statistics(u, rng)
            revolutions += cost["revolutions"]
            nfev += cost["rhs_evaluations"]
            top = np.max(np.abs(rate if self.limit_on == "u" else rate - rate.mean()))
            dT = self.step_limit / top if top > 0 else np.inf
            if T + dT >= until:
                dT = until - T
            # the Adams-Bashforth weights of this step; a step cut short at the depth keeps them,
            # so that the crossing stays exact (its error is third order)
            half_ratio = dT / previous[2] / 2 if self.scheme != "euler" and previous[2] > 0 else 0.0
            step_rate = (1 + half_ratio) * rate - half_ratio * previous[0]
            frac = stop_fraction(u0 - u, step_rate * dT, depth_limit)
            at_end = frac == 1.0 and dT == until - T
            previous_error, previous = previous[1], (rate, error, dT)
            dT *= frac
            u = u - step_rate * dT
            var = var + ((1 + half_ratio) * error * dT) ** 2 + (half_ratio * previous_error * dT) ** 2
            T = until if at_end else T + dT
            j += 1
            saved.append(u.copy())
            saved_err.append(np.sqrt(var))
            times.append(T)
            if progress is not None:
                progress(fraction_done(T, until, u0 - u, depth_limit))
            if checkpoint is not None:
                checkpoint(StepwiseCheckpoint(key, j, T, u.copy(), var.copy(), rng_state_text(rng),
                                              np.array(saved), np.array(saved_err), np.array(times),
                                              revolutions, nfev, *previous))
        error = {"u_standard_error": (("time", "angle"), np.array(saved_err),
                                      {"units": "m", "long_name": "Monte Carlo standard error of u"})}
        ds = result(saved, times, revolutions, nfev, f.service.mean,
                    {"strategy": "stepwise frozen geometry", "steps": j, "step_limit_m": self.step_limit,
                     "step_limit_on": self.limit_on, "scheme": self.scheme,
                     "wall_seconds": _time.perf_counter() - started}, error)
        return describe(ds)


def wear_intensity(model, u, beta, band_width, angle=0.0, turns=12, per_turn=20000, phase=0.0):
    """Depth rate (m/s) at the fixed wheel position ``angle`` (rad) over ``turns`` revolutions of
    the disk wheel ``model`` over the frozen ``u`` (m), paper Fig. 7: ``β P(t) / (2 a w)`` while
    the patch (half-length ``a``, uniform) covers the position, else 0. Also the integral of each
    "tooth" (m of depth per pass; the first and last may be partial) and the contact angle; starts
    at contact angle ``phase``. ``per_turn`` output times a revolution resolve a pass by about
    ``per_turn a / (π R0)`` samples (the teeth to about the inverse of that)."""
    from dataclasses import replace

    import xarray as xr

    from railwear.dynamics import simulate

    u = np.asarray(u, float)
    shape = u - u.mean()
    m = replace(model, radius_deviation=shape, initial_angle=float(phase),
                initial_lift=start_lift(model, shape, phase))
    duration = turns * wheel_turn(m)
    ds = simulate(m, duration, n_output=int(turns * per_turn) + 1)
    t, xc, power = ds.time.values, ds.contact_angle.values, ds.frictional_power.values
    half = m.patch_half_length / m.radius
    distance = np.angle(np.exp(1j * (xc - angle)))
    covered = np.abs(distance) <= half
    rate = np.where(covered, beta * power / (2 * m.patch_half_length * band_width), 0.0)
    # teeth: one per pass, where the patch leaves the position
    passes = np.cumsum(np.diff(covered.astype(int), prepend=0) == 1) * covered
    dt = np.gradient(t)
    teeth = np.array([np.sum(rate[passes == k] * dt[passes == k]) for k in range(1, passes.max() + 1)])
    return xr.Dataset(
        {"wear_intensity": ("time", rate, {"units": "m s-1", "long_name": f"depth rate at {np.degrees(angle):g} deg"}),
         "contact_angle": ("time", np.mod(xc, 2 * np.pi), {"units": "rad", "long_name": "contact angle on the wheel"}),
         "frictional_power": ("time", power, {"units": "W", "long_name": "frictional power in the contact"}),
         "tooth_depth": ("tooth", teeth, {"units": "m", "long_name": "depth worn at the position per pass"})},
        coords={"time": ("time", t, {"units": "s", "long_name": "time"})},
        attrs={"position_rad": float(angle), "speed": m.speed})
