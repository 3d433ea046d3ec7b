"""Wear laws: the volume of steel one contact removes per second (m³/s), and their internal state.

- :class:`EnergyLaw`: volume ∝ frictional power, paper eq. 2a (``u' = -β π`` with ``β = k_e / ρ``
  spread over the patch by ``χ``).
- :class:`Archard`: ``V = k N s / H`` per sliding distance ``s``.
- :class:`USFD`: the Tγ/A wear function of Braghin, Lewis, Dwyer-Joyce & Bruni, Wear 261 (2006)
  1253, mass per metre rolled per mm² of contact.
- :class:`InternalStateLaw`: the general form of paper eq. 2, ``u' = U(t, π, u, z)``,
  ``z' = Z(t, π, u, z)``, on the cells of a wear surface.
Rates are positive for material removed; depth ``u`` of the paper falls by them.

Every law a body can wear with is a :class:`WearLaw` registered by name: ``volume_rate_of``
takes a :class:`ContactSample` (what the dynamics know of the contact at each output time) and
returns m³/s. Laws proportional to the frictional power say so by their ``beta`` (m³/J), and the
bodies then take the compiled path that sweeps the frictional energy onto the cells.

A law may also give its :class:`Linearisation` about an operating point, which the linear
strategies (the Fourier technique, the multiplier law) need: factored as ``V = κ D`` (a
coefficient ``κ`` and the law's driver ``D``, ``driver_of``), the driver's value and its
derivatives with respect to the fields of :class:`ContactSample` (:data:`LINEARISED`).
"""

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Callable

import numpy as np

from railwear.errors import ScenarioError
from railwear.registry import Registered
from railwear.units import MM2, UG


@dataclass(frozen=True)
class ContactSample:
    """The contact at a series of instants (arrays of one shape, SI): ``frictional_power`` (W),
    ``normal_force`` (N), ``sliding_speed`` (m/s, the creepage's magnitude times the speed),
    ``speed`` (m/s, rolling) and ``patch_area`` (m², 0 out of contact)."""

    frictional_power: np.ndarray
    normal_force: np.ndarray
    sliding_speed: np.ndarray
    speed: np.ndarray
    patch_area: np.ndarray


LINEARISED = ("frictional_power", "normal_force", "sliding_speed", "speed", "patch_area")  # ContactSample fields


@dataclass(frozen=True)
class Linearisation:
    """A wear law about one operating point, factored as ``V = κ D``:

        V(q0 + δq) = κ (D0 + Σ_q ∂D/∂q δq) + O(δq²)

    ``coefficient`` κ (m³/s per unit of ``D``), ``driver`` ``D0``, ``partials`` ``∂D/∂q`` by
    field name of :class:`ContactSample` (:data:`LINEARISED`; a field not named: 0), ``regime``
    the piece of a piecewise law that holds at the point ("" for a smooth law)."""

    coefficient: float
    driver: float
    partials: dict
    regime: str = ""

    @property
    def volume_rate(self):
        """``V0 = κ D0`` (m³/s)."""
        return self.coefficient * self.driver

    def derivative(self, field):
        """``∂V/∂q = κ ∂D/∂q`` for the field ``q`` of :class:`ContactSample` (m³/s per its unit)."""
        if field not in LINEARISED:
            raise ScenarioError(f"field must be one of {LINEARISED}, not {field!r}")
        return self.coefficient * self.partials.get(field, 0.0)


def _one_instant(point):
    """``point``'s fields as floats: a linearisation is about one instant."""
    values = {f: np.asarray(getattr(point, f), float) for f in LINEARISED}
    if any(v.size != 1 or not np.isfinite(v).all() for v in values.values()):
        raise ScenarioError("the operating point must be one instant with finite fields")
    return {f: float(v.reshape(())) for f, v in values.items()}


class WearLaw(Registered, ABC):
    """A wear law; subclasses register with ``class X(WearLaw, name="x")``."""

    registry: dict = {}

    @abstractmethod
    def volume_rate_of(self, contact: ContactSample):
        """m³/s removed at each instant of ``contact``."""

    @property
    def beta(self):
        """Volume per frictional energy (m³/J) of a law proportional to the frictional power, else ``None``."""
        return None

    def linearisation(self, point: ContactSample):
        """The :class:`Linearisation` about ``point`` (a :class:`ContactSample` of one instant),
        or ``None``: the law has none, and the linear strategies refuse it."""
        return None

    def driver_of(self, contact: ContactSample):
        """The driver ``D`` at each instant of ``contact``, ``volume_rate_of = κ D`` with ``κ`` the
        :class:`Linearisation`'s coefficient; for a law with a linearisation."""
        raise ScenarioError(f"wear.law: {self.name!r} has no linearisation, so no driver")

