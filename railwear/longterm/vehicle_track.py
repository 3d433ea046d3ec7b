"""The Fourier technique on a wheel over the discretely supported track (issue 11, part 3).

The wheel is the disk wheel of :class:`~railwear.dynamics.DiskWheelModel` on a rigid rail
(unsprung mass, primary suspension to a sprung mass or a rigid frame, Hertz contact, rotation
with Kalker creep under a traction torque, frictional power ``Fx ξ V``); only the rail changes:
the disk wheel's rail mass on a pad becomes the rail of :mod:`railwear.track`, through its exact
receptance ``α(ω, d)`` at the wheel's offset ``d`` past a sleeper.

Linearisation (deviations from steady rolling, ``e^{iωt}``): the compiled disk-wheel kernel
linearised on a rigid rail, ``x' = A x + B ū + a_r z_r``, ``y = C x + D ū + c_r z_r`` with
``y = (N, ξ, Fx, π)``, where ``a_r, c_r`` are the columns of the rail displacement ``z_r``
(upward), which enters only the approach ``δ = δ0 + z_r - z_w + ū``. Per unit ``ū``:

    G_u = C (iω - A)^-1 B + D,   G_r = C (iω - A)^-1 a_r + c_r
    z_r = -α N  (the rail goes down under the wheel's load)  =>  z_r = -α G_u,N / (1 + α G_r,N)
    H(ω, d) = G_u + G_r z_r

For the normal force this is ``1 / (α_w + 1/k_c + α)``: wheel, contact and rail receptances in
series. Over the bay the transfer is averaged at ``n`` equally spaced offsets ``d_j = j L / n``
(the periodic trapezoidal rule, sleeper and, for even ``n``, midspan among them; ``d`` and
``L - d`` give the same point receptance, so about half are evaluated): the wheel is frozen at
each offset, which holds while the receptance varies little over the bay (within a few per cent
below 500 Hz) and not near the pinned-pinned frequency.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
import xarray as xr

from railwear.contact import contact_constants, hertz_contact
from railwear.contact.transient import TransientContact
from railwear.dynamics import DiskWheelModel
from railwear.errors import ScenarioError
from railwear.longterm.fourier import Fourier, Harmonics, contact_filter, law_terms, stability_map
from railwear.track import Support, Track, load_offset, rail, receptance, support_set
from railwear.track.between import localised_modes
from railwear.units import KM
from railwear.track.longitudinal import longitudinal_receptance

__all__ = ["VehicleCase", "VehicleTrackModel", "vehicle_track_fourier", "growth_map", "growth_parts", "METRO",
           "HIGH_SPEED", "HIGH_SPEED_TRACK", "WheelsOnRail", "WheelsFourier", "growing_combinations", "own_rates",
           "wheels_growth_map", "bay_offsets", "p2_frequency", "coupled_resonance"]

GRAVITY = 9.81  # m/s²
_RAIL_STATE = 6  # z_r in the disk wheel's state vector
TANGENTIAL = ("rail", "wheel")
PHASES = ("locked", "drifting")  # WheelsFourier.phases
_WHEEL_STATES = slice(0, 6)  # phi, Omega, z_w, z_w', z_s, z_s'


def bay_offsets(track: Track, positions):
    """Offsets ``d`` (m past a sleeper) and weights of the average over the bay.

    ``positions``: an integer ``n >= 1`` (the mean over ``d_j = j L / n``, mirror images folded
    together), or one position (``"midspan"``, ``"sleeper"`` or metres) with weight 1. A
    continuous track has one offset."""
    if isinstance(positions, (str, float)):
        return [positions], np.ones(1)
    if not isinstance(positions, (int, np.integer)) or isinstance(positions, bool) or positions < 1:
        raise ScenarioError(f"positions: must be an integer >= 1, 'midspan', 'sleeper' or metres, got {positions!r}")
    if not track.discrete:
        return ["sleeper"], np.ones(1)
    n = int(positions)
    j = np.arange(n // 2 + 1)
    weights = np.where((j == 0) | (2 * j == n), 1.0, 2.0)
    return [float(x) for x in j * track.sleeper_spacing / n], weights / n


@dataclass(frozen=True, eq=False)
class VehicleTrackModel:
    """A disk wheel (``wheel``, on a rigid rail: ``rail_mass=None``) on the rail of ``track``.

    Has what :meth:`Fourier.disk_wheel` reads of a :class:`DiskWheelModel` (``speed``,
    ``radius``, ``traction_torque``, ``static_load``, ``patch_half_length``,
    ``steady_creepage()``, ``transfer``, ``contact_force_transfer``), so that constructor and
    :func:`~railwear.longterm.fourier.stability_map` take it unchanged. ``positions``: see
    :func:`bay_offsets`. ``wheel_modes``: flexible modes of the wheelset as modal data
    ``(frequency_hz, modal_mass_kg, damping_ratio)``, the modal mass at the contact point; each
    adds the compliance ``1 / (m_k (ω_k² - ω² + 2iζ_k ω_k ω))`` in series with the rail's.
    ``contact``: ``"steady"`` (Kalker's steady creep, the perturbations spread evenly over the
    patch: today's model) or a :class:`~railwear.contact.transient.TransientContact` (the
    non-steady contact, :meth:`transient_transfer`). ``tangential``: the longitudinal compliances
    in series with the contact, any of ``"rail"`` (the rail head's,
    :func:`~railwear.track.longitudinal.longitudinal_receptance`) and ``"wheel"`` (the wheel's
    centre as a free mass, ``-1 / (m ω²)``); empty: both rigid (today's model)."""

    wheel: DiskWheelModel
    track: Track
    positions: int | str | float = 8
    wheel_modes: tuple = ()
    contact: object = "steady"
    tangential: tuple = ()

    def __post_init__(self):
        if not isinstance(self.wheel, DiskWheelModel):
            raise ScenarioError("wheel: must be a DiskWheelModel")
        if not isinstance(self.track, Track):
            raise ScenarioError("track: must be a railwear.track.Track")
        if self.wheel.rail_mass is not None:
            raise ScenarioError("wheel.rail_mass: must be None, the track replaces the rail mass on a pad")
        modes = np.asarray(self.wheel_modes, float).reshape(-1, 3)
        if not (np.all(np.isfinite(modes)) and np.all(modes[:, :2] > 0) and np.all(modes[:, 2] >= 0)):
            raise ScenarioError("wheel_modes: each mode is (frequency_hz > 0, modal_mass_kg > 0, damping_ratio >= 0)")
        object.__setattr__(self, "_modes", modes)
        if not (self.contact == "steady" if isinstance(self.contact, str) else isinstance(self.contact, TransientContact)):
            raise ScenarioError(f"contact: must be 'steady' or a TransientContact, got {self.contact!r}")
        tangential = tuple(self.tangential)
        if not set(tangential) <= set(TANGENTIAL) or len(set(tangential)) != len(tangential):
            raise ScenarioError(f"tangential: any of {', '.join(TANGENTIAL)}, each once, got {self.tangential!r}")
        object.__setattr__(self, "tangential", tangential)
        offsets, weights = bay_offsets(self.track, self.positions)
        object.__setattr__(self, "_offsets", offsets)
        object.__setattr__(self, "_weights", weights)
        object.__setattr__(self, "_linear", self.wheel.linearisation())
        object.__setattr__(self, "_cache", {})

    speed = property(lambda self: self.wheel.speed)
    radius = property(lambda self: self.wheel.radius)
    traction_torque = property(lambda self: self.wheel.traction_torque)
    static_load = property(lambda self: self.wheel.static_load)
    patch_half_length = property(lambda self: self.wheel.patch_half_length)
    LINEAR_OUTPUTS = DiskWheelModel.LINEAR_OUTPUTS

    @property
    def filters_contact(self) -> bool:
        """True when :meth:`transfer` carries the contact filter itself (the transient contact):
        :meth:`Fourier.disk_wheel` then puts no ``F_n²`` on it."""
        return not isinstance(self.contact, str)

    def steady_creepage(self) -> float:
        """The wheel's steady creepage under its traction torque (the track carries no traction)."""
        return self.wheel.steady_creepage()

    def rail_receptance(self, angular_frequency) -> np.ndarray:
        """``α(ω, d_j)`` [m/N] at the bay offsets, ``(offsets, len(ω))``; kept for the last ``ω``
        given (see :meth:`remember`)."""
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        key = omega.tobytes()
        if key not in self._cache:
            f = omega / (2 * np.pi)
            self._cache.clear()
            self._cache[key] = np.array([receptance(self.track, f, d) for d in self._offsets])
        return self._cache[key]

    def wheel_mode_receptance(self, angular_frequency) -> np.ndarray:
        """The flexible wheelset's compliance at the contact [m/N]: ``Σ_k 1 / (m_k (ω_k² - ω² +
        2iζ_k ω_k ω))`` (zero without ``wheel_modes``)."""
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        out = np.zeros(omega.shape, complex)
        for f, mass, zeta in self._modes:
            w = 2 * np.pi * f
            out += 1.0 / (mass * (w**2 - omega**2 + 2j * zeta * w * omega))
        return out

    def tangential_receptance(self, angular_frequency) -> np.ndarray:
        """The longitudinal compliance in series with the contact [m/N] (see ``tangential``)."""
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        out = np.zeros(omega.shape, complex)
        if "rail" in self.tangential:
            out += longitudinal_receptance(self.track.rail, omega)
        if "wheel" in self.tangential:
            out -= 1 / (self.wheel.wheel_mass * omega**2)
        return out

    def remember(self, angular_frequency, alpha):
        """Use ``alpha`` (``(offsets, len(ω))``, m/N) as the rail receptance at these ``ω``
        (rad/s): a map evaluates the track once for all speeds."""
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        self._cache.clear()
        self._cache[omega.tobytes()] = np.asarray(alpha, complex)

    def wheel_terms(self, angular_frequency):
        """``(G_u, G_r)``, ``(len(ω), 4)`` each: the outputs ``(N, ξ, Fx, π)`` per unit ``ū`` and
        per unit upward rail displacement of the wheel on a rigid rail."""
        a, b, c, d = self._linear
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        keep = _WHEEL_STATES
        A = a[keep, keep]
        M = 1j * omega[:, None, None] * np.eye(A.shape[0]) - A
        rhs = np.column_stack([b[keep], a[keep, _RAIL_STATE]]).astype(complex)
        X = np.linalg.solve(M, np.broadcast_to(rhs, (omega.size,) + rhs.shape))
        G = c[None, :, keep] @ X + np.column_stack([d, c[:, _RAIL_STATE]])[None]
        return G[..., 0], G[..., 1]

    def transfer(self, angular_frequency, output="frictional_power") -> np.ndarray:
        """Bay-averaged transfer from ``ū`` to ``output`` (one of ``LINEAR_OUTPUTS``) at
        ``angular_frequency`` [rad/s]: ``Σ_j w_j H(ω, d_j)``, complex (units of the output per m)."""
        if output not in self.LINEAR_OUTPUTS:
            raise ScenarioError(f"output: must be one of {self.LINEAR_OUTPUTS}, got {output!r}")
        if self.filters_contact or self.tangential:
            return self._closed_form(angular_frequency, output)
        return self._steady_transfer(angular_frequency, output)

    def _steady_transfer(self, angular_frequency, output):
        row = self.LINEAR_OUTPUTS.index(output)
        gu, gr = self.wheel_terms(angular_frequency)
        # The wheel's flexible deflection at the contact lowers the approach as the rail's does.
        alpha = self.rail_receptance(angular_frequency) + self.wheel_mode_receptance(angular_frequency)[None, :]
        z = -alpha * gu[:, 0] / (1 + alpha * gr[:, 0])
        out = self._weights @ (gu[:, row] + gr[:, row] * z)
        return out if np.ndim(angular_frequency) else out[0]

    def contact_force_transfer(self, angular_frequency) -> np.ndarray:
        """``N̂ / ū`` [N/m], bay-averaged: ``1 / (α_w + 1/k_c + α)`` at each offset (the vertical
        dynamics, the same under either contact)."""
        return self._steady_transfer(angular_frequency, "normal_force")

    def transient_transfer(self, angular_frequency, output="frictional_power", parts=False):
        """Transfer per unit amplitude ``û`` of the (unfiltered) harmonic under the non-steady
        ``contact``, at ``ω = n Ω`` [rad/s], ``κ = ω a / (Ω R0) = n a / R0``. With the
        :class:`~railwear.contact.transient.TransientContact` factors ``T_u, T_m`` (creep force to
        uniform and to material creepage) and ``W_u, W_m`` (frictional power as worn off the
        material), ``S = sinc κ`` (the normal problem's patch average, as the steady model), and
        from the kernel's linearisation ``A11 = ∂Ω'/∂Ω``, ``c_ξ = ∂ξ/∂Ω``, ``D_ξ = ∂ξ/∂ū``, the
        lever ``l`` and the load's ``Ω'`` per newton ``g``:

            Ω̂ (iω - A11 T_u) = (A11 / c_ξ) D_ξ T_m + S (l + g N̂/ū)
            π̂ = b (W_u c_ξ Ω̂ + W_m D_ξ) + a S² N̂/ū,   F̂ = f (T_u c_ξ Ω̂ + T_m D_ξ) + F_N S N̂/ū

        (``a, b`` of :meth:`power_sensitivities`, ``f = ∂F/∂ξ``, ``F_N = ∂F/∂N``; the load's part
        kept quasi-steady). With every factor 1 and ``S = 1`` this is the steady transfer
        (:meth:`power_load_split`). A ``tangential`` compliance ``α_t`` moves the surfaces apart
        by ``α_t F̂``, a uniform creepage ``-ik α_t F̂`` (``k = ω / V``), so the force and the
        uniform creepage the contact sees become

            F̂ = P [f (T_u c_ξ Ω̂ + T_m D_ξ) + F_N S N̂/ū],   ξ̂_u = c_ξ Ω̂ - ik α_t F̂,   P = 1 / (1 + ik α_t f T_u)

        and ``P`` multiplies every creep-force term of the rotation. Outputs: ``frictional_power``
        and ``normal_force`` (``S² N̂/ū``) as the wear sees them, ``creep_force``; ``creepage`` is
        refused (a law driven by the sliding speed has no deposit rule here). ``parts``: the
        power's ``rolling_radius`` (at fixed wheel speed and load), ``rotation`` and
        ``normal_force`` parts instead."""
        if not self.filters_contact:
            raise ScenarioError("contact: transient_transfer needs a TransientContact")
        return self._closed_form(angular_frequency, output, parts)

    def _closed_form(self, angular_frequency, output="frictional_power", parts=False, load=None):
        """:meth:`transient_transfer`'s equations, under the steady contact every factor 1 and
        ``S = 1`` (its filter ``F_n²`` then stays with :meth:`Fourier.disk_wheel`), where only
        ``creepage`` (``ξ̂_u + D_ξ``, the creepage the contact sees) is an output as well.
        ``load``: ``N̂/ū`` in place of this wheel's own (several wheels: the output is affine in it)."""
        if output == "creepage" and self.filters_contact:
            raise ScenarioError("contact: the transient contact carries the frictional power and the normal force; "
                                "a wear law driven by the sliding speed (archard) needs contact = 'steady'")
        A, B, c, d = self._linear
        out = self.LINEAR_OUTPUTS
        n, xi, fx = out.index("normal_force"), out.index("creepage"), out.index("creep_force")
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        if self.filters_contact:
            kappa = omega * self.patch_half_length / (self.speed * (1 + self.steady_creepage()))
            f = self.contact.factors(kappa)
            filt = contact_filter(kappa, 1.0)
        else:
            f = dict.fromkeys(("force_uniform", "force_material", "wear_uniform", "wear_material"), 1.0)
            filt = 1.0
        load = self._steady_transfer(omega, "normal_force") if load is None else load
        a_p, b_p, d_xi = self.power_sensitivities()
        c_xi, a11 = c[xi, 1], A[1, 1]
        slope, per_n = c[fx, 1] / c_xi, c[fx, 2] / c[n, 2]
        spin = a11 / c_xi  # Ω' per unit creepage
        per_load = A[1, 2] / c[n, 2]
        lever = B[1] - per_load * d[n] - spin * d_xi
        shift = 1j * omega / self.speed * self.tangential_receptance(omega)  # ik α_t
        p = 1 / (1 + shift * slope * f["force_uniform"])
        rotation = (p * spin * d_xi * f["force_material"] + filt * (lever + p * per_load * load)) / (
            1j * omega - p * a11 * f["force_uniform"])
        force = p * (slope * (f["force_uniform"] * c_xi * rotation + f["force_material"] * d_xi) + per_n * filt * load)
        if parts:
            material = p * slope * f["force_material"] * d_xi
            return {"rolling_radius": b_p * (f["wear_material"] * d_xi - f["wear_uniform"] * shift * material),
                    "rotation": b_p * f["wear_uniform"] * c_xi * rotation * p,
                    "normal_force": a_p * filt**2 * load - b_p * f["wear_uniform"] * shift * p * per_n * filt * load}
        uniform = c_xi * rotation - shift * force
        if output == "frictional_power":
            res = b_p * (f["wear_uniform"] * uniform + f["wear_material"] * d_xi) + a_p * filt**2 * load
        elif output == "normal_force":
            res = filt**2 * load
        elif output == "creepage":
            res = uniform + d_xi
        else:
            res = force
        return res if np.ndim(angular_frequency) else res[0]

    def power_sensitivities(self, terms=None):
        """``(a, b, D_ξ)`` of the linearised frictional power ``π̂ = a N̂ + b ξ̂``: ``a = ∂π/∂N``
        [m/s] at fixed creepage (Kalker's ``f11 ∝ N^(2/3)`` and the saturation limit ``μN``),
        ``b = ∂π/∂ξ`` [W] at fixed load (``V (F0 + ξ0 ∂F/∂ξ)``, ``2 V F0`` without saturation), and
        ``D_ξ = ∂ξ/∂ū`` [1/m] at fixed wheel speed (the rolling-radius change, ``Ω0 / V``).
        ``terms``: a wear law's driver ``D̂ = t_π π̂ + t_N N̂ + t_ξ ξ̂``
        (:func:`~railwear.longterm.fourier.law_terms`) in place of ``π̂``: ``a = t_π ∂π/∂N + t_N``,
        ``b = t_π ∂π/∂ξ + t_ξ`` (``None``: the frictional power, ``t_π = 1``)."""
        _, _, c, d = self._linear
        out = self.LINEAR_OUTPUTS
        n, xi, p = out.index("normal_force"), out.index("creepage"), out.index("frictional_power")
        a, b = float(c[p, 2] / c[n, 2]), float(c[p, 1] / c[xi, 1])
        if terms is not None:
            power = terms.get("frictional_power", 0.0)
            a, b = power * a + terms.get("normal_force", 0.0), power * b + terms.get("creepage", 0.0)
        return a, b, float(d[xi])

    def frictional_power_parts(self, angular_frequency, terms=None) -> dict:
        """The bay-averaged frictional-power transfer split by what carries it, ``π̂/ū = a N̂/ū +
        b ξ̂/ū`` with ``ξ̂/ū = D_ξ + R0 Ω̂/(V ū)`` (see :meth:`power_sensitivities`), complex [W/m]:
        ``"rolling_radius"`` ``b D_ξ`` (a higher spot rolls with more creepage at the same wheel
        speed), ``"rotation"`` ``b (ξ̂/ū - D_ξ)`` (the wheel's speed following the creep force),
        ``"normal_force"`` ``a N̂/ū``. They sum to ``transfer(ω, "frictional_power")``; with a
        law's ``terms`` (:meth:`power_sensitivities`) the same split of its driver's transfer."""
        if self.filters_contact or self.tangential:
            if terms is not None and set(terms) - {"frictional_power"}:
                raise ScenarioError("contact: the parts of the transient contact or a tangential compliance are those "
                                    "of the frictional power")
            weight = 1.0 if terms is None else terms["frictional_power"]
            return {k: weight * np.asarray(v, complex) for k, v in
                    self._closed_form(angular_frequency, parts=True).items()}
        a, b, d_xi = self.power_sensitivities(terms)
        creepage = np.asarray(self.transfer(angular_frequency, "creepage"), complex)
        normal = np.asarray(self.transfer(angular_frequency, "normal_force"), complex)
        return {"rolling_radius": b * d_xi * np.ones_like(creepage), "rotation": b * (creepage - d_xi),
                "normal_force": a * normal}

    def power_load_split(self, angular_frequency, terms=None):
        """``(P, Q)`` with ``π̂/ū = P + Q N̂/ū`` at every offset, complex, ``(len(ω),)`` each: the
        wheel's rotation (``J Ω' = T - (R0 + ū) Fx``) solved for the creepage given the load, so
        that ``P`` and ``Q`` hold only the rotation and the contact, not the vertical dynamics or
        the rail (the same at every offset). ``terms``: a law's driver for ``π``
        (:meth:`power_sensitivities`). Rigid tangentially only."""
        if self.tangential:
            raise ScenarioError("tangential: the load split and the passive bound are for the rigid tangential model")
        A, B, c, d = self._linear
        out = self.LINEAR_OUTPUTS
        n, xi = out.index("normal_force"), out.index("creepage")
        a, b, d_xi = self.power_sensitivities(terms)
        s = 1j * np.atleast_1d(np.asarray(angular_frequency, float))
        per_load = A[1, 2] / c[n, 2]  # Ω' per newton of load, through the approach
        per_u = B[1] - per_load * d[n]  # Ω' per metre of ū at fixed load: lever and rolling radius
        rotation = b * c[xi, 1] / (s - A[1, 1])
        return b * d_xi + rotation * per_u, a + rotation * per_load

    def passive_bound(self, angular_frequency, terms=None) -> np.ndarray:
        """The least ``Re(π̂/ū)`` [W/m] (bay-averaged) that any passive vertical addition on the
        wheel's side could give: a wheelset mode of any frequency, modal mass and damping ``>= 0``,
        an axle-box or bogie mode through the primary suspension. At each offset ``N̂/ū = 1/Z``
        with ``Z = α_w + Σ α_k + 1/k_c + α``, and passive terms have ``Im <= 0``, so ``Im Z <=
        Im α = -y``: ``N̂/ū`` lies in the disk of centre ``i/(2y)`` and radius ``1/(2y)``, where
        ``Re(Q N̂/ū) >= -(Im Q + |Q|)/(2y)``. The rail's ``Im α`` (its damping and the bending
        waves it radiates) alone bounds how far a resonance can drive the load against the
        smoothing. Attained by an undamped mode where the wheel has no damping of its own.
        ``terms``: the same for a law's driver (:meth:`power_sensitivities`)."""
        P, Q = self.power_load_split(angular_frequency, terms)
        y = -np.imag(self.rail_receptance(angular_frequency))
        if np.any(y <= 0):
            raise ScenarioError("track: the rail receptance must dissipate (Im α < 0) for the bound")
        out = np.real(P) - self._weights @ ((np.imag(Q) + np.abs(Q))[None, :] / (2 * y))
        return out if np.ndim(angular_frequency) else out[0]


def p2_frequency(model: VehicleTrackModel) -> float:
    """The P2 resonance [Hz]: :func:`coupled_resonance` over 20-150 Hz."""
    return coupled_resonance(model, 20.0, 150.0, 2601)


def coupled_resonance(model: VehicleTrackModel, low, high, points=4001) -> float:
    """The resonance [Hz] of wheel, contact and track between ``low`` and ``high`` Hz: the peak of
    the bay-averaged ``|N/ū|`` there (the P2 resonance over 20-150 Hz)."""
    f = np.linspace(low, high, points)
    return float(f[np.argmax(np.abs(model.contact_force_transfer(2 * np.pi * f)))])


def vehicle_track_fourier(wheel, track, speed, law, band_width, positions=8, driver="law",
                          wheel_modes=(), contact="steady", tangential=()) -> Fourier:
    """:class:`Fourier` rates of ``wheel`` (a rigid-rail :class:`DiskWheelModel`, with
    ``wheel_modes``) on ``track`` at ``speed`` (m/s), as :meth:`Fourier.disk_wheel` gives them for
    the disk wheel; ``contact`` and ``tangential`` as :class:`VehicleTrackModel` takes them."""
    model = VehicleTrackModel(dataclasses.replace(wheel, speed=float(speed)), track, positions, wheel_modes, contact,
                              tangential)
    return Fourier.disk_wheel(model, law, band_width, driver)


def growth_parts(wheel, track, speed, law, band_width, orders, positions=8, wheel_modes=(), contact="steady",
                 tangential=()) -> dict:
    """Growth rates ``Re λ_n`` [1/s] of ``wheel`` on ``track`` at ``speed`` (m/s) under the wear
    law ``law`` (with a linearisation), split as :meth:`VehicleTrackModel.frictional_power_parts`
    splits the transfer of the law's driver: ``"rolling_radius"``, ``"rotation"``,
    ``"normal_force"`` (each ``-c Re H_part F_n²``, summing to ``"total"``, which is
    :meth:`Fourier.rates`), with ``"contact_filter"``
    ``F_n²``, ``"passive_bound"`` (the largest rate any passive vertical wheel-side mode could give,
    from :meth:`VehicleTrackModel.passive_bound`), ``"frequency"`` ``n Ω`` [Hz] and ``"order"``.
    Under a transient ``contact`` the parts carry their own filters (``"contact_filter"`` is 1)
    and the passive bound is not given (NaN), nor with a ``tangential`` compliance."""
    model = VehicleTrackModel(dataclasses.replace(wheel, speed=float(speed)), track, positions, wheel_modes, contact,
                              tangential)
    fourier = Fourier.disk_wheel(model, law, band_width)
    _, terms = law_terms(model, law, band_width)
    n = np.atleast_1d(np.asarray(orders, float))
    if np.any(n < 1):
        raise ScenarioError("orders must be >= 1")
    omega = n * fourier.wheel_speed
    filt = np.ones_like(n) if model.filters_contact else contact_filter(n, fourier.half_angle) ** 2
    scale = -fourier.depth_per_driver * filt
    out = {name: scale * np.real(part) for name, part in model.frictional_power_parts(omega, terms).items()}
    out["total"] = fourier.rates(n).real
    out["contact_filter"] = filt
    out["passive_bound"] = (np.full_like(n, np.nan) if model.filters_contact or model.tangential
                            else scale * model.passive_bound(omega, terms))
    out["frequency"] = omega / (2 * np.pi)
    out["order"] = n
    return out


def growth_map(wheel, track, speeds, orders, law, band_width, positions=8, driver="law",
               wheel_modes=(), contact="steady", tangential=()):
    """:func:`stability_map` (growth per km over speed × order) of ``wheel`` on ``track``, with the
    rail receptance evaluated once per bay offset for every speed's frequencies ``n Ω``."""
    speeds = np.atleast_1d(np.asarray(speeds, float))
    n = np.asarray(np.atleast_1d(orders), float)
    models = {v: VehicleTrackModel(dataclasses.replace(wheel, speed=float(v)), track, positions, wheel_modes, contact,
                                   tangential) for v in speeds}
    omegas = [n * (v * (1 + m.steady_creepage()) / m.radius) for v, m in models.items()]
    first = next(iter(models.values()))
    alpha = first.rail_receptance(np.concatenate(omegas))
    for (m, w), part in zip(zip(models.values(), omegas), np.split(alpha, len(omegas), axis=1)):
        m.remember(w, part)
    return stability_map(models.__getitem__, speeds, orders, law, band_width, driver)


@dataclass(frozen=True)
class VehicleCase:
    """A named wheel on a named track, SI units, with the sources of its numbers.

    Per wheel: ``static_load`` [N], ``unsprung_mass`` [kg] (half the wheelset), ``wheel_inertia``
    [kg m²] (half the wheelset's polar inertia), ``sprung_mass`` [kg] (the bogie frame's share;
    ``None``: rigid frame), ``primary_stiffness`` [N/m], ``primary_damping`` [N s/m]. Contact:
    ``rail_head_radius`` [m] (the wheel tread taken flat across), ``traction_coefficient`` the
    traction demand ``T / (W R0)``, steel ``youngs_modulus`` [Pa] and ``poisson``; ``wheel_modes``
    the wheelset's flexible modes (see :class:`VehicleTrackModel`)."""

    name: str
    diameter: float
    static_load: float
    unsprung_mass: float
    wheel_inertia: float
    sprung_mass: float | None
    primary_stiffness: float
    primary_damping: float
    track: Track
    traction_coefficient: float
    band_width: float
    rail_head_radius: float = 0.3
    friction_coefficient: float = 0.4
    youngs_modulus: float = 210e9
    poisson: float = 0.28
    wheel_modes: tuple = ()
    sources: str = ""

    def wheel(self, speed) -> DiskWheelModel:
        """The rigid-rail disk wheel of this case at ``speed`` (m/s), Hertz and Kalker constants
        from :func:`railwear.contact.contact_constants`."""
        radius = self.diameter / 2
        constants = contact_constants(self.static_load, 1 / (2 * radius), 1 / (2 * self.rail_head_radius),
                                      self.youngs_modulus, self.poisson)
        return DiskWheelModel(
            speed=float(speed), radius=radius, wheel_mass=self.unsprung_mass, wheel_inertia=self.wheel_inertia,
            static_load=self.static_load, hertz_constant=constants["hertz_constant"],
            primary_stiffness=self.primary_stiffness, primary_damping=self.primary_damping, f11=constants["f11"],
            sprung_mass=self.sprung_mass, friction_coefficient=self.friction_coefficient,
            traction_torque=self.traction_coefficient * self.static_load * radius,
            patch_half_length=constants["patch_half_length"])

    def transient_contact(self, theory="halfspace") -> TransientContact:
        """The non-steady contact of this case's Hertz patch (its ``a / b``) under ``theory``."""
        patch = hertz_contact(self.static_load, 1 / self.diameter, 1 / (2 * self.rail_head_radius),
                              self.youngs_modulus, self.poisson)
        return TransientContact(aspect=round(float(patch.a / patch.b), 4), theory=theory, poisson=self.poisson)

    def _contact(self, contact):
        """``"steady"``, a :class:`TransientContact`, or ``"transient"`` / ``"simplified"`` for
        :meth:`transient_contact` of this case (half-space or simplified theory)."""
        if isinstance(contact, str) and contact in ("transient", "simplified"):
            return self.transient_contact("halfspace" if contact == "transient" else "simplified")
        return contact

    def fourier(self, speed, law, positions=8, driver="law", contact="steady", tangential=()) -> Fourier:
        """:func:`vehicle_track_fourier` of this case at ``speed`` (m/s); ``contact`` see :meth:`_contact`."""
        return vehicle_track_fourier(self.wheel(speed), self.track, speed, law, self.band_width, positions, driver,
                                     self.wheel_modes, self._contact(contact), tangential)

    def growth_parts(self, speed, orders, law, positions=8, contact="steady", tangential=()) -> dict:
        """:func:`growth_parts` of this case at ``speed`` (m/s)."""
        return growth_parts(self.wheel(speed), self.track, speed, law, self.band_width, orders, positions,
                            self.wheel_modes, self._contact(contact), tangential)

    def growth_map(self, speeds, orders, law, positions=8, driver="law", contact="steady", tangential=()):
        """:func:`growth_map` of this case over ``speeds`` (m/s) and ``orders``."""
        return growth_map(self.wheel(speeds[0]), self.track, speeds, orders, law, self.band_width, positions, driver,
                          self.wheel_modes, self._contact(contact), tangential)


# Metro motor car, 14 t axle load, on ballasted track (sources in docs/vehicle_track.md).
METRO_TRACK = "zhai-2004-no-subgrade"  # the support set of railwear/track/data/supports.toml
METRO = VehicleCase(
    name="metro",
    diameter=0.84,
    static_load=(43.08e3 + 2 * 6.5e3) / 4 / 2 * GRAVITY,  # overcrowded motor car body + 2 bogies, per wheel
    unsprung_mass=1539.0 / 2,
    wheel_inertia=60.0,  # assumption: half a motored wheelset's polar inertia
    sprung_mass=3420.0 / 4,  # motor bogie frame per wheel
    primary_stiffness=1.7e6,  # per axle box
    primary_damping=10e3,  # assumption: rubber primary, no vertical damper
    track=Track(rail("60E1", loss_factor=0.02), support_set(METRO_TRACK).support,
                sleeper_spacing=support_set(METRO_TRACK).sleeper_spacing),
    traction_coefficient=0.05,  # assumption: a typical mean traction demand T / (W R0)
    band_width=0.025,  # assumption: the lateral band the wear spreads over on straight track
    sources="vehicle: Math. Probl. Eng. 2020, 1584624, Table 6; track: Zhai, Wang & Lin, JSV 270 (2004) 673",
)



# High-speed trailer wheel braking by its discs through the contact, on slab track (sources in
# docs/vehicle_track.md, "The high-speed built-in"). A trailer wheel because its braking is the
# one the field singles out (avoiding disc braking at high speed suppresses polygons, Shock Vib.
# 2020, 2587152) and because it carries no traction: in cruise only its own rolling resistance.
HIGH_SPEED_TRACK = "crts-slab-2019"  # the slab set of railwear/track/data/supports.toml (Shock Vib. 2019, 2015465)
HIGH_SPEED_BRAKING = 0.92  # m/s²: CRH380A stops from 300 km/h within about 3760 m (People's Daily, 30 May 2011)
ROTATING_ALLOWANCE = 0.08  # assumption, as railwear.longterm.duty.line_cycle takes it
HIGH_SPEED = VehicleCase(
    name="high-speed",
    diameter=0.92,  # the survey's worst polygons, orders 16-29, are on 0.92 m wheels (doi 10.3969/j.issn.0258-2724.20210777)
    static_load=16e3 / 2 * GRAVITY,  # assumption: 16 t axle load, under the China Standardized EMU's 17 t limit
    unsprung_mass=1800.0 / 2,  # ICE3/AVE S103 wheelset 1800 kg (Goicolea 2014)
    wheel_inertia=100.0,  # assumption: half a trailer wheelset's polar inertia (wheels, axle, brake discs)
    sprung_mass=650.0,  # assumption: a quarter of a 2.6 t bogie frame
    primary_stiffness=1.2e6,  # per side (Goicolea 2014)
    primary_damping=10e3,  # per side (Goicolea 2014)
    track=Track(rail("60E1", loss_factor=0.02), support_set(HIGH_SPEED_TRACK).support,
                sleeper_spacing=support_set(HIGH_SPEED_TRACK).sleeper_spacing),
    traction_coefficient=-(1 + ROTATING_ALLOWANCE) * HIGH_SPEED_BRAKING / GRAVITY,  # disc braking, -0.101
    band_width=0.025,  # assumption, as METRO
    # 590 Hz: the middle of the bogie vibration measured at 565-616 Hz (Shock Vib. 2018, 6759105);
    # modal mass at the contact 500 kg and damping ratio 1 %: assumptions (no modal analysis found)
    wheel_modes=((590.0, 500.0, 0.01),),
    sources=("wheel diameter: J. Southwest Jiaotong Univ., doi 10.3969/j.issn.0258-2724.20210777; wheelset mass and "
             "primary suspension: Goicolea 2014; mode frequency: Shock Vib. 2018, 6759105 (565-616 Hz); braking rate: "
             "CRH380A, 3760 m from 300 km/h (People's Daily, 30 May 2011); track: Shock Vib. 2019, 2015465, Table 2; "
             "axle load, frame share, polar inertia, modal mass and damping, wear band: assumptions"),
)


@dataclass(frozen=True, eq=False)
class WheelsOnRail:
    """Identical wheels (``model.wheel``, each with ``model.wheel_modes``) on one rail of
    ``model.track``, at ``positions`` (m along the rail from the first wheel: ``(0, 2.5)`` a
    bogie of wheelbase 2.5 m), coupled through the rail's transfer receptance
    ``A_jk(ω) = α(ω, x_j ← x_k)``.

    At each wheel the wheel-on-rigid-rail outputs are ``y_j = G_u ū_j + G_r w_j`` (``G_u``,
    ``G_r`` of :meth:`VehicleTrackModel.wheel_terms`) and the rail under it moves by
    ``w = -A N``, so ``N = (I + G_r,N A)^-1 G_u,N ū`` and every output is a matrix over the
    wheels, ``Y = G_u I - G_r A (I + G_r,N A)^-1 G_u,N`` (the wheel's own flexible modes add to
    ``A_jj``). Averaged over the first wheel's offset in the bay (all ``n`` offsets, unfolded:
    a pair is not its own mirror image). A harmonic of order ``n`` on every wheel then evolves
    as ``dû/dt = -c F_n² H_D(nΩ) û`` (:class:`~railwear.longterm.fourier.Fourier`): the growth
    rates are the eigenvalues of that matrix, each with the combination of the wheels' polygons
    (amplitude and phase) that grows at it. One wheel is :class:`VehicleTrackModel` itself."""

    model: VehicleTrackModel
    positions: tuple = (0.0,)

    def __post_init__(self):
        x = np.asarray(self.positions, float)
        if x.ndim != 1 or x.size < 1 or not np.all(np.isfinite(x)) or x[0] != 0.0 or np.any(np.diff(x) <= 0):
            raise ScenarioError("positions: the wheels' distances along the rail from the first (m): 0, then increasing")
        n = self.model.positions
        offsets = ([j * self.model.track.sleeper_spacing / n for j in range(n)]
                   if isinstance(n, (int, np.integer)) and self.model.track.discrete else bay_offsets(self.model.track, n)[0])
        object.__setattr__(self, "_x", x)
        object.__setattr__(self, "_offsets", offsets)

    def rail_matrix(self, angular_frequency) -> np.ndarray:
        """``A_jk`` [m/N] at every offset of the first wheel, ``(offsets, len(ω), wheels, wheels)``:
        the rail's displacement under wheel ``j`` per unit force at wheel ``k``."""
        omega = np.atleast_1d(np.asarray(angular_frequency, float))
        f, track = omega / (2 * np.pi), self.model.track
        out = np.empty((len(self._offsets), omega.size, self._x.size, self._x.size), complex)
        for i, d in enumerate(self._offsets):
            base = load_offset(track, d) if isinstance(d, str) else float(d)
            at = base + self._x
            for k, load in enumerate(at):
                out[i, :, :, k] = receptance(track, f, float(load), response=at)
        return out

    def transfer_matrix(self, angular_frequency, output="frictional_power", rail=None) -> np.ndarray:
        """Bay-averaged ``Y(ω)`` from the wheels' ``ū`` to their ``output`` (one of
        ``LINEAR_OUTPUTS``), ``(len(ω), wheels, wheels)``, complex; ``rail`` a :meth:`rail_matrix`
        at these ``ω`` already evaluated (a map evaluates it once for every speed)."""
        m = self.model
        if output not in m.LINEAR_OUTPUTS:
            raise ScenarioError(f"output: must be one of {m.LINEAR_OUTPUTS}, got {output!r}")
        row, normal = m.LINEAR_OUTPUTS.index(output), m.LINEAR_OUTPUTS.index("normal_force")
        gu, gr = m.wheel_terms(angular_frequency)
        A = self.rail_matrix(angular_frequency) if rail is None else rail
        eye = np.eye(self._x.size)
        A = A + m.wheel_mode_receptance(angular_frequency)[None, :, None, None] * eye
        N = np.linalg.solve(eye + gr[:, normal, None, None] * A, gu[:, normal, None, None] * eye)
        if m.filters_contact or m.tangential:  # the closed form is affine in the load: Y = P I + Q N̄
            omega = np.atleast_1d(np.asarray(angular_frequency, float))
            mean = np.mean(N, axis=0)
            own = mean[:, 0, 0]  # a load of the right size: no cancellation in q
            p = m._closed_form(omega, output, load=np.zeros(omega.shape))
            q = (m._closed_form(omega, output, load=own) - p) / own
            return p[:, None, None] * eye + q[:, None, None] * mean
        Y = gu[:, row, None, None] * eye - gr[:, row, None, None] * (A @ N)
        return np.mean(Y, axis=0)

    def frequencies(self, orders):
        """``n Ω`` [rad/s] of polygon ``orders`` on the model's wheel (Ω under its steady creepage)."""
        m = self.model
        return np.atleast_1d(np.asarray(orders, float)) * m.speed * (1 + m.steady_creepage()) / m.radius

    def rate_matrix(self, orders, law, band_width, rail=None):
        """``M_n = -c F_n² H_D(nΩ)`` [1/s], ``(orders, wheels, wheels)``: a harmonic of order ``n``
        on every wheel evolves as ``dû/dt = M_n û`` (the wear law's driver, :func:`law_terms`);
        ``rail`` a :meth:`rail_matrix` at :meth:`frequencies` of these orders."""
        m = self.model
        n = np.atleast_1d(np.asarray(orders, float))
        if np.any(n < 1):
            raise ScenarioError("orders must be >= 1")
        lin, terms = law_terms(m, law, band_width)
        c = lin.coefficient / (2 * np.pi * m.radius * band_width)
        omega = self.frequencies(n)
        A = self.rail_matrix(omega) if rail is None else rail
        H = sum(weight * self.transfer_matrix(omega, output, A) for output, weight in terms.items())
        filt = np.ones_like(n) if m.filters_contact else contact_filter(n, m.patch_half_length / m.radius) ** 2
        return -c * filt[:, None, None] * H

    def rail_modes(self, count=3) -> dict:
        """The rail's first ``count`` bending modes between the first two wheels [Hz]
        (:func:`railwear.track.between.localised_modes`: the pinned and clamped span as bounds,
        and the peak of the rail held by the two wheels, taken rigid so that the wheel's own modes
        do not mix in), the first wheel at midspan."""
        if self._x.size < 2:
            raise ScenarioError("positions: the rail between the wheels needs two wheels")
        return localised_modes(self.model.track, float(self._x[1] - self._x[0]), count)

    def rates(self, orders, law, band_width):
        """``(λ, modes)``: for each polygon order the growth rates ``λ`` (1/s, complex,
        ``(orders, wheels)``, fastest first) and the combinations ``modes`` (``(orders, wheels,
        wheels)``, column ``i`` the wheels' complex amplitudes growing at ``λ[:, i]``, unit norm)
        of the wear law's driver (:func:`~railwear.longterm.fourier.law_terms`)."""
        return growing_combinations(self.rate_matrix(orders, law, band_width))


def own_rates(M):
    """Each wheel's own rate [1/s], the diagonal of the rate matrices ``M`` (``(..., wheels,
    wheels)``): what a wheel's polygon grows at when its phase drifts against the others'."""
    return np.diagonal(M, axis1=-2, axis2=-1)


def growing_combinations(M):
    """Eigen-rates and combinations of rate matrices ``M`` (``(..., wheels, wheels)``, 1/s):
    ``(λ, modes)`` sorted by ``Re λ``, fastest first, columns of ``modes`` of unit norm."""
    lam, vec = np.linalg.eig(M)
    order = np.argsort(-lam.real, axis=-1)
    return np.take_along_axis(lam, order, -1), np.take_along_axis(vec, order[..., None, :], -1)


@dataclass(frozen=True, eq=False)
class WheelsFourier(Harmonics):
    """The Fourier technique for identical wheels on one rail: ``parts`` (one :class:`WheelsOnRail`
    per segment of a duty cycle, the same wheels at its speed and demand) run the ``shares`` of the
    distance under ``law`` with its wear band ``band_width`` [m]. Per metre each order's matrix is
    the distance-weighted mean ``M̄_n = V̄ Σ p_k M_n^k / V_k`` (``V̄ = 1 / Σ p_k / V_k``, as
    :class:`~railwear.longterm.fourier.FourierCycle`), and the order's rate is the fastest
    eigenvalue of ``M̄_n``: ``u`` is a wheel's radius deviation when each order's polygons on the
    wheels lie in that growing combination (any other start ends in it, the others falling behind).
    One wheel is :class:`Fourier` itself to round-off.

    ``phases``: ``"locked"`` (the wheels' polygons keep their relative angles: identical
    diameters) or ``"drifting"`` (diameters that differ by ``ΔD``, as wheels of different axles
    do: wheel ``k``'s order ``n`` reaches wheel ``j`` at ``n Ω_k``, and on ``j``'s tread its
    phase slips by a turn every ``D / (n ΔD)`` revolutions, 525 for order 8 and 0.2 mm on
    840 mm, against ``10⁷`` revolutions of growth: the coupling ``M_jk`` averages out and each
    wheel grows at its own ``M̄_jj``, :func:`own_rates`; ``u`` is then, order by order, the
    fastest wheel's)."""

    parts: tuple
    law: object
    band_width: float
    shares: tuple = (1.0,)
    phases: str = "locked"

    def __post_init__(self):
        if not self.parts or len(self.parts) != len(self.shares):
            raise ScenarioError("shares: one share of the distance per part")
        if abs(sum(self.shares) - 1) > 1e-9 or min(self.shares) <= 0:
            raise ScenarioError("shares: must be > 0 and sum to 1")
        if len({tuple(p.positions) for p in self.parts}) != 1:
            raise ScenarioError("positions: every part carries the same wheels")
        if self.phases not in PHASES:
            raise ScenarioError(f"phases: one of {', '.join(PHASES)}, got {self.phases!r}")
        singles = tuple(Fourier.disk_wheel(p.model, self.law, self.band_width) for p in self.parts)
        object.__setattr__(self, "_singles", singles)
        object.__setattr__(self, "_cache", {})

    @property
    def speed(self):
        return 1.0 / sum(p / f.speed for p, f in zip(self.shares, self._singles))

    @property
    def radius(self):
        return self._singles[0].radius

    @property
    def positions(self):
        """The wheels' distances along the rail from the first [m]."""
        return tuple(float(x) for x in self.parts[0].positions)

    @property
    def mean_rate(self):
        """Rate of the mean radius [m/s] (every wheel's: the steady driver does not couple them)."""
        return self.speed * sum(p / f.speed * f.mean_rate for p, f in zip(self.shares, self._singles))

    def rate_matrix(self, orders):
        """``M̄_n`` [1/s at the mean speed], ``(orders, wheels, wheels)``."""
        return self.speed * sum(p / f.speed * w.rate_matrix(orders, self.law, self.band_width)
                                for p, f, w in zip(self.shares, self._singles, self.parts))

    def combinations(self, orders):
        """``(λ, modes)`` of :func:`growing_combinations` on :meth:`rate_matrix`, kept for the last
        orders asked (a run's bisection asks for the same ones again and again)."""
        n = np.atleast_1d(np.asarray(orders, float))
        key = n.tobytes()
        if key not in self._cache:
            self._cache.clear()
            self._cache[key] = growing_combinations(self.rate_matrix(n))
        return self._cache[key]

    def rates(self, orders):
        """The fastest eigen-rate of each order [1/s, complex]; with drifting phases the fastest
        wheel's own rate."""
        if self.phases == "locked":
            return self.combinations(orders)[0][:, 0]
        own = self.wheel_rates(orders)
        return np.take_along_axis(own, np.argmax(own.real, axis=1)[:, None], 1)[:, 0]

    def wheel_rates(self, orders):
        """Each wheel's own rate [1/s, complex], ``(orders, wheels)`` (:func:`own_rates` of
        :meth:`rate_matrix`)."""
        return own_rates(self.rate_matrix(np.atleast_1d(np.asarray(orders, float))))

    def evolve(self, u0, t):
        """:meth:`Harmonics.evolve` of one wheel's ``u0`` (in the growing combinations); ``u0`` of
        one row per wheel (``(wheels, angle)``, m) gives every wheel's ``u`` at the times ``t``
        (s), ``(len(t), wheels, angle)``: each order's harmonics over the wheels (``rfft``
        coefficients ``ĉ``) evolve as ``ĉ(t) = V e^{Λt} V⁻¹ ĉ(0)``, the eigen-decomposition
        ``M̄_n = V Λ V⁻¹`` (locked), or each wheel's on its own ``M̄_jj`` (drifting); the mean
        radius of every wheel falls at :attr:`mean_rate`."""
        u0 = np.asarray(u0, float)
        if u0.ndim == 1:
            return super().evolve(u0, t)
        if u0.ndim != 2 or u0.shape[0] != len(self.positions) or u0.shape[1] < 4:
            raise ScenarioError(f"u0: one row per wheel ({len(self.positions)}) of at least 4 angles, "
                                f"not shape {u0.shape}")
        t = np.atleast_1d(np.asarray(t, float))
        n = u0.shape[1]
        c0 = np.fft.rfft(u0, axis=-1)
        orders = np.arange(1, c0.shape[1])
        c = np.empty((t.size,) + c0.shape, complex)
        c[:, :, 0] = c0[None, :, 0] + n * self.mean_rate * t[:, None]
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is for the caller's guard to report
            if self.phases == "locked":
                lam, V = self.combinations(orders)
                weights = np.linalg.solve(V, c0[:, 1:].T[..., None])[..., 0]  # V⁻¹ ĉ(0), (orders, wheels)
                c[:, :, 1:] = np.einsum("nji,tni,ni->tjn", V, np.exp(lam[None] * t[:, None, None]), weights)
                c[t == 0, :, 1:] = c0[:, 1:]  # the start itself, without the round-off of V V⁻¹
            else:
                c[:, :, 1:] = c0[None, :, 1:] * np.exp(t[:, None, None] * self.wheel_rates(orders).T[None])
            return np.fft.irfft(c, n, axis=-1)

    def run(self, u0, duration, n_save=101, depth_limit=None, peak_to_peak_limit=None):
        """:meth:`Harmonics.run`, with each order's growing combination over the wheels:
        ``combination_amplitude`` (relative to the largest) and ``combination_phase`` (rad,
        against the first wheel) on ``(order, wheel)``; ``u0`` of one row per wheel
        (:meth:`evolve`) gives ``u`` on ``(time, wheel, angle)``, the ``wheel`` coordinate each
        wheel's distance along the rail from the first (m)."""
        ds = super().run(u0, duration, n_save, depth_limit, peak_to_peak_limit)
        if ds.u.ndim == 3:
            ds = ds.assign_coords(wheel=("wheel", np.asarray(self.positions),
                                         {"units": "m", "long_name": "wheel's distance behind the first on the rail"}))
        return self.describe(ds)

    def describe(self, ds):
        """``ds`` (a result over ``order``) with the wheels: their positions, the phases, each
        order's growing combination (locked) or each wheel's own growth per km (drifting), and the
        rail's modes between the first two (the multiplier's result takes them too)."""
        ds = ds.assign_coords(wheel_position=("wheel", np.asarray(self.positions),
                                              {"units": "m", "long_name": "wheel's distance along the rail from the first"}))
        ds.attrs["wheel_phases"] = self.phases
        if self.phases == "drifting":
            ds["wheel_growth_per_km"] = (("order", "wheel"), self.wheel_rates(ds.order.values).real / self.speed * 1e3,
                                         {"units": "km-1", "long_name": "growth rate of the wheel's own polygon per "
                                                                        "kilometre, phases drifting"})
            return self._rail_modes(ds)
        _, modes = self.combinations(ds.order.values)
        v = modes[:, :, 0]
        amplitude = np.abs(v) / np.abs(v).max(axis=1, keepdims=True)
        phase = np.angle(v * np.conj(v[:, :1]))
        ds["combination_amplitude"] = (("order", "wheel"), amplitude,
                                       {"units": "1", "long_name": "amplitude of the wheel's polygon in the growing "
                                                                   "combination, relative to the largest"})
        ds["combination_phase"] = (("order", "wheel"), phase,
                                   {"units": "rad", "long_name": "phase of the wheel's polygon in the growing "
                                                                 "combination, against the first wheel"})
        return self._rail_modes(ds)

    def _rail_modes(self, ds):
        """``ds`` with the rail's bending modes between the first two wheels (several wheels)."""
        if len(self.positions) > 1:
            modes = self.parts[0].rail_modes()
            ds = ds.assign_coords(rail_mode=("rail_mode", np.arange(1, modes["pinned"].size + 1),
                                             {"units": "1", "long_name": "rail bending mode between the first two wheels"}))
            for key, text in (("pinned", "rail span pinned at the two contacts"),
                              ("clamped", "rail span clamped at the two contacts"),
                              ("held", "peak of the rail held by the two wheels on the track (NaN: none)")):
                ds[f"rail_mode_{key}"] = ("rail_mode", modes[key], {"units": "Hz", "long_name": text})
        return ds


def wheels_growth_map(case, positions, speeds, orders, law, bay_positions=8, phases="locked", contact="steady",
                      tangential=()):
    """The fastest combination's growth rate [1/km] of ``case``'s wheels at ``positions`` (m along
    the rail) over ``speeds`` (m/s) × ``orders``, as :func:`growth_map` gives the single wheel's,
    the rail matrix evaluated once for every speed's frequencies ``n Ω``; with drifting
    ``phases`` (:class:`WheelsFourier`) the fastest wheel's own rate; ``contact`` and ``tangential``
    as :meth:`VehicleCase.fourier` takes them."""
    if phases not in PHASES:
        raise ScenarioError(f"phases: one of {', '.join(PHASES)}, got {phases!r}")
    fastest = (lambda M: growing_combinations(M)[0][:, 0]) if phases == "locked" else (
        lambda M: np.max(own_rates(M).real, axis=1))
    speeds = np.atleast_1d(np.asarray(speeds, float))
    n = np.asarray(np.atleast_1d(orders), float)
    wheels = [WheelsOnRail(VehicleTrackModel(case.wheel(v), case.track, bay_positions, case.wheel_modes,
                                             case._contact(contact), tangential), positions) for v in speeds]
    omegas = [w.frequencies(n) for w in wheels]
    A = wheels[0].rail_matrix(np.concatenate(omegas))
    rate = np.array([fastest(w.rate_matrix(n, law, case.band_width, a)).real / v * KM
                     for w, v, a in zip(wheels, speeds, np.split(A, len(speeds), axis=1))])
    what = "fastest combination of the wheels" if phases == "locked" else "fastest wheel, phases drifting"
    return xr.Dataset(
        {"growth_rate": (("speed", "order"), rate, {"units": "km-1", "long_name": f"growth rate per kilometre run, {what}"})},
        coords={"speed": ("speed", speeds, {"units": "m s-1", "long_name": "vehicle speed"}),
                "order": ("order", n.astype(int), {"units": "1", "long_name": "polygon order"})},
        attrs={"strategy": "Fourier technique", "driver": "law", "wheel_positions_m": list(map(float, positions)),
               "wheel_phases": phases},
    )
