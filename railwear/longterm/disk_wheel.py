"""The disk wheel as a long-term body (paper Fig. 5): strategies 1 and 3 on the compiled dynamics.

The dynamics are :class:`railwear.dynamics.DiskWheelModel` on the compiled integrator
(``railwear.dynamics.integrators.integrate``, Dormand-Prince 5(4) with contact-loss events) over
whole revolutions, the frictional energy swept onto the wheel cells. The energy ``E_j`` (J) a
cell of the ``u`` grid received becomes the depth (paper eq. 2a with the energy law, the patch
spread ``χ`` uniform over the cells it sweeps):

    Δu_j = -β E_j / (R0 Δx w),   Δx = 2π / n,

``β`` (m³/J) the energy law's volume per frictional energy and ``w`` (m) the lateral width of the
wear band: the volume removed equals ``β`` times the frictional energy, to round-off.

Frozen geometry (paper Fig. 7, strategy 3): with ``u`` frozen, the wheel runs
``transient_revolutions`` (thrown away) and then ``revolutions`` more, for ``samples`` random draws
of the initial phase (uniform on [0, 2π)) and of the speed from the service distribution; the
mean over the draws of the depth per unit normed time is the Monte Carlo rate, with its standard
error ``std / sqrt(samples)``. The dynamics see the shape ``u - mean(u)`` (a uniformly smaller
wheel only lowers the axle), each draw starting at the static approach under its cell.

A duty cycle (:class:`DutyService`) draws a segment ``k`` with the probability ``p_k``, its share
of the distance, and runs it at its speed ``V_k`` under its traction torque ``T_k = f_k W R0``
(``f_k`` its signed demand, ``W`` the static load). Each draw's depth is per unit distance run
(``Δu / (t V)`` times the distance of a unit of normed time), so the expected rate is

    E[r] = Σ_k p_k r_k,

the distance-weighted mean of the segments' rates per distance, exactly, whatever their speeds;
the Monte Carlo error (the spread of the draws, over the segments too) is reported as for any
service, and falls as ``1 / sqrt(samples)``.

Coupled (strategy 1): the wheel runs in segments of ``1 / updates_per_revolution`` of a
revolution over the current surface from where the last one ended; each segment's energy is worn
off at once with ``A β``. Finer is not better at large ``A``: each update wears the cells just
passed at once, a step of ``A`` times the wear right behind the patch that kicks the vertical
dynamics; per revolution it is spread round the whole wheel and only its uneven part is felt.
The error is first order in ``A``; ``A = 1`` is the coupled system itself.
"""

import math
from dataclasses import dataclass, field, replace

import numpy as np

from railwear.dynamics import kernels
from railwear.dynamics.integration import Integrator
from railwear.errors import ScenarioError
from railwear.longterm.base import RadiusBody, time_coordinates
from railwear.longterm.spectra import describe
from railwear.wear import ContactSample, WearLaw


def surface(u):
    """``u`` (m) at the nodes ``2π j / n`` followed by its cumulative trapezoidal integral: the
    part of the dynamics' surface array the contact filter reads (a model's full array, with its
    creep curve, is ``DiskWheelModel.surface_for``)."""
    u = np.asarray(u, float)
    dx = 2.0 * math.pi / u.size
    return np.concatenate([u, [0.0], np.cumsum(0.5 * dx * (u + np.roll(u, -1)))])


def long_term_integrator(rtol=1e-7, atol=1e-13, max_steps=50_000_000):
    """The compiled integrator of the long-term runs: Dormand-Prince 5(4) with the disk wheel's
    contact-loss events; ``atol`` on m-scale states."""
    return Integrator(method="dopri5", rtol=rtol, atol=atol, max_steps=max_steps, events=True, max_norm=1e6)


def advance(model, p, surf, y, t0, t1, energy, integrator, t_eval=None):
    """Integrate the disk wheel ``model`` (its parameter array ``p`` and surface ``surf``) from
    state ``y`` at ``t0`` to ``t1`` (s), adding the frictional energy (J) per cell to ``energy``
    (an empty array: none). Returns ``(y_end, rhs_evaluations)``, or with ``t_eval`` the
    :class:`~railwear.dynamics.integration.IntegrationResult`."""
    out = integrator.run(model.kind, p, surf, y, t0, t1, t_eval=t_eval, energy=energy)
    out.check(f"disk wheel at {model.speed:g} m/s")
    return out if t_eval is not None else (out.y.copy(), int(out.stats.rhs_evaluations))


