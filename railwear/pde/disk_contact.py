"""The wear rate ``h(u_xx, v)`` of a rigid disk wheel (paper Fig. 5 and section "A phenomenological model").

Derivation (written out in ``docs/evolution.md``):

1. A rigid wheel of radius ``R0`` rolls at speed ``v``; its centre follows the radius under the
   contact point, so the unsprung mass ``m`` is accelerated by ``u_xx (v/R0)²`` and the normal
   force is ``N = W + m (v/R0)² u_xx`` (``W`` the static wheel load).
2. Hertz: the patch semi-axes grow like ``N^(1/3)``, so Kalker's creep stiffness
   ``k(N) = G a b C11`` grows like ``N^(2/3)`` (the shape ``a/b``, and so ``C11``, does not change).
3. A fixed longitudinal traction demand ``F = f W`` needs the creepage
   ``ξ = (3 μ N / k)(1 - (1 - F/(μN))^(1/3))`` (Kalker's slope with the cubic saturation of
   Vermeulen & Johnson, J. Appl. Mech. 31 (1964) 338); far from saturation ``ξ = F/k ∝ N^(-2/3)``.
   Where ``μ N < F`` the wheel slides at the saturation creepage ``3 μ N / k`` under the force
   ``μ N``; where ``N <= 0`` the contact is lost and nothing wears.
4. The frictional energy per metre rolled ``Tγ = F_x ξ`` (the frictional power over the speed)
   removes the mass ``k_e Tγ`` per metre (energy law, paper eq. 2a, with ``k_e`` in kg/J), spread
   over the circumference ``2π R0`` times the wear band; one unit of normed time is
   ``life_distance`` metres.
5. The load is not steady on real track: ``Tγ`` is averaged over a normal scatter of the load with
   standard deviation ``load_scatter · W`` (the paper's randomisation). This smooths the cusp at
   saturation and the kink at contact loss, so that ``h`` is smooth and the PDE solvable.

``h`` rises with ``u_xx`` (smoothing, well-posed) where ``N`` is above the saturation load
``F/μ`` and falls with it (unstable) below: crests of the radius (``u_xx < 0``) unload as the speed
grows, and the speeds where they reach that branch are the regime changes.
"""

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from railwear.errors import ScenarioError
from railwear.pde.forms import BuiltinRate, Pointwise, register_rate

_SCATTER_STEPS_PER_SIGMA = 2000  # resolution of the load-scatter convolution
_LOAD_POINTS = 2049


