"""The disk wheel on the ring track: wheel, contact and track in one compiled RK4 loop.

The wheel is :class:`~railwear.dynamics.DiskWheelModel` on a rigid rail (``rail_mass=None``:
states ``φ, Ω, z_w, z_w', z_s, z_s'``, its contact filter, Hertz ``N = k_H δ^(3/2)``, Kalker creep
under the traction torque, frictional power ``π = Fx ξ V``), the rail the ring track of
:class:`railwear.track.modal.RingTrack` under the wheel at ``x = x0 + V t``. The rail's upward
displacement under the wheel is ``z_r = -(w_m + r N)``: ``w_m`` the kept modes and the near pads'
residual deflection, ``r N`` the residual flexibility of the modes left out, in series with
Hertz, so the approach solves ``δ + r k_H δ^(3/2) = δ0 - w_m - z_w + ū`` (Newton; ``δ <= 0``: no
contact). The wheel's right-hand side is the disk wheel's own (``kernels.disk_wheel_rhs``) with
that ``z_r``; the track's is ``ring_rhs`` under ``N`` (the full force: the static load included,
the track's state is absolute). Classical RK4 at a fixed step; the frictional energy of each step
(trapezoidal in time) is swept onto the wheel cells as the patch moves (``kernels.sweep``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.dynamics import kernels as k
from railwear.errors import ScenarioError
from railwear.track.modal import RingTrack, ring_near, ring_pads, ring_rail_displacement, ring_rhs, ring_shapes

__all__ = ["WheelOnRing", "wheel_on_ring_run", "N_RECORDS"]

WHEEL_STATES = 6
N_RECORDS = 8  # t, N, creepage, power, contact angle (unwrapped), rail under the wheel (down), z_w, x


@njit(cache=True)
def _contact(t, y, p, surf, x, length, spacing, residual, kh, arrays, scratch, guess):
    """Rail under the wheel and the approach: fills ``scratch`` (shapes, near sleepers, pads)
    and returns ``(N, w_m, δ)``."""
    imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, rtab, step = arrays
    phi, near, weight, pads = scratch
    nm, ns = imass.size, norm.size
    yt = y[WHEEL_STATES:]
    ring_shapes(x, length, phi)
    ring_near(x, spacing, ns, rtab, step, near, weight)
    ring_pads(yt, nm, ns, group, sign, tp, pads)
    wm = ring_rail_displacement(yt, phi, near, weight, pads, basis, 0.0, 0.0)
    r0 = p[k.DW_RADIUS]
    xc = p[k.DW_INITIAL_ANGLE] + p[k.DW_SPEED] / r0 * t + y[0]
    ubar = k.patch_average(surf, int(p[k.DW_N_CELLS]), xc, p[k.DW_PATCH_HALF_ANGLE])
    normal, d = approach(p[k.DW_STATIC_APPROACH] - wm - y[2] + ubar, residual, kh, guess)
    return normal, wm, d


@njit(cache=True)
def approach(dm, residual, kh, guess):
    """``(N, δ)`` of ``δ + r k_H δ^(3/2) = δ_m`` (Newton from ``guess``), ``N = k_H δ^(3/2)``;
    ``δ_m <= 0``: no contact, ``(0, δ_m)``."""
    if dm <= 0.0:
        return 0.0, dm
    d = min(max(guess, 1e-3 * dm), dm)
    for _ in range(30):
        s = math.sqrt(d)
        g = d + residual * kh * d * s - dm
        dn = d - g / (1.0 + 1.5 * residual * kh * s)
        if dn <= 0.0:
            dn = 0.5 * d
        if abs(dn - d) <= 1e-14 * dm:
            d = dn
            break
        d = dn
    return kh * d * math.sqrt(d), d


@njit(cache=True)
def _derivatives(t, y, p, surf, x, length, spacing, residual, kh, arrays, scratch, y8, d8, guess, out, rec):
    """``out = dy/dt`` of wheel and track (``out`` empty: none); returns ``δ``. With ``rec``
    non-empty, the contact outputs (t, N, ξ, π, x_c unwrapped, rail under the wheel, z_w, x)."""
    normal, wm, delta = _contact(t, y, p, surf, x, length, spacing, residual, kh, arrays, scratch, guess)
    for i in range(WHEEL_STATES):
        y8[i] = y[i]
    y8[6] = -(wm + residual * normal)
    y8[7] = 0.0
    if rec.size > 0:
        c = k._disk_contact(t, y8, p, surf)
        rec[0] = t
        rec[1] = c[0]
        rec[2] = c[1]
        rec[3] = c[3]
        rec[4] = p[k.DW_INITIAL_ANGLE] + p[k.DW_SPEED] / p[k.DW_RADIUS] * t + y[0]
        rec[5] = wm + residual * normal
        rec[6] = y[2]
        rec[7] = x
    if out.size > 0:
        k.disk_wheel_rhs(t, y8, p, surf, d8)
        for i in range(WHEEL_STATES):
            out[i] = d8[i]
        imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, rtab, step = arrays
        phi, near, weight, pads = scratch
        ring_rhs(y[WHEEL_STATES:], phi, normal, near, weight, imass, stiff, damp, group, sign, norm, scale, basis,
                 bnorm, tp, pads, out[WHEEL_STATES:])
    return delta


@njit(cache=True)
def wheel_on_ring_run(y0, t0, dt, n_steps, x0, p, surf, energy, every, imass, stiff, damp, group, sign, norm, scale,
                      basis, bnorm, tp, rtab, step, n_near):
    """RK4 from ``y0`` at ``t0`` [s] over ``n_steps`` of ``dt``, the wheel at ``x0 + V (t - t0)``
    on the ring; adds the frictional energy [J] per cell to ``energy`` (empty: none) and records
    the contact every ``every`` steps (``every <= 0``: none). Returns ``(y, records)``."""
    arrays = (imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, rtab, step)
    nm, ns = imass.size, norm.size
    length, spacing, residual = tp[6], tp[7], tp[8]
    kh = p[k.DW_HERTZ_CONSTANT]
    v = p[k.DW_SPEED]
    scratch = (np.empty(nm), np.empty(n_near, np.int64), np.empty(n_near), np.empty(2 * ns))
    y8, d8 = np.zeros(8), np.zeros(8)
    n = y0.size
    y = y0.copy()
    ys = np.empty(n)
    ks = np.empty((4, n))
    n_rec = n_steps // every + 1 if every > 0 else 0
    records = np.empty((n_rec, N_RECORDS))
    rec = np.empty(N_RECORDS)
    none = np.empty(0)
    half = p[k.DW_PATCH_HALF_ANGLE]
    sweep = energy.size > 0
    guess = p[k.DW_STATIC_APPROACH]
    xa, pa = 0.0, 0.0
    r = 0
    for i in range(n_steps + 1):
        t = t0 + i * dt
        x = (x0 + v * (t - t0)) % length
        last = i == n_steps
        guess = _derivatives(t, y, p, surf, x, length, spacing, residual, kh, arrays, scratch, y8, d8, guess,
                             none if last else ks[0], rec)
        if sweep and i > 0:
            k.sweep(energy, xa, rec[4], half, 0.5 * (pa + rec[3]) * dt)
        xa, pa = rec[4], rec[3]
        if every > 0 and i % every == 0:
            for j in range(N_RECORDS):
                records[r, j] = rec[j]
            records[r, 7] = x0 + v * (t - t0)
            r += 1
        if last:
            break
        for stage in range(1, 4):
            h = dt if stage == 3 else 0.5 * dt
            for j in range(n):
                ys[j] = y[j] + h * ks[stage - 1, j]
            ts = t + h
            x = (x0 + v * (ts - t0)) % length
            guess = _derivatives(ts, ys, p, surf, x, length, spacing, residual, kh, arrays, scratch, y8, d8, guess,
                                 ks[stage], none)
        for j in range(n):
            y[j] += dt / 6.0 * (ks[0, j] + 2.0 * ks[1, j] + 2.0 * ks[2, j] + ks[3, j])
    return y, records


@dataclass(frozen=True, eq=False)
class WheelOnRing:
    """The rigid-rail disk wheel ``wheel`` (a :class:`~railwear.dynamics.DiskWheelModel`,
    ``rail_mass=None``) rolling on ``ring`` (a :class:`~railwear.track.modal.RingTrack`) at the
    wheel's speed, RK4 steps of ``dt`` [s]. State: the wheel's six, then the ring's."""

    wheel: object
    ring: RingTrack
    dt: float = 5e-5

    def __post_init__(self):
        if getattr(self.wheel, "rail_mass", 0.0) is not None:
            raise ScenarioError("wheel.rail_mass: must be None, the ring track is the rail")
        if not (math.isfinite(self.dt) and self.dt > 0):
            raise ScenarioError(f"dt: must be positive and finite, got {self.dt!r}")
        rate = self.fastest_rate()
        if rate * self.dt > 2.5:
            raise ScenarioError(f"dt: {self.dt:g} s is beyond RK4's stability for the track's fastest mode "
                                f"({rate:.4g} 1/s); take at most {2.5 / rate:.3g} s")

    def fastest_rate(self) -> float:
        """Largest ``|λ|`` [1/s] of a rail mode (with its damping) or of the wheel's contact and
        creep: the RK4 step must keep ``|λ| dt`` inside the stability region (2.5 taken)."""
        ring, w = self.ring, self.wheel
        m, c, kk = ring.mass, ring.damping, ring.stiffness
        a = c / (2 * m)
        disc = a * a - kk / m
        lam = np.where(disc >= 0, a + np.sqrt(np.abs(disc)), np.sqrt(kk / m))
        kc = 1.0 / (1.0 / w.contact_stiffness + ring.contact_residual)
        contact = math.sqrt(kc / w.wheel_mass + kc / ring.mass.min() * ring.n_modes)
        creep = w.radius**2 * w.f11 / (w.wheel_inertia * w.speed)
        return float(max(lam.max(), contact, creep))

    @property
    def n_states(self) -> int:
        return WHEEL_STATES + self.ring.n_states

    def static_state(self, x, lift=0.0) -> np.ndarray:
        """Wheel and track at rest under the static load with the wheel at ``x`` [m]: the track's
        static deflection, the wheel and frame lowered with the rail under the wheel, ``lift`` [m]
        added to the wheel (the disk wheel's start lift over ``u``); ``Ω`` at the steady creepage
        for a round wheel (``DiskWheelModel.initial_state`` with its own ``radius_deviation``)."""
        w = self.wheel
        y = np.zeros(self.n_states)
        y[:WHEEL_STATES] = w.initial_state()[:WHEEL_STATES]
        track = self.ring.static_state(x, w.static_load)
        y[WHEEL_STATES:] = track
        down = self.rail_under(y, x, w.static_load)
        y[2] = -down + lift
        y[4] = -down
        return y

    def rail_under(self, y, x, force) -> float:
        """Rail displacement [m, down] at ``x`` under ``force`` [N] in the state ``y``."""
        ring = self.ring
        phi, near, weight, pads = (np.empty(ring.n_modes), np.empty(ring.n_near, np.int64), np.empty(ring.n_near),
                                   np.empty(2 * ring.n_sleepers))
        yt = np.ascontiguousarray(y[WHEEL_STATES:])
        x = float(x) % ring.length
        ring_shapes(x, ring.length, phi)
        ring_near(x, ring.track.sleeper_spacing, ring.n_sleepers, ring.rtab, ring.step, near, weight)
        ring_pads(yt, ring.n_modes, ring.n_sleepers, ring.group, ring.sign, ring.tp, pads)
        return float(ring_rail_displacement(yt, phi, near, weight, pads, ring.basis, ring.contact_residual,
                                            float(force)))

    def run(self, y, t0, n_steps, x0, params, surf, energy=None, every=0):
        """``n_steps`` RK4 steps from ``y`` at ``t0`` [s] with the wheel at ``x0`` [m]; the
        frictional energy [J] per cell added to ``energy``; records every ``every`` steps (rows
        of ``t, N, ξ, π, x_c, rail under the wheel (down), z_w, x``). Returns ``(y, records)``."""
        energy = np.zeros(0) if energy is None else energy
        return wheel_on_ring_run(np.asarray(y, float), float(t0), float(self.dt), int(n_steps), float(x0), params,
                                 surf, energy, int(every), *self.ring.arrays())