def dense_contact(model, p, surf, y, t0, t1, integrator, n_output):
    """Run as :func:`advance` with ``n_output`` dense outputs: ``(y_end, rhs_evaluations, t,
    normal_force, creepage, power, angle)`` at the outputs (the angle unwrapped)."""
    t = np.linspace(t0, t1, n_output)
    out = advance(model, p, surf, y, t0, t1, np.zeros(0), integrator, t_eval=t)
    c = kernels.outputs(model.kind, out.t_out, out.y_out, p, surf, kernels.DW_N_OUTPUTS)
    return (out.y.copy(), int(out.stats.rhs_evaluations), out.t_out, c[:, 0], c[:, 1], c[:, 3],
            np.unwrap(c[:, 4]))  # the outputs wrap the angle


def swept_volume(model, p, surf, y, t0, t1, law, n_cells, band_width, integrator, n_output):
    """Run as :func:`advance` with ``n_output`` dense outputs and wear by ``law`` (a
    :class:`~railwear.wear.WearLaw`): the volume (m³) per cell, each output interval's
    trapezoidal volume swept over the cells as the patch passes (the compiled energy sweep's
    spread), with the Hertz patch area ``π a b (N/W)^(2/3)``, ``b`` half the band. Returns
    ``(y_end, rhs_evaluations, cell_volumes)``."""
    y, nfev, t, force, creepage, power, angle = dense_contact(model, p, surf, y, t0, t1, integrator, n_output)
    scale = np.cbrt(np.maximum(force, 0.0) / model.static_load) ** 2
    contact = ContactSample(power, force, np.abs(creepage) * model.speed, np.full(t.size, model.speed),
                            np.pi * model.patch_half_length * band_width / 2 * scale)
    rate = np.asarray(law.volume_rate_of(contact), float)
    volume = 0.5 * (rate[1:] + rate[:-1]) * np.diff(t)
    cells = np.zeros(n_cells)
    half = model.patch_half_length / model.radius
    for k in range(volume.size):
        kernels.sweep(cells, angle[k], angle[k + 1], half, volume[k])
    return y, nfev, cells


def wheel_turn(model):
    """Time of one wheel revolution in steady rolling (s): ``2π R0 / (V (1 + ξ))``."""
    return 2.0 * math.pi * model.radius / (model.speed * (1.0 + model.steady_creepage()))


def start_lift(model, u, angle):
    """Lift (m) that starts the wheel at its static approach over ``u`` at contact ``angle`` (rad):
    the patch mean of ``u`` there (the contact filter of the dynamics)."""
    return float(kernels.patch_average(surface(u), u.size, float(angle), model.patch_half_length / model.radius))


def depth_per_energy(model, n_cells, beta, band_width):
    """Depth (m) per joule a cell receives: ``β / (R0 Δx w)``."""
    return beta / (model.radius * (2.0 * math.pi / n_cells) * band_width)


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

    demands = None  # the model's own demand at every peak; DutyService carries one per peak

    @property
    def mean(self):
        """Mean speed (m/s)."""
        return float(np.dot(self.peaks, self.weights))

    def draw(self, rng, n):
        """``n`` draws with ``rng``: their speeds (m/s) and the index of the peak each came from."""
        peak = rng.choice(len(self.peaks), size=n, p=np.asarray(self.weights))
        v = np.asarray(self.peaks)[peak] + self.scatter * rng.standard_normal(n)
        low = v < 0.5
        while np.any(low):
            v[low] = np.asarray(self.peaks)[peak[low]] + self.scatter * rng.standard_normal(int(low.sum()))
            low = v < 0.5
        return v, peak

    def sample(self, rng, n):
        """``n`` speeds (m/s) drawn with ``rng``."""
        return self.draw(rng, n)[0]

    def at_peak(self, model, peak):
        """What a draw from ``peak`` changes in the disk wheel ``model`` besides its speed: here
        nothing (every peak runs the model's own traction torque)."""
        return {}


