"""Strategy 2 of the paper: the Fourier technique for dynamics linear in ``u`` (Brommundt 1996).

A harmonic ``Re(û_n e^{i n x})`` of the radius deviation passes under the contact at the angular
frequency ``ω_n = n Ω`` (``Ω`` the wheel's angular velocity). Averaged over the patch (the contact
filter ``F_n = sin(n δ) / (n δ)``, ``δ`` the patch half-length over the radius) it drives the
wear driver ``D`` (the wear law's, :meth:`~railwear.wear.WearLaw.linearisation`: the frictional
power for the energy law) through the linear transfer function ``H(ω)``; the wear law turns ``D``
into a depth rate ``c D`` at the point in contact, spread over the patch again (``F_n`` once
more). So each harmonic evolves on its own:

    d û_n / dt = λ_n û_n,   λ_n = -c H(n Ω) F_n²

``Re λ_n`` is the growth rate (1/s) and ``-Im λ_n / n`` the drift of the pattern round the wheel
(rad/s). The mean radius falls at ``c D_0``. No dynamics is integrated in time.
"""

from dataclasses import dataclass
from typing import Callable

import numpy as np
import xarray as xr

from railwear.errors import NumericalInstabilityError, ScenarioError, start_past_limit
from railwear.longterm.base import Strategy, checked_start, stop_time, time_coordinates
from railwear.longterm.spectra import describe
from railwear.units import KM
from railwear.wear import ContactSample, WearLaw


def contact_filter(orders, half_angle):
    """Mean of ``e^{i n x}`` over ``|x| <= half_angle`` (rad): ``sin(n δ)/(n δ)``."""
    return np.sinc(np.asarray(orders, float) * half_angle / np.pi)


def operating_point(model, band_width):
    """The contact of steady rolling on the round wheel, as the disk-wheel body samples it
    (:func:`~railwear.longterm.disk_wheel.swept_volume`): frictional power ``π0 = |T/R0 · ξ0| V``
    (W), the static load ``W`` (N), sliding speed ``|ξ0| V`` (m/s), the speed ``V`` and the patch
    area ``π a w/2`` (m²: the Hertz half-length ``a``, half the band ``w`` across)."""
    creepage = model.steady_creepage()
    return ContactSample(abs(model.traction_torque / model.radius * creepage) * model.speed, model.static_load,
                         abs(creepage) * model.speed, model.speed, np.pi * model.patch_half_length * band_width / 2)


def linearised_laws():
    """Names of the registered wear laws that give a linearisation."""
    return [name for name, cls in WearLaw.registry.items() if cls.linearisation is not WearLaw.linearisation]


def law_terms(model, law, band_width):
    """``(linearisation, terms)``: ``law`` (a :class:`~railwear.wear.WearLaw`) about the
    :func:`operating_point` of ``model``, and its driver's perturbation as a sum over the model's
    linear outputs, ``D̂ = Σ_o terms[o] ŷ_o`` (``o`` in frictional_power, normal_force, creepage):

        π: ∂D/∂π
        N: ∂D/∂N + ∂D/∂A (2/3) A0/W      (Hertz: A ∝ N^(2/3), as the bodies take it)
        ξ: ∂D/∂s sign(ξ0) V              (s = |ξ| V)

    The speed ``V`` is the vehicle's, held. Zero terms are left out. A law without a
    linearisation is refused, naming ``wear.law``."""
    point = operating_point(model, band_width)
    lin = law.linearisation(point) if isinstance(law, WearLaw) else None
    if lin is None:
        name = getattr(law, "name", None) or type(law).__name__
        raise ScenarioError(f"wear.law: a linear strategy (Fourier, multiplier) needs a law with a linearisation "
                            f"({', '.join(linearised_laws())}), not {name!r}")
    d = lin.partials
    load = d.get("normal_force", 0.0)
    if d.get("patch_area", 0.0):
        load = load + d["patch_area"] * (2.0 / 3.0) * float(point.patch_area) / model.static_load
    creepage = d.get("sliding_speed", 0.0) * float(np.sign(model.steady_creepage())) * model.speed
    terms = {"frictional_power": d.get("frictional_power", 0.0), "normal_force": load, "creepage": creepage}
    return lin, {o: w for o, w in terms.items() if w != 0.0}