@register_rate
@dataclass(frozen=True)
class DiskContact(BuiltinRate):
    """Wear rate of the rigid disk wheel; SI units, rate in m per unit of normed life time."""

    wheel_radius: float = 0.46
    unsprung_mass: float = 1000.0
    static_load: float = 80e3
    traction_coefficient: float = 0.05
    friction_coefficient: float = 0.3
    youngs_modulus: float = 210e9
    poisson: float = 0.28
    rail_head_radius: float = 0.3
    load_scatter: float = 0.2
    specific_wear: float = 5.3e-9
    density: float = 7850.0
    life_distance: float = 5e7
    wear_band_width: float | None = None
    name = "disk_contact"

    def __post_init__(self):
        positive = ("wheel_radius", "unsprung_mass", "static_load", "traction_coefficient",
                    "friction_coefficient", "youngs_modulus", "rail_head_radius", "specific_wear",
                    "density", "life_distance")
        for f in positive:
            value = getattr(self, f)
            if not (np.isfinite(value) and value > 0):
                raise ScenarioError(f"disk_contact.{f} must be finite and > 0, got {value}")
        if not 0 <= self.poisson < 0.5:
            raise ScenarioError(f"disk_contact.poisson must lie in [0, 0.5), got {self.poisson}")
        if not 0.01 <= self.load_scatter <= 1:
            raise ScenarioError(
                f"disk_contact.load_scatter must lie in [0.01, 1], got {self.load_scatter}")
        if self.wear_band_width is not None and not self.wear_band_width > 0:
            raise ScenarioError("disk_contact.wear_band_width must be > 0 (m)")

    @cached_property
    def patch(self):
        """Hertz patch at the static load: rolling-direction semi-axis ``a`` and lateral ``b`` (m)."""
        from railwear.contact import hertz_contact

        return hertz_contact(self.static_load, 1 / (2 * self.wheel_radius),
                             1 / (2 * self.rail_head_radius), self.youngs_modulus, self.poisson)

    @cached_property
    def creep_stiffness(self):
        """Kalker's longitudinal creep stiffness ``G a b C11`` at the static load (N)."""
        from railwear.contact import kalker_coefficients

        a, b = float(self.patch.a), float(self.patch.b)
        c11 = float(kalker_coefficients(a / b, self.poisson)[0])
        shear_modulus = self.youngs_modulus / (2 * (1 + self.poisson))
        return shear_modulus * a * b * c11

    @property
    def saturation_load(self):
        """Load below which the traction demand saturates, ``F/μ`` (N)."""
        return self.traction_coefficient * self.static_load / self.friction_coefficient

    def depth_per_energy(self):
        """Radius lost per unit frictional energy per metre rolled, times the life (m per J/m)."""
        band = self.wear_band_width if self.wear_band_width is not None else 2 * float(self.patch.b)
        area = 2 * np.pi * self.wheel_radius * band
        return self.specific_wear * self.life_distance / (self.density * area)

    def frictional_energy(self, normal_force):
        """Frictional energy per metre rolled ``Tγ`` under a steady load (J/m = N): ``F ξ`` with
        ``ξ = ξ_s (1 - (1 - F/(μN))^(1/3))``, ``ξ_s = 3 μN / k(N)`` (the inverse cubic law,
        :func:`~railwear.contact.inverse_cubic`), ``μN ξ_s`` where the wheel slides."""
        from railwear.contact.saturation import inverse_cubic

        N = np.asarray(normal_force, float)
        F = self.traction_coefficient * self.static_load
        mu = self.friction_coefficient
        Np = np.maximum(N, 1e-300)
        k = self.creep_stiffness * (Np / self.static_load) ** (2 / 3)
        saturation_creepage = 3 * mu * Np / k
        sliding = N * mu <= F
        with np.errstate(over="ignore"):  # F / (μ N) past the float range where N is ~0: q = 1
            _, fraction = inverse_cubic(F, mu * Np)
        adhesion = F * saturation_creepage * fraction
        energy = np.where(sliding, mu * Np * saturation_creepage, adhesion)
        return np.where(N > 0, energy, 0.0)

    @cached_property
    def _scatter_table(self):
        """Mean ``Tγ`` and its slope over the load scatter, on a grid of loads (N, J/m, m).

        A convolution with the normal density (and its derivative) on a fine grid of loads that
        has the contact-loss and saturation loads as nodes, by FFT.
        """
        from scipy.signal import fftconvolve

        W, sigma = self.static_load, self.load_scatter * self.static_load
        load = np.linspace(-6 * sigma, W * 3 + 6 * sigma, _LOAD_POINTS)
        step = sigma / _SCATTER_STEPS_PER_SIGMA
        step = self.saturation_load / max(1, round(self.saturation_load / step))
        fine = step * np.arange(round((load[0] - 8 * sigma) / step), round((load[-1] + 8 * sigma) / step) + 1)
        z = step * np.arange(-round(8 * sigma / step), round(8 * sigma / step) + 1) / sigma
        density = np.exp(-0.5 * z**2) / (sigma * np.sqrt(2 * np.pi)) * step
        f = self.frictional_energy(fine)
        mean = fftconvolve(f, density, mode="same")
        slope = fftconvolve(f, -density * z / sigma, mode="same")
        return load, np.interp(load, fine, mean), np.interp(load, fine, slope)

    def mean_frictional_energy(self, normal_force):
        """``Tγ`` averaged over the load scatter (J/m), cubic Hermite in the load."""
        load, mean, slope = self._scatter_table
        g = Pointwise(np.zeros(1), load[0], load[1] - load[0], mean, slope)
        return g(normal_force)

    def normal_force(self, s, speed):
        """``N = W + m (v/R0)² u_xx`` (N) for curvature ``s`` (m/rad²) at speed ``v`` (m/s)."""
        return self.static_load + self.unsprung_mass * (speed / self.wheel_radius) ** 2 * s

    def at_speed(self, speed):
        load, mean, slope = self._scatter_table
        c = -self.depth_per_energy()
        stiffness = self.unsprung_mass * (speed / self.wheel_radius) ** 2  # N per (m/rad²)
        if stiffness == 0:
            return Pointwise(np.array([c * float(self.mean_frictional_energy(self.static_load))]))
        s_lo = (load[0] - self.static_load) / stiffness
        ds = (load[1] - load[0]) / stiffness
        return Pointwise(np.zeros(1), s_lo, ds, c * mean, c * slope * stiffness)

    def crest_curvature(self, speed):
        """Curvature (m/rad², < 0) at which a crest unloads to the saturation load ``F/μ``."""
        stiffness = self.unsprung_mass * (np.asarray(speed, float) / self.wheel_radius) ** 2
        with np.errstate(divide="ignore"):
            return (self.saturation_load - self.static_load) / stiffness