@dataclass(frozen=True)
class DutyService(ServiceSpeeds):
    """A duty cycle as a service distribution: segment ``k`` runs at the speed ``peaks[k]`` (m/s,
    with the normal ``scatter``) under the signed demand ``demands[k]`` (creep force over the
    wheel load: > 0 traction, < 0 braking) and is drawn with the probability ``weights[k]``, its
    share ``p_k`` of the distance. A draw sets the traction torque ``T_k = f_k W R0``; the mean
    speed is distance over time, ``V̄ = 1 / Σ_k p_k / V_k`` (the cycle's, as the Fourier technique
    counts its seconds)."""

    demands: tuple = ()

    def __post_init__(self):
        super().__post_init__()
        demands = tuple(float(f) for f in np.atleast_1d(self.demands))
        object.__setattr__(self, "demands", demands)
        if len(demands) != len(self.peaks):
            raise ScenarioError(f"demands: one per peak is needed ({len(self.peaks)}), not {len(demands)}")
        if not all(np.isfinite(f) and abs(f) < 1 for f in demands):
            raise ScenarioError("demands: every traction coefficient must lie in (-1, 1)")

    @classmethod
    def of(cls, duty, scatter=0.0):
        """The service of a :class:`~railwear.longterm.duty.DutyCycle`."""
        return cls(tuple(duty.speeds), tuple(duty.shares), scatter, tuple(duty.demands))

    @property
    def mean(self):
        """Distance over time, ``1 / Σ_k p_k / V_k`` (m/s)."""
        return float(1.0 / np.sum(np.asarray(self.weights) / np.asarray(self.peaks)))

    def at_peak(self, model, peak):
        """The traction torque ``f_k W R0`` (N m) of segment ``peak``."""
        return {"traction_torque": self.demands[peak] * model.static_load * model.radius}