def law_transfer(model, terms):
    """``ω ↦ Σ_o terms[o] H_o(ω)`` (complex, driver per m of filtered radius deviation) from the
    model's transfer functions ``model.transfer(ω, o)``; a term of weight 1 is the transfer itself."""

    def transfer(w):
        total = None
        for output, weight in terms.items():
            h = np.asarray(model.transfer(w, output), complex)
            h = h if weight == 1.0 else weight * h
            total = h if total is None else total + h
        return np.zeros(np.shape(w), complex) if total is None else total

    return transfer


class Harmonics:
    """What follows from rates that are diagonal in the polygon order: ``rates(orders)`` (``λ_n``,
    1/s, complex) and ``mean_rate`` (m/s) of a subclass, at its ``speed`` (m/s) on a wheel of
    ``radius`` (m): the exact solution and its stops, and the closest local odd terms."""

    def odd_terms(self, power, grid_points=None):
        """Drift ``c`` and dispersion ``d`` (rad/s, rad³/s) of the local law ``c u_x + d u_xxx``
        closest to these rates: the least-squares fit of ``c n - d n³`` to ``Im λ_n`` over orders
        ``n = 1..len(power)`` weighted by ``power`` (``|û_n|²``), which is what a least-squares fit
        over the cells of a geometry with that spectrum finds (Parseval). ``grid_points``: put the
        filter ``sinc³(n / N)`` of a grid of ``N`` points (u read linearly interpolated, wear
        gathered on cells) on ``λ_n``."""
        power = np.asarray(power, float)
        n = np.arange(1, power.size + 1, dtype=float)
        target = self.rates(n).imag
        if grid_points is not None:
            target = target * np.sinc(n / grid_points) ** 3
        weight = np.sqrt(power)
        basis = np.column_stack([n, -(n**3)]) * weight[:, None]
        drift, dispersion = np.linalg.lstsq(basis, target * weight, rcond=None)[0]
        return float(drift), float(dispersion)

    def evolve(self, u0, t):
        """``u`` (m) at the times ``t`` (s) from ``u0`` on equally spaced angles: ``(len(t), n)``."""
        u0 = np.asarray(u0, float)
        if u0.ndim != 1 or u0.size < 4:
            raise ScenarioError("u0 must be 1-D with at least 4 angles")
        t = np.atleast_1d(np.asarray(t, float))
        n = u0.size
        spectrum = np.fft.rfft(u0)
        evolved = np.empty((t.size, spectrum.size), complex)
        evolved[:, 0] = spectrum[0] + n * self.mean_rate * t
        # Fourier coefficients of Re(û e^{inx}) in numpy's e^{+inx} convention grow with e^{λ t}.
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is for the caller's guard to report
            evolved[:, 1:] = spectrum[None, 1:] * np.exp(np.outer(t, self.rates(np.arange(1, spectrum.size))))
            return np.fft.irfft(evolved, n, axis=-1)

    def run(self, u0, duration, n_save=101, depth_limit=None, peak_to_peak_limit=None):
        """``u(x, t)`` (m) from ``u0`` over ``duration`` seconds of running, stopping where the
        most worn spot has lost ``depth_limit`` (m) or the wheel is ``peak_to_peak_limit`` (m) out
        of round, found by bisection on the exact solution from the saved interval that passes it (the
        first saved state is ``u0`` itself); a start at or past ``peak_to_peak_limit`` is refused
        (:class:`ScenarioError`: reached at 0 km). A state that is not finite (a harmonic
        overflowed before a limit stopped the run, or a rate is not finite) raises
        :class:`NumericalInstabilityError` with the last finite saved state and its time (s)."""
        if not duration > 0:
            raise ScenarioError("duration must be > 0 (s)")
        u0 = np.asarray(u0, float)
        if peak_to_peak_limit is not None:
            self._check_start(u0, peak_to_peak_limit)
        limited = depth_limit is not None or peak_to_peak_limit is not None

        def reached(u):
            # An overflowed harmonic has passed either limit; the bisection finds where, finite.
            # With several wheels (u of (time, wheel, angle)) the first wheel to reach a limit stops the run.
            every = tuple(range(1, u.ndim))
            hit = ~np.all(np.isfinite(u), axis=every) if limited else np.zeros(len(u), bool)
            with np.errstate(invalid="ignore"):
                if depth_limit is not None:
                    hit |= np.max(u0[None] - u, axis=every) >= depth_limit
                if peak_to_peak_limit is not None:
                    hit |= _out_of_round(u) >= peak_to_peak_limit
            return hit

        t = np.linspace(0.0, duration, n_save)
        u = self.evolve(u0, t)
        # The start is u0 itself, checked under the limit above: irfft(rfft(u0)) may differ from it by
        # round-off and put a start within round-off of the limit past it, leaving no bracket start.
        u[0] = u0
        stop = duration
        past = np.flatnonzero(reached(u))
        if past.size:  # past[0] >= 1: the crossing lies in (t[past[0] - 1], t[past[0]]]
            lo, hi = t[past[0] - 1], t[past[0]]
            for _ in range(60):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if reached(self.evolve(u0, mid))[0] else (mid, hi)
            stop = hi
            t = np.append(t[: past[0]], stop)
            u = np.vstack([u[: past[0]], self.evolve(u0, stop)])
        n = u.shape[-1]
        orders = np.arange(1, n // 2 + 1)
        lam = self.rates(orders)
        self._check_finite(u, t, lam, orders)
        return xr.Dataset(
            {"u": (("time", "angle") if u.ndim == 2 else ("time", "wheel", "angle"), u,
                   {"units": "m", "long_name": "radius deviation from the nominal radius"}),
             "growth_rate": (("order",), lam.real, {"units": "s-1", "long_name": "growth rate of the harmonic"}),
             "drift": (("order",), -lam.imag / orders,
                       {"units": "rad s-1", "long_name": "drift of the harmonic round the wheel"})},
            coords={"time": ("time", t, {"units": "s", "long_name": "time in service"}),
                    "distance": ("time", t * self.speed / KM, {"units": "km", "long_name": "distance run"}),
                    "angle": ("angle", 2 * np.pi * np.arange(n) / n, {"units": "rad", "long_name": "angle round the wheel"}),
                    "order": ("order", orders, {"units": "1", "long_name": "polygon order"})},
            attrs={"strategy": "Fourier technique for linear dynamics (Brommundt)", "stop_seconds": stop},
        )

    def _check_start(self, u0, limit):
        """Refuse a start ``u0`` (m; a row per wheel with several) at or past the peak-to-peak
        ``limit`` (m), the run's stop at 0 km, in one line naming the field, the wheel and by how
        much (a start within round-off of the limit prints as the limit at 4 digits)."""
        each = np.ptp(u0, axis=-1).reshape(-1)
        k = int(np.argmax(each))
        excess = each[k] - limit
        if excess < 0:
            return
        positions = getattr(self, "positions", None)
        wheel = f"the wheel at {positions[k]:g} m" if u0.ndim == 2 and positions is not None else "the wheel"
        raise start_past_limit("solver.peak_to_peak_limit_mm", each[k], limit, wheel)

    def _check_finite(self, u, t, lam, orders):
        """Raise :class:`NumericalInstabilityError` at the first saved state ``u`` (m) at times
        ``t`` (s) that is not finite, naming the fastest rate ``lam`` (1/s) and its order."""
        bad = ~np.all(np.isfinite(u), axis=tuple(range(1, u.ndim)))
        if not bad.any():
            return
        k = int(np.argmax(bad))
        finite = np.isfinite(lam)
        if not finite.all():
            why = f"the growth rate of order {int(orders[np.argmin(finite)])} is not finite"
        else:
            i = int(np.argmax(lam.real))
            why = (f"order {int(orders[i])} grows at {lam.real[i]:.3g} 1/s and its amplitude overflowed by "
                   f"{t[k] * self.speed / KM:.4g} km with no limit reached")
        good = max(k - 1, 0)
        raise NumericalInstabilityError(f"the Fourier solution is not finite: {why}",
                                        last_good=u[good], last_time=float(t[good]))


def _out_of_round(u):
    """Peak to peak (m) of ``u`` (``(time, angle)``, or ``(time, wheel, angle)``: the wheel most
    out of round) at each time."""
    return np.ptp(u, axis=-1).reshape(len(u), -1).max(axis=1)


@dataclass(frozen=True)
class Fourier(Harmonics):
    """Harmonic wear growth from a transfer function.

    ``transfer(ω)``: driver per metre of filtered radius deviation at ``ω`` (rad/s), complex;
    ``steady_driver`` the driver of the round wheel; ``depth_per_driver`` ``c`` (m/s per unit of
    driver); ``wheel_speed`` Ω (rad/s); ``half_angle`` δ (rad); ``speed`` v (m/s) for distances;
    ``radius`` R0 (m) of the wheel, for wavelengths (``None``: unknown); ``filtered``: the
    transfer already carries the contact filter (a non-steady contact), so no ``F_n²``.
    """

    transfer: Callable
    steady_driver: float
    depth_per_driver: float
    wheel_speed: float
    half_angle: float
    speed: float
    radius: float | None = None
    filtered: bool = False

    def __post_init__(self):
        for name in ("depth_per_driver", "wheel_speed", "speed"):
            if not getattr(self, name) > 0:
                raise ScenarioError(f"{name} must be > 0")
        if not 0 <= self.half_angle < np.pi / 2:
            raise ScenarioError("half_angle must lie in [0, π/2)")

    def rates(self, orders):
        """``λ_n`` (1/s, complex) for polygon orders ``n >= 1``."""
        n = np.atleast_1d(np.asarray(orders, float))
        if np.any(n < 1):
            raise ScenarioError("orders must be >= 1")
        H = np.asarray(self.transfer(n * self.wheel_speed), complex)
        if self.filtered:
            return -self.depth_per_driver * H
        return -self.depth_per_driver * H * contact_filter(n, self.half_angle) ** 2

    @property
    def mean_rate(self):
        """Rate of the mean radius (m/s, negative: it wears)."""
        return -self.depth_per_driver * self.steady_driver

    @classmethod
    def disk_wheel(cls, model, law, band_width, driver="law"):
        """From a :class:`~railwear.dynamics.DiskWheelModel` (or a model with its transfer
        functions) linearised about steady rolling.

        ``driver`` "law": the driver ``D`` of the wear law ``law`` (a :class:`~railwear.wear.WearLaw`
        with a linearisation, :func:`law_terms`; the frictional power for the energy law),
        ``c = κ / (2π R0 w)``, ``D0`` the law's driver at the :func:`operating_point`; or
        "normal_force" with a law ``c`` = ``law`` (m/s per N) given as a number. ``band_width``
        ``w`` (m) is the lateral width the wear spreads over.
        """
        if not band_width > 0:
            raise ScenarioError("band_width must be > 0 (m)")
        creepage = model.steady_creepage()
        omega = model.speed * (1 + creepage) / model.radius
        circumference = 2 * np.pi * model.radius
        if driver == "law":
            lin, terms = law_terms(model, law, band_width)
            depth_per_driver = lin.coefficient / (circumference * band_width)
            steady = lin.driver
            transfer = law_transfer(model, terms)
        elif driver == "normal_force":
            depth_per_driver = float(law)
            steady = model.static_load
            transfer = model.contact_force_transfer
        else:
            raise ScenarioError(f"driver must be 'law' or 'normal_force', not {driver!r}")
        return cls(transfer, steady, depth_per_driver, omega, model.patch_half_length / model.radius,
                   model.speed, model.radius, bool(getattr(model, "filters_contact", False)))


@dataclass(frozen=True)
class FourierCycle(Harmonics):
    """The Fourier technique over a duty cycle: ``parts`` (one :class:`Fourier` per segment, the
    same wheel) run the ``shares`` of the distance. Per metre the rates are the distance-weighted
    mean ``Σ p_k λ_n^k / V_k``, exact for any order of the segments since every part is diagonal
    in ``n`` (:mod:`railwear.longterm.duty`); seconds are counted at the mean speed
    ``V̄ = 1 / Σ p_k / V_k``. One part is that part itself (:meth:`of`)."""

    parts: tuple
    shares: tuple

    def __post_init__(self):
        if len(self.parts) != len(self.shares) or not self.parts:
            raise ScenarioError("a Fourier cycle needs one share per part")
        if abs(sum(self.shares) - 1) > 1e-9 or min(self.shares) <= 0:
            raise ScenarioError("the shares of a Fourier cycle must be > 0 and sum to 1")

    @classmethod
    def of(cls, parts, shares):
        """The technique over the cycle; a cycle of one segment is its :class:`Fourier` itself."""
        return parts[0] if len(parts) == 1 else cls(tuple(parts), tuple(float(p) for p in shares))

    @property
    def speed(self):
        return 1.0 / sum(p / f.speed for p, f in zip(self.shares, self.parts))

    @property
    def radius(self):
        return self.parts[0].radius

    def rates(self, orders):
        """``V̄ Σ_k p_k λ_n^k / V_k`` (1/s at the mean speed)."""
        return self.speed * sum(p / f.speed * f.rates(orders) for p, f in zip(self.shares, self.parts))

    @property
    def mean_rate(self):
        return self.speed * sum(p / f.speed * f.mean_rate for p, f in zip(self.shares, self.parts))


@dataclass(frozen=True)
class FourierStrategy(Strategy, name="fourier"):
    """The Fourier technique behind the strategy interface, in normed life time (one unit is
    ``life_distance`` metres at the model's speed); ``body`` names the model the transfer
    functions come from."""

    fourier: Fourier
    life_distance: float
    n_save: int = 101
    body: str = "disk_wheel"
    peak_to_peak_limit: float | None = None

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """Like :meth:`Phenomenological.run`, stopping also at ``peak_to_peak_limit`` (m); the
        solution is exact, so there is nothing to checkpoint or resume and ``checkpoint`` and
        ``resume`` are not used."""
        speed = self.fourier.speed
        # several wheels (WheelsFourier): one row per wheel, each checked as one wheel's start
        start = (np.array([checked_start(row, until, depth_limit) for row in u0]) if np.ndim(u0) == 2 else
                 checked_start(u0, until, depth_limit))
        try:
            ds = self.fourier.run(start, until * self.life_distance / speed,
                                  self.n_save, depth_limit, self.peak_to_peak_limit)
        except NumericalInstabilityError as e:  # its time in seconds, the strategy's in normed time
            raise NumericalInstabilityError(str(e), last_good=e.last_good,
                                            last_time=e.last_time * speed / self.life_distance) from None
        seconds = ds.time.values
        ds = ds.drop_vars(["time", "distance"]).assign_coords(
            time_coordinates(seconds * speed / self.life_distance, self.life_distance, speed))
        ds = ds.assign_coords(service_time=("time", seconds, {"units": "s", "long_name": "time in service"}))
        ds = ds.rename({"growth_rate": "harmonic_growth_rate", "drift": "harmonic_drift"})
        ds["stop_time"] = stop_time(ds.time.values)
        if self.peak_to_peak_limit is not None:
            ds["peak_to_peak_limit"] = ((), self.peak_to_peak_limit,
                                        {"units": "m", "long_name": "out-of-roundness limit, peak to peak"})
        ds["cost_transfer_evaluations"] = ((), ds.sizes["order"],
                                           {"units": "1", "long_name": "orders of the transfer function evaluated"})
        ds.attrs.update(strategy=self.name, body=self.body, scenario_hash="",
                        strategy_description=ds.attrs["strategy"])
        if progress is not None:
            progress(1.0)
        return describe(ds.drop_vars("order"), self.fourier.radius)


def stability_map(make_model, speeds, orders, law, band_width, driver="law"):
    """Growth rate (1/km) of polygon order ``n`` over speed (m/s) for a linear dynamic model.

    ``make_model(speed)`` returns the model at a speed. Per kilometre run, so that speeds compare.
    """
    speeds = np.atleast_1d(np.asarray(speeds, float))
    orders = np.atleast_1d(np.asarray(orders, int))
    rate = np.array([Fourier.disk_wheel(make_model(v), law, band_width, driver).rates(orders).real / v * KM
                     for v in speeds])
    return xr.Dataset(
        {"growth_rate": (("speed", "order"), rate, {"units": "km-1", "long_name": "growth rate per kilometre run"})},
        coords={"speed": ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"}),
                "order": ("order", orders, {"units": "1", "long_name": "polygon order"})},
        attrs={"strategy": "Fourier technique", "driver": driver},
    )
