"""The multiplier law as a long-term strategy: the Fourier technique's rates plus the contact's nonlinearity.

    u_T = Λ u + B g(A u)        (railwear.pde.multiplier)

``Λ`` is the Fourier technique's ``λ_n`` (``railwear.longterm.fourier``: ``-c H(nΩ) F_n²``,
converted to normed time, 1/s times ``life_distance / V``), exact in ETDRK4's linear part, so
the law selects the orders the dynamics select. The local part is one of:

- none: ``g`` the mean wear rate ``-c D_0`` alone; the run is the Fourier technique's solution;
- a local law ``h(u_xx)`` (``A_n = -n²``), entering as its :class:`~railwear.pde.multiplier.Remainder`
  (its value and slope at 0 removed: the slope's smoothing is in ``Λ`` already);
- the contact's own nonlinearity (:func:`load_nonlinearity`): ``w`` the dynamic normal force
  (``A_n = F_n H_N(nΩ)``, N per m of ``u``) and ``g(w) = -c [D(W + w) - D(W) - D'(W) w]``, ``D``
  the wear law's driver (:meth:`~railwear.wear.WearLaw.driver_of`; the frictional power ``P``
  for the energy law) at the quasi-static contact under the load ``W + w`` and the traction
  demand (:func:`quasi_static_contact`: Kalker ``f11 ∝ N^(2/3)``, Johnson-Vermeulen saturation
  at ``μ N``, nothing below contact loss), spread over the patch (``B_n = F_n``).

Over a duty cycle ``Λ`` is the cycle's (:class:`~railwear.longterm.fourier.FourierCycle`): per
unit distance ``Σ_k p_k λ_n^k / V_k``, exact for the linear part however the segments alternate,
since each segment's operator is diagonal in ``n``. The load nonlinearity is not averaged: each
segment has its own ``A_n`` (the load transfer at its wheel speed), ``B_n`` and ``g`` (the contact
under its demand), so the cycle's law would be ``Λ̄ u + Σ_k p_k (L/V_k) B_k g_k(A_k u)``, a sum of
as many nonlinear terms as segments, where the solver takes one; a cycle runs with ``local``
``None`` or a local law ``h(u_xx)``, and the load is refused.

``grid_points`` puts the filter of the direct strategy's surface grid on the multipliers: it reads
``u`` linearly interpolated between nodes (``sinc²(n/N)`` on ``A``) and gathers the wear on whole
cells (``sinc(n/N)`` on ``B``), ``sinc³`` on ``λ_n`` (docs/strategies.md, grid study).
"""

from dataclasses import dataclass, field

import numpy as np

from railwear.contact.saturation import inverse_cubic
from railwear.errors import ScenarioError, start_past_limit
from railwear.longterm.base import Strategy, checked_start
from railwear.longterm.fourier import Fourier, FourierCycle, contact_filter
from railwear.longterm.phenomenological import finish, solver_checkpoints
from railwear.pde import BuiltinRate, Cubic, Pointwise
from railwear.pde.multiplier import Fixed, Remainder, solve_multiplier
from railwear.wear import ContactSample

LOAD_TABLE_RANGE = 1.5  # the table of D spans W (1 ± this) in load


def quasi_static_creep(wheel, load):
    """``(creepage, power)`` of ``wheel`` (a :class:`~railwear.dynamics.DiskWheelModel` with
    the cubic creep law) at the normal force ``load`` (N) under its traction demand ``F = T / R0``:
    ``ξ = (3 μ N / f11(N)) (1 - (1 - q)^(1/3))`` with ``q = |F| / (μ N)`` and ``f11(N) = f11
    (N/W)^(2/3)`` (the inverse of the kernel's creep law, :func:`~railwear.contact.inverse_cubic`;
    ``|F| / f11(N)`` without saturation); at ``q >= 1`` the wheel slides at ``3 μ N / f11(N)`` under
    ``μ N``. The frictional power ``P = |F| ξ V`` (W); both 0 where ``N <= 0``."""
    if wheel.creep_law != "cubic":
        raise ScenarioError("the load nonlinearity needs the cubic creep law")
    demand = abs(wheel.traction_torque / wheel.radius)
    n = np.asarray(load, float)
    on = n > 0
    safe = np.where(on, n, 1.0)
    f11 = wheel.f11 * (safe / wheel.static_load) ** (2.0 / 3.0)
    if not np.isfinite(wheel.friction_coefficient):
        creepage = demand / f11
        return np.where(on, creepage, 0.0), np.where(on, demand**2 / f11 * wheel.speed, 0.0)
    limit = wheel.friction_coefficient * safe
    q, fraction = inverse_cubic(demand, limit)
    creepage = 3 * limit / f11 * fraction
    return np.where(on, creepage, 0.0), np.where(on, q * limit * creepage * wheel.speed, 0.0)