@dataclass(frozen=True)
class DiskWheel(RadiusBody, name="disk_wheel"):
    """The disk wheel ``model`` (a :class:`~railwear.dynamics.DiskWheelModel`; its speed, phase
    and ``u`` are replaced per run) worn by ``law`` (a :class:`~railwear.wear.WearLaw`) over the
    lateral ``band_width`` (m); ``life_distance`` (m) one unit of normed time. Frozen geometry
    draws the speed from ``service`` (default: the model's speed); the coupled run updates the
    surface ``updates_per_revolution`` times a revolution. A :class:`DutyService` runs a
    duty cycle: each draw takes a segment's speed and demand. The energy law takes the compiled
    energy sweep; other laws read the contact at ``outputs_per_revolution`` times a revolution
    (:func:`swept_volume`)."""

    model: object
    law: WearLaw
    band_width: float
    life_distance: float
    service: ServiceSpeeds | None = None
    revolutions: int = 4
    transient_revolutions: int = 4
    samples: int = 8
    updates_per_revolution: int = 1
    outputs_per_revolution: int = 2000
    integration: Integrator = field(default_factory=long_term_integrator)
    _coupled: dict = field(default_factory=dict, compare=False, repr=False)

    label = "disk wheel"

    def __post_init__(self):
        if not isinstance(self.law, WearLaw):
            raise ScenarioError(f"law must be a railwear.wear.WearLaw, not {type(self.law).__name__}")
        for name in ("band_width", "life_distance"):
            if not (np.isfinite(getattr(self, name)) and getattr(self, name) > 0):
                raise ScenarioError(f"{name} must be finite and > 0")
        for name, low in (("revolutions", 1), ("transient_revolutions", 0), ("samples", 2),
                          ("updates_per_revolution", 1), ("outputs_per_revolution", 16)):
            value = getattr(self, name)
            if int(value) != value or value < low:
                raise ScenarioError(f"{name} must be a whole number >= {low}, got {value}"
                                    + (" (for a variance)" if name == "samples" else ""))
        if self.service is None:
            object.__setattr__(self, "service", ServiceSpeeds((self.model.speed,)))

    # the dynamics hook: a body on other dynamics (VehicleTrackBody) overrides these five
    def dynamics(self, model):
        """What integrates the disk wheel ``model``: here the model itself, by ``integration``."""
        return model

    def positions(self, rng, count):
        """Where each of ``count`` runs starts along the track: here nowhere (no draw)."""
        return [None] * count

    def at_rest(self, model, dyn, where):
        """The state a run of ``model`` starts in at ``where``."""
        return model.initial_state()

    def seconds(self, model, dyn, revolutions, per=1):
        """Duration (s) of ``revolutions / per`` wheel turns."""
        return revolutions * wheel_turn(model) / per

    def run(self, model, dyn, p, surf, y, where, t0, energy, revolutions, per=1):
        """``(y, where, seconds, rhs)`` after ``revolutions / per`` turns from ``y`` at ``t0`` (s),
        the frictional energy (J) per cell added to ``energy`` (size 0: none)."""
        seconds = self.seconds(model, dyn, revolutions, per)
        y, n = advance(model, p, surf, y, t0, t0 + seconds, energy, self.integration)
        return y, where, seconds, n

    def _transient(self, model, dyn, p, surf, where, cost):
        """State, position and time (s) after ``transient_revolutions`` from rest at ``where``."""
        y, t = self.at_rest(model, dyn, where), 0.0
        if self.transient_revolutions > 0:
            y, where, t, n = self.run(model, dyn, p, surf, y, where, 0.0, np.zeros(0), self.transient_revolutions)
            cost["rhs_evaluations"] += n
        return y, where, t

    # frozen geometry
    def frozen_runs(self, shape, rng, cost):
        """The Monte Carlo draws over the frozen ``shape`` (m): for each, the model at its drawn
        speed (and, over a duty cycle, its segment's traction torque: ``service.at_peak``), phase
        and track position, its dynamics, parameters, surface, state after the
        transient, the transient's end (s) and the position; the transient's right-hand sides are
        added to ``cost``."""
        speeds, peaks = self.service.draw(rng, self.samples)
        phases = rng.uniform(0.0, 2.0 * np.pi, self.samples)
        for v, k, phase, where in zip(speeds, peaks, phases, self.positions(rng, self.samples)):
            model = self.drawn(shape, v, k, phase)
            dyn = self.dynamics(model)
            p, surf = model.params(), model.surface()
            y, where, t0 = self._transient(model, dyn, p, surf, where, cost)
            yield model, dyn, p, surf, y, t0, where

    def drawn(self, shape, speed, peak, phase):
        """The model of one draw over the frozen ``shape`` (m): at ``speed`` (m/s), the service's
        ``peak`` (its traction torque over a duty cycle) and contact ``phase`` (rad), started at
        the static approach there."""
        return replace(self.model, speed=float(speed), radius_deviation=shape, initial_angle=float(phase),
                       initial_lift=start_lift(self.model, shape, phase), **self.service.at_peak(self.model, peak))

    def draw(self, u, rng):
        """One Monte Carlo set over the frozen ``u`` (m): ``(rates, cost)``, ``rates`` the depth
        per unit normed time of each draw and cell (m), ``(samples, n)``; ``cost`` a dict of
        revolutions simulated and right-hand-side evaluations."""
        u = np.asarray(u, float)
        rates = np.empty((self.samples, u.size))
        cost = {"revolutions": self.samples * (self.revolutions + self.transient_revolutions), "rhs_evaluations": 0}
        for i, (model, dyn, p, surf, y, t0, where) in enumerate(self.frozen_runs(u - u.mean(), rng, cost)):
            depth, seconds, n = self._wear(model, dyn, p, surf, y, where, t0, u.size)
            cost["rhs_evaluations"] += n
            rates[i] = depth / (seconds * model.speed) * self.life_distance
        return rates, cost

    def statistics(self, u, rng):
        """Mean wear rate per cell (m per unit normed time), its standard error and the cost."""
        rates, cost = self.draw(u, rng)
        return rates.mean(0), rates.std(0, ddof=1) / np.sqrt(self.samples), cost

    @property
    def beta(self):
        """The energy law's volume per frictional energy (m³/J), ``None`` for another law."""
        return self.law.beta

    def _wear(self, model, dyn, p, surf, y, where, t0, n_cells):
        """Depth (m) per cell worn over ``revolutions`` from ``t0`` (s), their seconds and the
        right-hand sides; the compiled energy sweep for the energy law."""
        if self.beta is not None:
            energy = np.zeros(n_cells)
            _, _, seconds, n = self.run(model, dyn, p, surf, y, where, t0, energy, self.revolutions)
            return energy * depth_per_energy(model, n_cells, self.beta, self.band_width), seconds, n
        n_output = max(int(math.ceil(self.revolutions * self.outputs_per_revolution)), 2) + 1
        seconds = self.seconds(model, dyn, self.revolutions)
        _, n, volume = swept_volume(model, p, surf, y, t0, t0 + seconds, self.law, n_cells, self.band_width,
                                    self.integration, n_output)
        return volume / self.cell_volume(n_cells), seconds, n

    def cell_volume(self, n_cells):
        """Volume (m³) per metre of depth of one of ``n_cells`` cells: ``R0 Δx w``."""
        return self.model.radius * (2.0 * math.pi / n_cells) * self.band_width

    # the body protocol
    def new_cost(self):
        return {"revolutions": 0, "rhs_evaluations": 0}

    def rates(self, u, rng, cost):
        rate, error, spent = self.statistics(u, rng)
        for k, v in spent.items():
            cost[k] += v
        return rate, error, float(rate.sum() * self.cell_volume(u.shape[-1])), None

    def carried(self, where):
        """The track position kept in a coupled run's carry (none here)."""
        return {}

    def couple(self, u, rng, acceleration, cost):
        shape = u - u.mean()
        model, dyn, p, _, _ = self._derived(shape, acceleration)
        y, where, t = self._transient(model, dyn, p, model.surface(), self.positions(rng, 1)[0], cost)
        cost["revolutions"] += self.transient_revolutions
        return {"shape": shape, "seconds": t, "state": y, **self.carried(where)}

    def _derived(self, shape, acceleration):
        """The model over the start's ``shape`` (m), its dynamics and parameters, the depth per
        joule times ``A`` and the normed time per segment, kept for the run."""
        key = (np.asarray(shape, float).tobytes(), acceleration)
        if self._coupled.get("key") != key:
            model = replace(self.model, radius_deviation=shape,
                            initial_lift=start_lift(self.model, shape, self.model.initial_angle))
            dyn = self.dynamics(model)
            gain = acceleration * (1.0 if self.beta is None else
                                   depth_per_energy(model, shape.size, self.beta, self.band_width))
            segment = self.seconds(model, dyn, 1, self.updates_per_revolution)
            dT = acceleration * model.speed * segment / self.life_distance
            self._coupled.clear()
            self._coupled.update(key=key, derived=(model, dyn, model.params(), gain, dT))
        return self._coupled["derived"]

    def segment(self, u, carry, acceleration, remaining, cost):
        model, dyn, p, gain, dT = self._derived(carry["shape"], acceleration)
        t, surf, where = carry["seconds"], model.surface_for(u - u.mean()), carry.get("position")
        if self.beta is not None:
            energy = np.zeros(u.size)
            y, where, segment, n = self.run(model, dyn, p, surf, carry["state"], where, t, energy, 1,
                                            self.updates_per_revolution)
            increment, law = gain * energy, acceleration * self.beta * float(energy.sum())
        else:
            segment = self.seconds(model, dyn, 1, self.updates_per_revolution)
            n_output = max(int(math.ceil(self.outputs_per_revolution / self.updates_per_revolution)), 2) + 1
            y, n, volume = swept_volume(model, p, surf, carry["state"], t, t + segment, self.law, u.size,
                                        self.band_width, self.integration, n_output)
            increment, law = acceleration * volume / self.cell_volume(u.size), acceleration * float(volume.sum())
        cost["rhs_evaluations"] += n
        cost["revolutions"] += 1 / self.updates_per_revolution
        carry = {"shape": carry["shape"], "seconds": t + segment, "state": y, **self.carried(where)}
        return increment, dT, False, law, None, carry

    def record(self, u, seen, law_volume):
        return {"u": u.copy(), "law_volume": law_volume}

    def result(self, records, times, cost, error, attrs):
        import xarray as xr

        saved = np.asarray(records["u"])
        n = saved.shape[-1]
        removed = (saved[0] - saved).reshape(saved.shape[0], -1).sum(1) * self.cell_volume(n)
        dims = ("time", *self.batch_coordinates(), "angle")
        data = {"u": (dims, saved, {"units": "m", "long_name": "radius deviation from the nominal radius"}),
                "removed_volume": ("time", removed, {"units": "m3", "long_name": "volume removed from the tread"}),
                "law_volume": ("time", np.asarray(records["law_volume"], float),
                               {"units": "m3", "long_name": "volume of the wear law"})}
        if error is not None:
            data["u_standard_error"] = (dims, np.asarray(error),
                                        {"units": "m", "long_name": "Monte Carlo standard error of u"})
        coords = time_coordinates(times, self.life_distance, self.service.mean)
        coords["angle"] = ("angle", 2 * np.pi * np.arange(n) / n, {"units": "rad", "long_name": "angle round the wheel"})
        coords.update(self.batch_coordinates())
        return describe(xr.Dataset(data, coords=coords, attrs=attrs), self.model.radius)

    def batch_coordinates(self):
        """The coordinates ``u`` has between ``time`` and ``angle`` (here none: one wheel)."""
        return {}

    def fingerprint_parts(self):
        return (repr(self.law), self.band_width, self.life_distance, self.service, self.revolutions,
                self.transient_revolutions, self.samples, self.updates_per_revolution, self.outputs_per_revolution,
                self.integration, repr(self.model))


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
