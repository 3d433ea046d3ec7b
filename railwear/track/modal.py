"""Time-domain track: modal superposition of a long finite rail on discrete supports (compiled).

The rail, simply supported at both ends of a track of ``n_sleepers`` bays (length ``n L``), is
expanded in its pinned-pinned modes ``w = Σ q_k sin(β_k x)``, ``β_k = kπ / (n L)``, kept up to
``max_frequency_hz``. Euler: ``ω_k² = EI β_k⁴ / m``, modal mass ``m nL / 2``. Timoshenko: the lower
root of ``(m ω² - κGA β²)(ρI ω² - EI β² - κGA) = (κGA β)²`` with ``ψ = B cos(β x)``,
``B = (κGA β² - m ω²) / (κGA β)``, modal mass ``(m + ρI B²) nL / 2`` (the shear branch, above
about 5 kHz for rails, is left out). Sleepers (mass ``M_s``) sit at the bay centres
``x_j = (j + 1/2) L``; pads and ballast are spring-dampers:

    M_k q̈_k + c_k q̇_k + M_k ω_k² q_k = Σ_j sin(β_k x_j) P_j + sin(β_k x_F) F(t)
    P_j = -k_p (w(x_j) - z_j) - c_p (ẇ(x_j) - ż_j)
    M_s z̈_j = -P_j - k_b z_j - c_b ż_j

A loss factor becomes the viscous coefficient ``c = η k / ω_ref`` at ``reference_frequency_hz``
(exact for a harmonic load at that frequency), the rail's per mode ``c_k = η M_k ω_k² / ω_ref``.
Classical fixed-step Runge-Kutta 4, compiled with numba; ``rhs`` and ``rail_displacement`` are
top-level compiled functions a body's own compiled loop can call.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.errors import ScenarioError
from railwear.track.model import Track

__all__ = ["ModalTrack", "MovingLoadResult", "rhs", "rail_displacement"]


@njit(cache=True)
def rail_displacement(y, x, beta, n_modes):
    """Rail displacement [m] at ``x`` from the modal coordinates ``y[:n_modes]``."""
    w = 0.0
    for k in range(n_modes):
        w += y[k] * math.sin(beta[k] * x)
    return w


@njit(cache=True)
def rhs(y, x_load, force, mass, stiff, damp, beta, shape, ks, cs, kb, cb, ms, rigid, out):
    """``out = dy/dt`` for the state ``y = (q, q̇, z, ż)`` under ``force`` [N] at ``x_load`` [m];
    ``shape[j, k] = sin(β_k x_j)``; per-sleeper ``ks, cs`` (pad), ``kb, cb`` (ballast), ``ms``;
    ``rigid``: pads on a rigid base (z = 0)."""
    nm = mass.size
    ns = shape.shape[0]
    q = y[:nm]
    qd = y[nm:2 * nm]
    gen = np.zeros(nm)
    for j in range(ns):
        w = 0.0
        wd = 0.0
        for k in range(nm):
            w += shape[j, k] * q[k]
            wd += shape[j, k] * qd[k]
        z = 0.0 if rigid else y[2 * nm + j]
        zd = 0.0 if rigid else y[2 * nm + ns + j]
        p = -ks * (w - z) - cs * (wd - zd)
        for k in range(nm):
            gen[k] += shape[j, k] * p
        if not rigid:
            out[2 * nm + j] = zd
            out[2 * nm + ns + j] = (-p - kb * z - cb * zd) / ms
    for k in range(nm):
        out[k] = qd[k]
        out[nm + k] = (gen[k] + math.sin(beta[k] * x_load) * force - damp[k] * qd[k] - stiff[k] * q[k]) / mass[k]


@njit(cache=True)
def _run(y0, dt, n_steps, x0, speed, f0, f1, omega_f, mass, stiff, damp, beta, shape, ks, cs, kb, cb, ms, rigid,
         x_probe, every):
    """RK4 under the load ``F = f0 + f1 sin(Ω t)`` at ``x0 + V t``; records every ``every`` steps
    the time, the rail under the load and at ``x_probe``."""
    nm = mass.size
    y = y0.copy()
    n_rec = n_steps // every + 1
    t_out = np.empty(n_rec)
    w_load = np.empty(n_rec)
    w_probe = np.empty(n_rec)
    k1 = np.empty_like(y)
    k2 = np.empty_like(y)
    k3 = np.empty_like(y)
    k4 = np.empty_like(y)
    r = 0
    for n in range(n_steps + 1):
        t = n * dt
        if n % every == 0:
            t_out[r] = t
            w_load[r] = rail_displacement(y, x0 + speed * t, beta, nm)
            w_probe[r] = rail_displacement(y, x_probe, beta, nm)
            r += 1
        if n == n_steps:
            break
        th = t + 0.5 * dt
        rhs(y, x0 + speed * t, f0 + f1 * math.sin(omega_f * t), mass, stiff, damp, beta, shape, ks, cs, kb, cb, ms,
            rigid, k1)
        rhs(y + 0.5 * dt * k1, x0 + speed * th, f0 + f1 * math.sin(omega_f * th), mass, stiff, damp, beta, shape, ks,
            cs, kb, cb, ms, rigid, k2)
        rhs(y + 0.5 * dt * k2, x0 + speed * th, f0 + f1 * math.sin(omega_f * th), mass, stiff, damp, beta, shape, ks,
            cs, kb, cb, ms, rigid, k3)
        rhs(y + dt * k3, x0 + speed * (t + dt), f0 + f1 * math.sin(omega_f * (t + dt)), mass, stiff, damp, beta,
            shape, ks, cs, kb, cb, ms, rigid, k4)
        y += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)
    return t_out[:r], w_load[:r], w_probe[:r], y


@dataclass(frozen=True)
class MovingLoadResult:
    """Output of ``ModalTrack.run``: times [s], rail displacement under the load and at the probe [m]
    (positive in the direction of the force), and the final state."""

    t: np.ndarray
    w_load: np.ndarray
    w_probe: np.ndarray
    state: np.ndarray


@dataclass(frozen=True, eq=False)
class ModalTrack:
    """A finite discrete track of ``n_sleepers`` bays in modal coordinates (module docstring).

    ``max_frequency_hz``: highest rail mode kept; ``reference_frequency_hz``: where loss factors
    become viscous coefficients. The arrays of the compiled ``rhs`` are attributes (``mass``,
    ``stiffness``, ``damping``, ``beta``, ``shape``) and ``support_parameters`` gives the rest.
    """

    track: Track
    n_sleepers: int = 81
    max_frequency_hz: float = 10000.0
    reference_frequency_hz: float = 100.0

    def __post_init__(self):
        if not self.track.discrete:
            raise ScenarioError("sleeper_spacing: the modal track needs discrete supports")
        if int(self.n_sleepers) != self.n_sleepers or self.n_sleepers < 3:
            raise ScenarioError(f"n_sleepers: must be an integer >= 3, got {self.n_sleepers!r}")
        for name in ("max_frequency_hz", "reference_frequency_hz"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ScenarioError(f"{name}: must be a positive finite number, got {value!r}")
        r, L = self.track.rail, self.track.sleeper_spacing
        length = self.n_sleepers * L
        m, EI = r.mass_per_metre, r.young_modulus * r.second_moment
        S, J = r.shear_coefficient * r.shear_modulus * r.area, r.rotary_inertia
        beta, omega2, mass = [], [], []
        k = 1
        while True:
            b = k * math.pi / length
            if self.track.beam == "euler":
                w2, mk = EI * b**4 / m, m * length / 2
            else:
                a2, a1, a0 = m * J, m * (EI * b**2 + S) + J * S * b**2, EI * S * b**4
                w2 = 2 * a0 / (a1 + math.sqrt(a1 * a1 - 4 * a2 * a0))
                B = (S * b**2 - m * w2) / (S * b)
                mk = (m + J * B * B) * length / 2
            if math.sqrt(w2) > 2 * math.pi * self.max_frequency_hz:
                break
            beta.append(b)
            omega2.append(w2)
            mass.append(mk)
            k += 1
        beta, omega2, mass = np.array(beta), np.array(omega2), np.array(mass)
        stiff = mass * omega2
        w_ref = 2 * math.pi * self.reference_frequency_hz
        xs = (np.arange(self.n_sleepers) + 0.5) * L
        for name, value in (("length", length), ("beta", beta), ("mass", mass), ("stiffness", stiff),
                            ("damping", r.loss_factor * stiff / w_ref), ("sleeper_positions", xs),
                            ("shape", np.sin(np.outer(xs, beta)))):
            object.__setattr__(self, name, value)

    @property
    def n_modes(self) -> int:
        return self.beta.size

    @property
    def n_states(self) -> int:
        return 2 * self.n_modes + (0 if self.track.support.rigid_base else 2 * self.n_sleepers)

    @property
    def support_parameters(self) -> tuple:
        """``(k_p, c_p, k_b, c_b, M_s, rigid)`` for ``rhs``, loss factors made viscous at ``ω_ref``."""
        s, w_ref = self.track.support, 2 * math.pi * self.reference_frequency_hz
        cp = s.pad_damping + s.pad_loss_factor * s.pad_stiffness / w_ref
        if s.rigid_base:
            return s.pad_stiffness, cp, 0.0, 0.0, 1.0, True
        cb = s.ballast_damping + s.ballast_loss_factor * s.ballast_stiffness / w_ref
        if s.sleeper_mass <= 0:
            raise ScenarioError("sleeper_mass: the modal track needs a sleeper mass on ballast")
        return s.pad_stiffness, cp, s.ballast_stiffness, cb, s.sleeper_mass, False

    def middle(self, position="midspan") -> float:
        """Coordinate [m] of ``"midspan"`` (between the two middle sleepers) or ``"sleeper"`` (the middle one)."""
        j = self.n_sleepers // 2
        if position == "sleeper":
            return float(self.sleeper_positions[j])
        if position == "midspan":
            return float(self.sleeper_positions[j] + 0.5 * self.track.sleeper_spacing)
        raise ScenarioError(f"position: must be 'midspan' or 'sleeper', got {position!r}")

    def run(self, t_end, dt=2e-5, x0=None, speed=0.0, force=0.0, amplitude=0.0, frequency_hz=0.0, probe=None,
            every=1, state=None) -> MovingLoadResult:
        """Rail response to the load ``force + amplitude sin(2π f t)`` [N] at ``x0 + speed t`` [m]
        (default x0: the middle midspan) from rest or ``state``; records every ``every`` steps."""
        x0 = self.middle() if x0 is None else float(x0)
        probe = x0 if probe is None else float(probe)
        n_steps = int(round(t_end / dt))
        if n_steps < 1 or not math.isfinite(dt) or dt <= 0:
            raise ScenarioError(f"dt: must be positive and below t_end, got {dt!r}")
        end = x0 + speed * t_end
        if not (0 < x0 < self.length and 0 < end < self.length):
            raise ScenarioError("x0: the load must stay on the track")
        y0 = np.zeros(self.n_states) if state is None else np.asarray(state, dtype=float)
        kp, cp, kb, cb, ms, rigid = self.support_parameters
        t, wl, wp, y = _run(y0, float(dt), n_steps, x0, float(speed), float(force), float(amplitude),
                            2 * math.pi * float(frequency_hz), self.mass, self.stiffness, self.damping, self.beta,
                            self.shape, kp, cp, kb, cb, ms, rigid, probe, int(every))
        return MovingLoadResult(t=t, w_load=wl, w_probe=wp, state=y)