def frictional_power_at_load(wheel, load):
    """Quasi-static frictional power ``P = |F| ξ V`` (W) of ``wheel`` at the normal force ``load``
    (N), :func:`quasi_static_creep`; 0 for ``N <= 0``."""
    return quasi_static_creep(wheel, load)[1]


def quasi_static_contact(wheel, load, band_width):
    """The :class:`~railwear.wear.ContactSample` of ``wheel`` at the normal force ``load`` (N),
    as the disk-wheel body samples its contact: the frictional power and creepage of
    :func:`quasi_static_creep`, sliding speed ``|ξ| V`` (m/s), the speed ``V`` and the Hertz patch
    area ``π a w/2 (N/W)^(2/3)`` (m², ``w`` = ``band_width`` in m); nothing for ``N <= 0``."""
    creepage, power = quasi_static_creep(wheel, load)
    n = np.asarray(load, float)
    area = np.pi * wheel.patch_half_length * band_width / 2 * np.cbrt(np.maximum(n, 0.0) / wheel.static_load) ** 2
    return ContactSample(power, n, np.abs(creepage) * wheel.speed, np.full(n.shape, float(wheel.speed)), area)


@dataclass(frozen=True, eq=False)
class QuasiStaticDriver:
    """``N ↦ D``: the driver of the wear ``law`` (:meth:`~railwear.wear.WearLaw.driver_of`) at
    the :func:`quasi_static_contact` of ``wheel`` under the load ``N`` (N), band ``band_width`` (m)."""

    wheel: object
    law: object
    band_width: float

    def __call__(self, load):
        return np.asarray(self.law.driver_of(quasi_static_contact(self.wheel, load, self.band_width)), float)


def load_nonlinearity(wheel, depth_per_driver, driver=None):
    """``g(w) = -c [D(W + w) - D(W) - D'(W) w]`` (m/s) over the dynamic load ``w`` (N) as a
    Hermite table, ``c`` the Fourier technique's ``depth_per_driver`` (m/s per unit of ``D``) and
    ``driver`` ``D(N)`` (a :class:`QuasiStaticDriver`; ``None``: the frictional power
    :func:`frictional_power_at_load`, the energy law's driver)."""
    W = wheel.static_load
    if driver is None:
        def driver(load):
            return frictional_power_at_load(wheel, load)

    def value(w):
        return -depth_per_driver * driver(W + w)

    def slope(w):
        step = 1e-6 * W
        return (value(w + step) - value(w - step)) / (2 * step)

    return Remainder(Fixed(Pointwise.from_samples(-LOAD_TABLE_RANGE * W, LOAD_TABLE_RANGE * W, value, slope)))