STEEL_DENSITY = 7850.0  # kg/m³


def _positive(name, value):
    if not (np.isfinite(value) and value > 0):
        raise ScenarioError(f"{name} must be finite and > 0, got {value}")


@dataclass(frozen=True)
class EnergyLaw(WearLaw, name="energy"):
    """Removed mass ``k_e π`` per second: ``specific_wear`` k_e in kg/J, ``density`` in kg/m³."""

    specific_wear: float = 5.3e-9
    density: float = STEEL_DENSITY

    def __post_init__(self):
        _positive("specific_wear", self.specific_wear)
        _positive("density", self.density)

    @property
    def beta(self):
        """Volume per frictional energy ``β = k_e / ρ`` (m³/J)."""
        return self.specific_wear / self.density

    def volume_rate(self, power, **_):
        """m³/s for frictional power ``power`` (W)."""
        return self.beta * np.asarray(power, float)

    def volume_rate_of(self, contact):
        return self.volume_rate(contact.frictional_power)

    def driver_of(self, contact):
        """The frictional power (W): ``V = β π``."""
        return np.asarray(contact.frictional_power, float)

    def linearisation(self, point):
        """``κ = β``, ``D = π``: ``∂D/∂π = 1``, linear everywhere."""
        return Linearisation(self.beta, _one_instant(point)["frictional_power"], {"frictional_power": 1.0})


@dataclass(frozen=True)
class Archard(WearLaw, name="archard"):
    """``V = k N s / H``: ``coefficient`` k (1), ``hardness`` H (Pa); ``s`` the sliding distance."""

    coefficient: float = 1e-4
    hardness: float = 3e9

    def __post_init__(self):
        _positive("coefficient", self.coefficient)
        _positive("hardness", self.hardness)

    def volume_rate(self, normal_force, sliding_speed, **_):
        """m³/s for the normal force (N) and the sliding speed ``|creepage| v`` (m/s)."""
        return self.coefficient * np.asarray(normal_force, float) * np.abs(sliding_speed) / self.hardness

    def volume_rate_of(self, contact):
        return self.volume_rate(np.maximum(contact.normal_force, 0.0), contact.sliding_speed)

    def driver_of(self, contact):
        """``N⁺ |s|`` (W: normal force times sliding speed), ``κ = k / H``."""
        return np.maximum(np.asarray(contact.normal_force, float), 0.0) * np.abs(contact.sliding_speed)

    def linearisation(self, point):
        """``κ = k / H``, ``D = N |s|``: ``∂D/∂N = |s0|``, ``∂D/∂s = sign(s0) N0``. Refused where
        the law has a kink: without load (``N0 <= 0``) or without sliding (``s0 = 0``, no creepage)."""
        q = _one_instant(point)
        n, s = q["normal_force"], q["sliding_speed"]
        if not n > 0:
            raise ScenarioError(f"wear.law: Archard's N⁺ has a kink at contact loss; the operating point carries "
                                f"N = {n:g} N")
        if s == 0:
            raise ScenarioError("wear.law: Archard's |s| has a kink at zero sliding, and the operating point does not "
                                "slide (no creepage: no traction)")
        return Linearisation(self.coefficient / self.hardness, n * abs(s),
                             {"normal_force": abs(s), "sliding_speed": float(np.sign(s)) * n})


