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

``RingTrack``: the same track closed into a ring of ``n`` bays in Bloch coordinates (each pad
couples one rail mode to one sleeper coordinate), with the modes left out as residual
flexibility; ``ring_*`` its compiled pieces (docs/vehicle_track_time.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.errors import ScenarioError
from railwear.track.model import Track

__all__ = ["ModalTrack", "MovingLoadResult", "RingTrack", "rhs", "rail_displacement", "ring_near", "ring_pads",
           "ring_rail_displacement", "ring_rhs", "ring_rhs_loads", "ring_shapes"]


def rail_modes(track, step, max_frequency_hz, half_length):
    """Rail bending modes ``β_k = k step``, ``k = 1, 2, ...``, up to ``max_frequency_hz``:
    ``(β, ω², M)`` with the modal mass ``M`` of a shape ``sin`` or ``cos(β x)`` over a length
    ``2 half_length``. Euler ``ω² = EI β⁴ / m``, ``M = m half_length``; Timoshenko the lower root
    of ``(m ω² - κGA β²)(ρI ω² - EI β² - κGA) = (κGA β)²``, ``M = (m + ρI B²) half_length`` with
    ``ψ = B cos(β x)``, ``B = (κGA β² - m ω²) / (κGA β)``."""
    r = track.rail
    m, EI = r.mass_per_metre, r.youngs_modulus * r.second_moment
    S, J = r.shear_coefficient * r.shear_modulus * r.area, r.rotary_inertia
    beta, omega2, mass = [], [], []
    k = 1
    while True:
        b = k * step
        if track.beam == "euler":
            w2, mk = EI * b**4 / m, m * half_length
        else:
            a2, a1, a0 = m * J, m * (EI * b**2 + S) + J * S * b**2, EI * S * b**4
            w2 = 2 * a0 / (a1 + math.sqrt(a1 * a1 - 4 * a2 * a0))
            B = (S * b**2 - m * w2) / (S * b)
            mk = (m + J * B * B) * half_length
        if math.sqrt(w2) > 2 * math.pi * max_frequency_hz:
            break
        beta.append(b)
        omega2.append(w2)
        mass.append(mk)
        k += 1
    return np.array(beta), np.array(omega2), np.array(mass)


def _one_mass_per_seat(support):
    """Refuse a support the time-domain track does not model: a ballast mass on a subgrade."""
    if not support.rigid_ground:
        raise ScenarioError("subgrade_stiffness: the time-domain track has one mass per rail seat, on the ballast "
                            "spring; a ballast mass on a subgrade has its receptance only (railwear.track.receptance, "
                            "the Fourier technique)")


def viscous_support(support, reference_frequency_hz):
    """``(k_p, c_p, k_b, c_b, M_s, rigid)`` of ``support``, loss factors made viscous,
    ``c = c_v + η k / ω_ref``, at ``reference_frequency_hz``."""
    s, w_ref = support, 2 * math.pi * reference_frequency_hz
    _one_mass_per_seat(s)
    cp = s.pad_damping + s.pad_loss_factor * s.pad_stiffness / w_ref
    if s.rigid_base:
        return s.pad_stiffness, cp, 0.0, 0.0, 1.0, True
    cb = s.ballast_damping + s.ballast_loss_factor * s.ballast_stiffness / w_ref
    if s.sleeper_mass <= 0:
        raise ScenarioError("sleeper_mass: the modal track needs a sleeper mass on ballast")
    return s.pad_stiffness, cp, s.ballast_stiffness, cb, s.sleeper_mass, False


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


class _ModalStates:
    """The state size of a modal track: modes and their rates, sleepers and theirs."""

    @property
    def n_states(self) -> int:
        return 2 * self.n_modes + (0 if self.track.support.rigid_base else 2 * self.n_sleepers)


@dataclass(frozen=True, eq=False)
class ModalTrack(_ModalStates):
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
        _one_mass_per_seat(self.track.support)
        if int(self.n_sleepers) != self.n_sleepers or self.n_sleepers < 3:
            raise ScenarioError(f"n_sleepers: must be an integer >= 3, got {self.n_sleepers!r}")
        for name in ("max_frequency_hz", "reference_frequency_hz"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ScenarioError(f"{name}: must be a positive finite number, got {value!r}")
        r, L = self.track.rail, self.track.sleeper_spacing
        length = self.n_sleepers * L
        beta, omega2, mass = rail_modes(self.track, math.pi / length, self.max_frequency_hz, length / 2)
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
    def support_parameters(self) -> tuple:
        """``(k_p, c_p, k_b, c_b, M_s, rigid)`` for ``rhs``, loss factors made viscous at ``ω_ref``."""
        return viscous_support(self.track.support, self.reference_frequency_hz)

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


# ---- the ring track: a periodic discrete track, in Bloch coordinates -----------------------

@njit(cache=True)
def ring_shapes(x, length, phi):
    """Ring mode shapes at ``x`` [m] into ``phi``: ``1, cos β_1 x, sin β_1 x, cos β_2 x, ...``,
    ``β_k = 2π k / length`` (by the recurrence of ``e^{ikθ}``)."""
    th = 2.0 * math.pi * x / length
    c1, s1 = math.cos(th), math.sin(th)
    c, s = 1.0, 0.0
    phi[0] = 1.0
    for k in range(1, (phi.size + 1) // 2):
        c, s = c * c1 - s * s1, s * c1 + c * s1
        phi[2 * k - 1] = c
        phi[2 * k] = s


@njit(cache=True)
def ring_near(x, spacing, n_sleepers, rtab, step, near, weight):
    """The sleepers within reach of the residual flexibility of a force at ``x`` [m]: their
    indices into ``near`` and ``R(x - x_j)`` [m/N] (``rtab`` sampled at ``d = i step``) into
    ``weight``; ``near.size`` sleepers about the nearest."""
    nn = near.size
    base = math.floor(x / spacing + 0.5) - nn // 2
    for i in range(nn):
        j = int(base) + i
        d = abs(x - j * spacing)
        pos = d / step
        m = int(pos)
        if m >= rtab.size - 1:
            weight[i] = 0.0
        else:
            f = pos - m
            weight[i] = (1.0 - f) * rtab[m] + f * rtab[m + 1]
        near[i] = j % n_sleepers


@njit(cache=True)
def ring_pads(y, nm, ns, group, sign, tp, pads):
    """Pad forces on the rail [N] in the sleeper basis without the residual flexibility,
    ``P_g = -k_p (W_g - Z_g) - c_p (Ẇ_g - Ż_g)``, ``W_g = Σ_{g(i) = g} σ_i q_i``, into
    ``pads[:ns]`` (``pads[ns:2 ns]`` is work space)."""
    kp, cp, rigid = tp[0], tp[1], tp[5]
    for g in range(2 * ns):
        pads[g] = 0.0
    for i in range(nm):
        g = group[i]
        if g >= 0:
            pads[g] += sign[i] * y[i]
            pads[ns + g] += sign[i] * y[nm + i]
    for g in range(ns):
        if rigid:
            pads[g] = -kp * pads[g] - cp * pads[ns + g]
        else:
            pads[g] = -kp * (pads[g] - y[2 * nm + g]) - cp * (pads[ns + g] - y[2 * nm + ns + g])


@njit(cache=True)
def ring_rhs(y, phi, force, near, weight, imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, pads,
             out):
    """``out = dy/dt`` of the ring track, ``y = (q, q̇, Z, Ż)`` (``Z`` the sleepers in their
    basis), under ``force`` [N] (positive down) at the point whose shapes are ``phi`` and whose
    near sleepers are ``near``/``weight`` (``ring_near``); ``pads`` from ``ring_pads`` (its first
    ``ns`` entries are replaced by the pad forces with the residual flexibility,
    ``P = (P⁰ - k_p X) scale``, ``scale = 1 / (1 + k_p λ)``, ``X`` the residual deflection of the
    seats under the force). ``imass = 1 / M``; ``basis[j, g] = b_g(j)``, ``bnorm = b_g(j) / ‖b_g‖²``;
    ``tp = (k_p, c_p, k_b, c_b, 1 / M_s, rigid, ...)``. No divisions: this runs four times a step."""
    nm = imass.size
    ns = norm.size
    kp, kb, cb, ims, rigid = tp[0], tp[2], tp[3], tp[4], tp[5]
    for i in range(near.size):
        x = kp * weight[i] * force
        if x != 0.0:
            row = bnorm[near[i]]
            for g in range(ns):
                pads[g] -= x * row[g]
    for g in range(ns):
        pads[g] *= scale[g]
    for i in range(nm):
        gen = phi[i] * force
        g = group[i]
        if g >= 0:
            gen += sign[i] * norm[g] * pads[g]
        out[i] = y[nm + i]
        out[nm + i] = (gen - damp[i] * y[nm + i] - stiff[i] * y[i]) * imass[i]
    if not rigid:
        _seat_rates(y, pads, nm, ns, kb, cb, ims, out)


@njit(cache=True, inline="always")
def _seat_rates(y, pads, nm, ns, kb, cb, ims, out):
    """The sleepers' rows of ``dy/dt``: each seat's mass on the ballast under its pad force."""
    for g in range(ns):
        z = y[2 * nm + g]
        zd = y[2 * nm + ns + g]
        out[2 * nm + g] = zd
        out[2 * nm + ns + g] = -(pads[g] + kb * z + cb * zd) * ims


@njit(cache=True)
def ring_rhs_loads(y, phis, forces, nears, weights, imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp,
                   pads, out):
    """``out = dy/dt`` of the ring track under several ``forces`` [N] (positive down), row ``a``
    of ``phis``, ``nears``, ``weights`` the shapes and near sleepers of force ``a``: ``ring_rhs``
    with ``φ F → Σ_a φ_a F_a`` and the seats' residual deflection ``X = Σ_a R(x_j - x_a) F_a``
    (the same operations in the same order for one force)."""
    nm = imass.size
    ns = norm.size
    kp, kb, cb, ims, rigid = tp[0], tp[2], tp[3], tp[4], tp[5]
    nf = forces.size
    for a in range(nf):
        near, weight = nears[a], weights[a]
        for i in range(near.size):
            x = kp * weight[i] * forces[a]
            if x != 0.0:
                row = bnorm[near[i]]
                for g in range(ns):
                    pads[g] -= x * row[g]
    for g in range(ns):
        pads[g] *= scale[g]
    for i in range(nm):
        gen = phis[0, i] * forces[0]
        for a in range(1, nf):
            gen += phis[a, i] * forces[a]
        g = group[i]
        if g >= 0:
            gen += sign[i] * norm[g] * pads[g]
        out[i] = y[nm + i]
        out[nm + i] = (gen - damp[i] * y[nm + i] - stiff[i] * y[i]) * imass[i]
    if not rigid:
        _seat_rates(y, pads, nm, ns, kb, cb, ims, out)


@njit(cache=True)
def ring_rail_displacement(y, phi, near, weight, pads, basis, residual, force):
    """Rail displacement [m] at the point of ``phi``: the kept modes, the near pads' residual
    deflection ``Σ_j R(x - x_j) P_j`` (``pads`` from ``ring_pads``, before the residual's own
    correction: a second-order difference) and ``residual force``."""
    w = 0.0
    for i in range(phi.size):
        w += phi[i] * y[i]
    ns = basis.shape[1]
    for i in range(near.size):
        if weight[i] != 0.0:
            row = basis[near[i]]
            p = 0.0
            for g in range(ns):
                p += pads[g] * row[g]
            w += weight[i] * p
    return w + residual * force


@njit(cache=True)
def _ring_run(y0, dt, n_steps, x0, speed, f0, f1, omega_f, x_probe, every, imass, stiff, damp, group, sign, norm,
              scale, basis, bnorm, tp, rtab, step, n_near):
    """RK4 of the ring track under ``f0 + f1 sin(Ω t)`` at ``x0 + V t``; records every ``every``
    steps the time and the rail under the load and at ``x_probe``."""
    nm, ns = imass.size, norm.size
    length, spacing, residual = tp[6], tp[7], tp[8]
    y = y0.copy()
    n_rec = n_steps // every + 1
    t_out, w_load, w_probe = np.empty(n_rec), np.empty(n_rec), np.empty(n_rec)
    ks = np.empty((4, y.size))
    phi, phi_p = np.empty(nm), np.empty(nm)
    near, near_p = np.empty(n_near, np.int64), np.empty(n_near, np.int64)
    weight, weight_p = np.empty(n_near), np.empty(n_near)
    pads = np.empty(2 * ns)
    ys = np.empty_like(y)
    r = 0
    for n in range(n_steps + 1):
        t = n * dt
        if n % every == 0:
            x = x0 + speed * t
            force = f0 + f1 * math.sin(omega_f * t)
            ring_shapes(x, length, phi)
            ring_near(x, spacing, ns, rtab, step, near, weight)
            ring_pads(y, nm, ns, group, sign, tp, pads)
            t_out[r] = t
            w_load[r] = ring_rail_displacement(y, phi, near, weight, pads, basis, residual, force)
            ring_shapes(x_probe, length, phi_p)
            ring_near(x_probe, spacing, ns, rtab, step, near_p, weight_p)
            d = abs(x_probe - x) / step
            cross = 0.0 if d >= rtab.size - 1 else rtab[int(d)] + (d - int(d)) * (rtab[int(d) + 1] - rtab[int(d)])
            w_probe[r] = ring_rail_displacement(y, phi_p, near_p, weight_p, pads, basis, cross, force)
            r += 1
        if n == n_steps:
            break
        for stage in range(4):
            h = 0.0 if stage == 0 else (dt if stage == 3 else 0.5 * dt)
            for i in range(y.size):
                ys[i] = y[i] + (h * ks[stage - 1, i] if stage > 0 else 0.0)
            ts = t + h
            x = x0 + speed * ts
            ring_shapes(x, length, phi)
            ring_near(x, spacing, ns, rtab, step, near, weight)
            ring_pads(ys, nm, ns, group, sign, tp, pads)
            ring_rhs(ys, phi, f0 + f1 * math.sin(omega_f * ts), near, weight, imass, stiff, damp, group, sign, norm,
                     scale, basis, bnorm, tp, pads, ks[stage])
        for i in range(y.size):
            y[i] += dt / 6.0 * (ks[0, i] + 2.0 * ks[1, i] + 2.0 * ks[2, i] + ks[3, i])
    return t_out[:r], w_load[:r], w_probe[:r], y


@dataclass(frozen=True, eq=False)
class RingTrack(_ModalStates):
    """A periodic discrete track of ``n_sleepers`` bays closed into a ring of length ``ℓ = n L``
    (a wheel runs round it for ever), in Bloch coordinates; the time-domain model the
    vehicle-track body runs on.

    Rail: ``w = q_0 + Σ_k q_k^c cos β_k x + q_k^s sin β_k x``, ``β_k = 2π k / ℓ``, the modes of
    :func:`rail_modes` up to ``max_frequency_hz`` (``M_0 = m ℓ``, ``ω_0 = 0``). Sleepers at
    ``x_j = j L``, their displacements ``z_j = Σ_g Z_g b_g(j)`` in the real Fourier basis of the
    lattice (``b = 1, cos 2πpj/n, sin 2πpj/n, ...``, ``‖b_g‖² = n`` or ``n/2``). A rail mode
    ``cos``/``sin β_k x`` is ``±b_g`` on the lattice (``g`` from ``k mod n``), so every pad couples
    one rail mode to one sleeper coordinate, ``P_g = -k_p (W_g - Z_g) - c_p (Ẇ_g - Ż_g)``,
    ``W_g = Σ_{g(i)=g} σ_i q_i``:

        M_i q̈_i + c_i q̇_i + K_i q_i = σ_i ‖b_g‖² P_g + φ_i(x_F) F,   M_s Z̈_g = -P_g - k_b Z_g - c_b Ż_g

    an ``O(modes + sleepers)`` right-hand side. The modes left out act quasi-statically
    (residual flexibility): ``R(d) = G(d) - Σ_{k≤K} cos(β_k d) / K_k``, ``G`` the static Green's
    function of the free ring beam (Euler ``-(2/ℓ)(ℓ/2π)⁴ π⁴ B_4(d/ℓ) / 3EI``, Timoshenko plus
    ``(2/ℓ)(ℓ/2π)² π² B_2(d/ℓ) / κGA``, ``B_n`` Bernoulli polynomials); the rail under a force
    moves by ``r F`` more (``r = R(0)``), the seats by ``R(x_j - x_F) F`` (``n_near`` sleepers
    about the force) and by ``λ_g P_g`` from the pads (``λ_g`` the lattice transform of ``R``):
    ``P_g → (P_g - k_p X_g) / (1 + k_p λ_g)``. Loss factors become viscous at
    ``reference_frequency_hz`` as in :class:`ModalTrack`.
    """

    track: Track
    n_sleepers: int = 48
    max_frequency_hz: float = 3000.0
    reference_frequency_hz: float = 100.0
    residual: bool = True
    n_near: int = 3

    def __post_init__(self):
        if not self.track.discrete:
            raise ScenarioError("sleeper_spacing: the ring track needs discrete supports")
        if int(self.n_sleepers) != self.n_sleepers or self.n_sleepers < 4:
            raise ScenarioError(f"n_sleepers: must be an integer >= 4, got {self.n_sleepers!r}")
        if int(self.n_near) != self.n_near or not 1 <= self.n_near <= self.n_sleepers:
            raise ScenarioError(f"n_near: must be an integer from 1 to n_sleepers, got {self.n_near!r}")
        for name in ("max_frequency_hz", "reference_frequency_hz"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise ScenarioError(f"{name}: must be a positive finite number, got {value!r}")
        r, L, n = self.track.rail, self.track.sleeper_spacing, int(self.n_sleepers)
        length = n * L
        beta, omega2, modal = rail_modes(self.track, 2 * math.pi / length, self.max_frequency_hz, length / 2)
        K = beta.size
        mass = np.concatenate([[r.mass_per_metre * length], np.repeat(modal, 2)])
        stiff = np.concatenate([[0.0], np.repeat(modal * omega2, 2)])
        # the lattice basis and the group of each rail mode
        basis = np.empty((n, n))  # basis[g, j] here, stored as [j, g]
        j = np.arange(n)
        basis[0] = 1.0
        for p in range(1, (n - 1) // 2 + 1):
            basis[2 * p - 1] = np.cos(2 * np.pi * p * j / n)
            basis[2 * p] = np.sin(2 * np.pi * p * j / n)
        if n % 2 == 0:
            basis[n - 1] = np.cos(np.pi * j)
        norm = np.sum(basis**2, axis=1)
        group, sign = np.full(2 * K + 1, -1, np.int64), np.ones(2 * K + 1)
        group[0] = 0
        for k in range(1, K + 1):
            p = k % n
            if p == 0:
                group[2 * k - 1] = 0
            elif 2 * p == n:
                group[2 * k - 1] = n - 1
            else:
                q = min(p, n - p)
                group[2 * k - 1], group[2 * k] = 2 * q - 1, 2 * q
                sign[2 * k] = 1.0 if p == q else -1.0
        object.__setattr__(self, "_kept", (beta, modal * omega2))
        step = L / 400
        reach = (self.n_near // 2 + 1) * L
        d_tab = np.arange(int(np.ceil(reach / step)) + 2) * step
        rtab = self.residual_flexibility(d_tab) if self.residual else np.zeros(d_tab.size)
        lam = np.zeros(n)
        if self.residual:
            lattice = self.residual_flexibility(j * L)
            for g in range(n):  # the circulant R(x_j - x_l) is diagonal in the basis
                lam[g] = np.sum(lattice * np.cos(2 * np.pi * self._frequency_index(g, n) * j / n))
        w_ref = 2 * math.pi * self.reference_frequency_hz
        kp, cp, kb, cb, ms, rigid = viscous_support(self.track.support, self.reference_frequency_hz)
        tp = np.array([kp, cp, kb, cb, 1.0 / ms, float(rigid), length, L, rtab[0], 0.0])
        for name, value in (("length", length), ("wavenumbers", beta), ("mass", mass), ("stiffness", stiff),
                            ("damping", r.loss_factor * stiff / w_ref), ("group", group), ("sign", sign),
                            ("norm", norm), ("basis", np.ascontiguousarray(basis.T)), ("lam", lam),
                            ("bnorm", np.ascontiguousarray((basis / norm[:, None]).T)), ("rtab", rtab), ("step", step),
                            ("tp", tp)):
            object.__setattr__(self, name, value)

    @staticmethod
    def _frequency_index(g, n):
        """The lattice wavenumber index ``p`` of basis function ``g``."""
        if g == 0:
            return 0
        if n % 2 == 0 and g == n - 1:
            return n // 2
        return (g + 1) // 2

    def residual_flexibility(self, distance) -> np.ndarray:
        """``R(d)`` [m/N]: the static displacement at distance ``d`` [m] from a unit force of the
        rail modes left out (the free ring beam's Green's function less the kept modes')."""
        r = self.track.rail
        EI, S = r.youngs_modulus * r.second_moment, r.shear_coefficient * r.shear_modulus * r.area
        length = self.n_sleepers * self.track.sleeper_spacing
        t = np.mod(np.asarray(distance, float), length) / length
        b4 = t**4 - 2 * t**3 + t**2 - 1 / 30
        b2 = t**2 - t + 1 / 6
        g = (2 / length) * ((length / (2 * np.pi))**4 / EI * (-np.pi**4 * b4 / 3))
        if self.track.beam == "timoshenko":
            g = g + (2 / length) * (length / (2 * np.pi))**2 / S * np.pi**2 * b2
        beta, kk = self._kept
        return g - np.cos(np.multiply.outer(t * length, beta)) @ (1 / kk)

    @property
    def n_modes(self) -> int:
        return self.mass.size

    @property
    def contact_residual(self) -> float:
        """``r = R(0)`` [m/N]: the residual flexibility under a force, in series with it."""
        return float(self.tp[8])

    def arrays(self):
        """The arrays of the compiled ``ring_rhs`` from ``imass`` on, then the residual's table:
        ``(1/mass, stiffness, damping, group, sign, norm, 1/(1 + k_p λ), basis, bnorm, tp, rtab,
        step, n_near)``."""
        return (1.0 / self.mass, self.stiffness, self.damping, self.group, self.sign, self.norm,
                1.0 / (1.0 + self.tp[0] * self.lam), self.basis, self.bnorm, self.tp, self.rtab, self.step,
                int(self.n_near))

    def static_state(self, x, force) -> np.ndarray:
        """The state at rest under ``force`` [N] at ``x`` [m] (the linear static problem)."""
        return self.static_loads([x], [force])

    def static_loads(self, positions, forces) -> np.ndarray:
        """The state at rest under ``forces`` [N] at ``positions`` [m] (the linear static
        problem ``A y = -b``: ``A`` the accelerations per unit displacement, ``b`` under the loads)."""
        n = self.n_states
        nm, ns = self.n_modes, self.n_sleepers
        xs, fs = np.asarray(positions, float), np.asarray(forces, float)
        if xs.ndim != 1 or xs.shape != fs.shape or xs.size < 1:
            raise ScenarioError("forces: one force per position")
        pos = np.r_[np.arange(nm), 2 * nm + np.arange(ns if n > 2 * nm else 0)]
        acc = np.r_[nm + np.arange(nm), 2 * nm + ns + np.arange(ns if n > 2 * nm else 0)]
        phis, nears, weights = (np.empty((xs.size, nm)), np.empty((xs.size, self.n_near), np.int64),
                                np.empty((xs.size, self.n_near)))
        for a, x in enumerate(xs):
            ring_shapes(float(x), self.length, phis[a])
            ring_near(float(x), self.track.sleeper_spacing, ns, self.rtab, self.step, nears[a], weights[a])

        def accel(y, f):
            out, pads = np.zeros(n), np.empty(2 * ns)
            ring_pads(y, nm, ns, self.group, self.sign, self.tp, pads)
            ring_rhs_loads(y, phis, f, nears, weights, *self.arrays()[:10], pads, out)
            return out[acc]
        b = accel(np.zeros(n), fs)
        A = np.empty((pos.size, pos.size))
        for c, i in enumerate(pos):
            e = np.zeros(n)
            e[i] = 1.0
            A[:, c] = accel(e, np.zeros(xs.size))
        y = np.zeros(n)
        y[pos] = np.linalg.solve(A, -b)
        return y

    def run(self, t_end, dt=5e-5, x0=None, speed=0.0, force=0.0, amplitude=0.0, frequency_hz=0.0, probe=None,
            every=1, state=None) -> MovingLoadResult:
        """Rail response to ``force + amplitude sin(2π f t)`` [N] at ``x0 + speed t`` [m] (default
        x0: a midspan) from rest or ``state``, as :meth:`ModalTrack.run`."""
        L = self.track.sleeper_spacing
        x0 = 0.5 * L if x0 is None else float(x0)
        probe = x0 if probe is None else float(probe)
        n_steps = int(round(t_end / dt))
        if n_steps < 1 or not math.isfinite(dt) or dt <= 0:
            raise ScenarioError(f"dt: must be positive and below t_end, got {dt!r}")
        y0 = np.zeros(self.n_states) if state is None else np.asarray(state, dtype=float)
        t, wl, wp, y = _ring_run(y0, float(dt), n_steps, x0, float(speed), float(force), float(amplitude),
                                 2 * math.pi * float(frequency_hz), probe, int(every), *self.arrays())
        return MovingLoadResult(t=t, w_load=wl, w_probe=wp, state=y)