@dataclass(frozen=True, eq=False)
class Multiplier(Strategy, name="multiplier"):
    """The multiplier law on a wheel whose ``fourier`` (:class:`Fourier`, or a
    :class:`~railwear.longterm.fourier.FourierCycle` without the load) gives ``λ_n``;
    ``life_distance`` (m) is one unit of normed time. ``local``: ``None``, a built-in form
    ``h(u_xx)`` (m per unit normed time) or ``"load"``; the load needs ``wheel`` (the
    :class:`~railwear.dynamics.DiskWheelModel` whose contact it is) and ``load_transfer`` (``N̂ /
    ū`` in N/m at ω in rad/s, the model's ``contact_force_transfer``), with ``load_driver`` the
    wear law's driver at a load (:class:`QuasiStaticDriver`; ``None``: the frictional power).
    ``grid_points``: the surface grid of the direct run to compare with (``None``: no grid
    filter). ``epsilon``, ``nu`` and ``options`` as for
    :class:`~railwear.longterm.phenomenological.Phenomenological`.
    ``peak_to_peak_limit`` (m): stop where the wheel is that far out of round, peak to peak (the
    crossing bracketed within one ETDRK4 step, :func:`~railwear.pde.multiplier.solve_multiplier`)."""

    checkpoint_format = "evolution"

    fourier: Fourier
    life_distance: float
    local: object = None
    wheel: object = None
    load_transfer: object = None
    load_driver: object = None
    grid_points: int | None = None
    epsilon: float = 0.0
    nu: float = 0.0
    options: dict = field(default_factory=dict)
    body: str = "disk_wheel"
    peak_to_peak_limit: float | None = None

    def __post_init__(self):
        if not self.life_distance > 0:
            raise ScenarioError("life_distance must be > 0 (m)")
        if self.local == "load" and (self.wheel is None or self.load_transfer is None):
            raise ScenarioError("local = 'load' needs the wheel and its load_transfer")
        if self.local == "load" and isinstance(self.fourier, FourierCycle):
            raise ScenarioError("local: the load nonlinearity is one per segment, not over a duty cycle (FourierCycle); "
                                "use local = None")
        if not (self.local is None or self.local == "load" or isinstance(self.local, BuiltinRate)):
            raise ScenarioError("local must be None, 'load' or a built-in wear-rate form")
        if self.grid_points is not None and not (int(self.grid_points) == self.grid_points >= 2):
            raise ScenarioError("grid_points must be a whole number >= 2")
        if self.peak_to_peak_limit is not None and not (np.isfinite(self.peak_to_peak_limit)
                                                        and self.peak_to_peak_limit > 0):
            raise ScenarioError(f"peak_to_peak_limit must be > 0 (m), got {self.peak_to_peak_limit!r}")

    @classmethod
    def from_fourier(cls, fourier, life_distance, local=None, **options):
        """The law from any :class:`Fourier` (e.g. ``METRO.fourier(speed, law)``), with ``local``
        ``None`` or a local law ``h(u_xx)``."""
        return cls(fourier, life_distance, local, **options)

    @classmethod
    def from_model(cls, model, law, band_width, life_distance, **options):
        """The law of a linear wheel model (a :class:`~railwear.dynamics.DiskWheelModel` or a
        :class:`~railwear.longterm.vehicle_track.VehicleTrackModel`) with the contact's load
        nonlinearity of the wear law ``law`` (one with a linearisation): :meth:`Fourier.disk_wheel`
        for ``Λ``, :class:`QuasiStaticDriver` for ``g``."""
        wheel = getattr(model, "wheel", model)
        return cls(Fourier.disk_wheel(model, law, band_width), life_distance, "load", wheel,
                   model.contact_force_transfer, QuasiStaticDriver(wheel, law, band_width), **options)

    @property
    def seconds_per_unit(self):
        """Service seconds in one unit of normed time (s)."""
        return self.life_distance / self.fourier.speed

    def multipliers(self, n):
        """``(λ_n, A_n, B_n, g)`` on ``n`` angles, orders ``0..n/2``, per unit normed time."""
        f, scale = self.fourier, self.seconds_per_unit
        orders = np.arange(n // 2 + 1, dtype=float)
        grid = np.ones(orders.size) if self.grid_points is None else np.sinc(orders / self.grid_points)
        rate = np.zeros(orders.size, complex)
        rate[1:] = f.rates(orders[1:]) * scale
        rate *= grid**3
        mean = f.mean_rate * scale
        if self.local is None:
            return rate, None, None, Cubic(mean)
        if self.local != "load":
            return rate, None, None, Remainder(self.local, mean)
        filt = contact_filter(orders, f.half_angle)
        a = np.zeros(orders.size, complex)
        a[1:] = filt[1:] * np.asarray(self.load_transfer(orders[1:] * f.wheel_speed), complex) * grid[1:] ** 2
        table = load_nonlinearity(self.wheel, f.depth_per_driver * scale, self.load_driver)
        return rate, a, filt * grid, Remainder(table, mean)

    def run(self, u0, until=1.0, depth_limit=None, progress=None, checkpoint=None, resume=None):
        """Solve to normed time ``until``, removed depth ``depth_limit`` (m) at the most worn spot or
        the ``peak_to_peak_limit``, whichever comes first; checkpoints and resume as
        :class:`~railwear.longterm.phenomenological.Phenomenological`."""
        u0 = checked_start(u0, until, depth_limit)
        if u0.size % 2 or u0.size < 8:
            raise ScenarioError("u0 must have an even number >= 8 of angles")
        limit = self.peak_to_peak_limit
        if limit is not None and np.ptp(u0) >= limit:
            raise start_past_limit("solver.peak_to_peak_limit_mm", np.ptp(u0), limit)
        rate, a, b, g = self.multipliers(u0.size)
        save, resume = solver_checkpoints(self.name, checkpoint, resume)
        ds = solve_multiplier(u0, until, rate, g, self.fourier.speed, self.epsilon, self.nu, local_input=a,
                              local_output=b, depth_limit=depth_limit, peak_to_peak_limit=limit, progress=progress,
                              checkpoint=save, resume=resume, **self.options)
        ds = finish(ds, self.name, self.life_distance, "multiplier law: Fourier rates plus the local nonlinearity",
                    self.fourier.radius)
        if limit is not None:
            ds["peak_to_peak_limit"] = ((), limit, {"units": "m", "long_name": "out-of-roundness limit, peak to peak"})
        ds.attrs["body"] = self.body
        describe = getattr(self.fourier, "describe", None)  # several wheels: their combinations
        return ds if describe is None else describe(ds)