@dataclass(frozen=True)
class USFD(WearLaw, name="usfd"):
    """Wear rate ``K`` (µg per metre rolled per mm² of contact) from ``Tγ/A`` (N/mm²).

    ``K = 5.3 Tγ/A`` below 10.4, ``55.0`` up to 77.2, ``61.9 Tγ/A - 4778.7`` above. As printed
    the law steps down twice: by 0.12 at 10.4 (5.3 × 10.4 = 55.12) and by 55 at 77.2, where the
    severe branch starts at -0.02. ``convention="continuous"`` (the default) makes ``K``
    continuous and never falling as ``Tγ/A`` grows: the mild branch meets the plateau where
    ``5.3 Tγ/A = 55`` (10.38 N/mm²), and the plateau holds until the severe branch rises past it
    (78.09 N/mm²). ``"as_printed"`` keeps the published steps (the severe branch clipped at 0).
    """

    convention: str = "continuous"
    density: float = STEEL_DENSITY
    mild_slope = 5.3
    mild_limit = 10.4
    plateau = 55.0
    severe_limit = 77.2
    severe_slope = 61.9
    severe_offset = 4778.7

    def __post_init__(self):
        if self.convention not in ("continuous", "as_printed"):
            raise ScenarioError(f"USFD convention must be 'continuous' or 'as_printed', not {self.convention!r}")
        _positive("density", self.density)

    def rate(self, t_gamma_over_area):
        """``K`` in µg/(m mm²) for ``Tγ/A`` in N/mm²."""
        x = np.asarray(t_gamma_over_area, float)
        severe = self.severe_slope * x - self.severe_offset
        mild = self.mild_slope * x
        if self.convention == "continuous":
            severe = np.maximum(severe, self.plateau)
            mild = np.minimum(mild, self.plateau)
        return np.where(x < self.mild_limit, mild,
                        np.where(x <= self.severe_limit, self.plateau, np.maximum(severe, 0.0)))

    def volume_rate(self, power, speed, patch_area, **_):
        """m³/s for frictional power (W), rolling speed (m/s) and contact area (m²)."""
        power, speed, area = (np.asarray(v, float) for v in (power, speed, patch_area))
        t_gamma = power / speed  # N
        area_mm2 = area / MM2
        mass_per_metre = self.rate(t_gamma / area_mm2) * area_mm2 * UG  # kg/m
        return mass_per_metre * speed / self.density

    def _inside(self, contact, of):
        """``of(power, speed, area)`` where the patch has an area, 0 elsewhere."""
        area = np.asarray(contact.patch_area, float)
        inside = area > 0
        rate = np.zeros(np.broadcast(area, contact.frictional_power).shape)
        power, speed = (np.broadcast_to(v, rate.shape) for v in (contact.frictional_power, contact.speed))
        rate[inside] = of(power[inside], speed[inside], area[inside])
        return rate

    def volume_rate_of(self, contact):
        return self._inside(contact, self.volume_rate)

    def driver_of(self, contact):
        """``K(Tγ/A) A v`` in µg/s (``A`` in mm²), ``κ = 1 µg / ρ``."""
        return self._inside(contact, lambda power, speed, area: self.rate(power / speed / (area / MM2)) * (area / MM2)
                            * speed)

    def pieces(self):
        """The affine pieces ``K = m x + q`` of the rate over ``x = Tγ/A`` (N/mm²) in order:
        ``(name, upper end of x, m in µg/(m N), q in µg/(m mm²))``; a kink or step at each end."""
        severe = ("severe", np.inf, self.severe_slope, -self.severe_offset)
        if self.convention == "continuous":
            return (("mild", self.plateau / self.mild_slope, self.mild_slope, 0.0),
                    ("plateau", (self.plateau + self.severe_offset) / self.severe_slope, 0.0, self.plateau), severe)
        return (("mild", self.mild_limit, self.mild_slope, 0.0), ("plateau", self.severe_limit, 0.0, self.plateau),
                ("clipped", self.severe_offset / self.severe_slope, 0.0, 0.0), severe)

    def linearisation(self, point):
        """``κ = 1 µg / ρ``, ``D = K(x) A v = m π + q A v`` on the piece ``K = m x + q`` that holds
        at ``x = Tγ/A = π / (v A)`` (``regime``): ``∂D/∂π = m``, ``∂D/∂A = q v``, ``∂D/∂v = q A``
        (``A`` in mm²). Mild: proportional to the frictional power (``m = 5.3``), as the energy
        law; plateau: to the area and speed alone. Refused on a kink between pieces and
        without contact (``A <= 0``)."""
        p = _one_instant(point)
        power, speed, area = p["frictional_power"], p["speed"], p["patch_area"] / MM2
        if not (area > 0 and speed > 0):
            raise ScenarioError(f"wear.law: USFD's Tγ/A needs contact and rolling; the operating point has "
                                f"A = {area:g} mm², v = {speed:g} m/s")
        x = power / speed / area
        lower = -np.inf
        for name, upper, m, q in self.pieces():
            if x == upper:
                raise ScenarioError(f"wear.law: USFD's rate has a kink at Tγ/A = {x:g} N/mm², where the operating "
                                    "point lies")
            if lower < x < upper:
                return Linearisation(UG / self.density, m * power + q * area * speed,
                                     {"frictional_power": m, "patch_area": q * speed / MM2, "speed": q * area},
                                     regime=name)
            lower = upper
        raise ScenarioError(f"wear.law: Tγ/A = {x:g} N/mm² lies outside USFD's pieces")


class StatefulLaw(WearLaw):
    """A law with an internal state ``z`` per cell of a surface (paper eq. 2): ``rates(t, π, u,
    z)`` gives ``(u', z')`` for the local frictional power density ``π`` (W/m²); a body must carry
    ``z`` (:class:`~railwear.longterm.disk_wheel_state.StatefulDiskWheel`)."""

    stateful = True

    @abstractmethod
    def rates(self, t, power_density, u, z):
        """``(u', z')``: m/s (negative for wear) and the state's rate, per cell."""

    def initial_state(self, n_cells):
        """``z`` of a new surface."""
        return np.zeros(n_cells)

    def advance(self, t, dt, power_density, u, z):
        """One explicit midpoint step of ``(u, z)`` over ``dt`` (s) with ``π`` held."""
        du, dz = self.rates(t, power_density, u, z)
        du2, dz2 = self.rates(t + dt / 2, power_density, u + dt / 2 * du, z + dt / 2 * dz)
        return u + dt * du2, z + dt * dz2

    def volume_rate_of(self, contact):
        raise ScenarioError(f"law {self.name!r} has an internal state: it wears a body that carries it per cell")


@dataclass(frozen=True)
class InternalStateLaw(StatefulLaw, name="internal_state"):
    """Paper eq. 2: ``u' = U(t, π, u, z)``, ``z' = Z(t, π, u, z)`` on the cells of a surface.

    ``U`` and ``Z`` are vectorised callables over arrays of cells; ``π`` is the local frictional
    power density (W/m²), ``u`` the radius deviation (m, negative where worn), ``z`` the internal
    state. ``U`` returns m/s (negative for wear).
    """

    U: Callable
    Z: Callable

    def rates(self, t, power_density, u, z):
        return (np.asarray(self.U(t, power_density, u, z), float),
                np.asarray(self.Z(t, power_density, u, z), float))

    @classmethod
    def energy(cls, law: EnergyLaw):
        """The plain energy law in this form: ``u' = -β π``, no state."""
        return cls(U=lambda t, p, u, z: -law.beta * np.asarray(p), Z=lambda t, p, u, z: np.zeros_like(z))

    @classmethod
    def hardening(cls, law: EnergyLaw, saturation=1.0, power_scale=1e6, time_constant=3600.0):
        """:class:`Hardening` on the energy law ``law``."""
        return Hardening(law.specific_wear, law.density, saturation, power_scale, time_constant)


@dataclass(frozen=True)
class Hardening(StatefulLaw, name="hardening"):
    """Work hardening on the energy law (``specific_wear`` kg/J, ``density`` kg/m³): the surface
    state ``z`` rises towards ``saturation`` as ``z' = (saturation π/(π + power_scale) - z) /
    time_constant`` (π in W/m², the time constant in s) and relaxes without contact; the wear
    coefficient falls to ``β / (1 + z)``: ``u' = -β π / (1 + z)``."""

    specific_wear: float = 5.3e-9
    density: float = STEEL_DENSITY
    saturation: float = 1.0
    power_scale: float = 1e6
    time_constant: float = 3600.0

    def __post_init__(self):
        for name in ("specific_wear", "density", "power_scale", "time_constant"):
            _positive(name, getattr(self, name))
        if not (np.isfinite(self.saturation) and self.saturation >= 0):
            raise ScenarioError(f"saturation must be finite and >= 0, got {self.saturation}")

    def rates(self, t, power_density, u, z):
        p = np.asarray(power_density, float)
        beta = self.specific_wear / self.density
        return -beta * p / (1 + z), (self.saturation * p / (p + self.power_scale) - z) / self.time_constant
