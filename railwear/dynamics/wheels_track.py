"""Several disk wheels on the ring track: wheels, contacts and track in one compiled RK4 loop.

Identical rigid-rail disk wheels (:class:`~railwear.dynamics.DiskWheelModel`, ``rail_mass=None``)
at ``s_a`` metres behind the first (a bogie ``(0, 2.5)``), each with its own states
``φ_a, Ω_a, z_w,a, z_w,a', z_s,a, z_s,a'``, radius deviation ``u_a`` and phase, roll at ``V`` over
one :class:`~railwear.track.modal.RingTrack`: wheel ``a`` is at ``x_a = x0 - s_a + V t``. Each
contact is :class:`~railwear.dynamics.disk_wheel_track.WheelOnRing`'s,

    δ_a + r k_H δ_a^(3/2) = δ0 - w_m(x_a) - z_w,a + ū_a(x_c,a),     N_a = k_H δ_a^(3/2)

``w_m(x_a)`` the kept modes and the near pads' residual deflection under wheel ``a`` (the rail
carries every wheel's load: its state is absolute), and the track takes every force,
``M_i q̈_i + ... = σ_i ‖b_g‖² P_g + Σ_a φ_i(x_a) N_a`` (``ring_rhs_loads``). The residual
flexibility between two wheels, ``R(s_a - s_b) N_b``, is zero within the model: the wheels must
be further apart than the residual's table (``(n_near // 2 + 1) L`` plus two steps of ``L / 400``,
1.2 m on 0.6 m bays), both along the ring and round it. One wheel is ``WheelOnRing`` bit for bit.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.dynamics import kernels as k
from railwear.dynamics.disk_wheel_track import N_RECORDS, WHEEL_STATES, WheelOnRing, approach
from railwear.errors import ScenarioError
from railwear.track.modal import ring_near, ring_pads, ring_rail_displacement, ring_rhs_loads, ring_shapes

__all__ = ["WheelsOnRing", "wheels_on_ring_run", "force_transfer", "odd_response"]

MAX_WHEELS = 8


@njit(cache=True)
def _derivatives(t, y, p, surf, xs, length, spacing, residual, arrays, scratch, y8, d8, guess, out, rec):
    """``out = dy/dt`` of the wheels and the track (``out`` empty: none); the approaches into
    ``guess``. With ``rec`` non-empty, each wheel's contact outputs into its row (t, N, ξ, π,
    x_c unwrapped, rail under the wheel, z_w, x)."""
    imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, rtab, step = arrays
    phis, nears, weights, pads, forces = scratch
    nw = xs.size
    nm, ns = imass.size, norm.size
    yt = y[nw * WHEEL_STATES:]
    ring_pads(yt, nm, ns, group, sign, tp, pads)
    for a in range(nw):
        pa = p[a]
        o = a * WHEEL_STATES
        ring_shapes(xs[a], length, phis[a])
        ring_near(xs[a], spacing, ns, rtab, step, nears[a], weights[a])
        wm = ring_rail_displacement(yt, phis[a], nears[a], weights[a], pads, basis, 0.0, 0.0)
        r0 = pa[k.DW_RADIUS]
        xc = pa[k.DW_INITIAL_ANGLE] + pa[k.DW_SPEED] / r0 * t + y[o]
        ubar = k.patch_average(surf[a], int(pa[k.DW_N_CELLS]), xc, pa[k.DW_PATCH_HALF_ANGLE])
        normal, d = approach(pa[k.DW_STATIC_APPROACH] - wm - y[o + 2] + ubar, residual, pa[k.DW_HERTZ_CONSTANT],
                             guess[a])
        guess[a] = d
        forces[a] = normal
        for i in range(WHEEL_STATES):
            y8[i] = y[o + i]
        y8[6] = -(wm + residual * normal)
        y8[7] = 0.0
        if rec.size > 0:
            c = k._disk_contact(t, y8, pa, surf[a])
            rec[a, 0] = t
            rec[a, 1] = c[0]
            rec[a, 2] = c[1]
            rec[a, 3] = c[3]
            rec[a, 4] = xc
            rec[a, 5] = wm + residual * normal
            rec[a, 6] = y[o + 2]
            rec[a, 7] = xs[a]
        if out.size > 0:
            k.disk_wheel_rhs(t, y8, pa, surf[a], d8)
            for i in range(WHEEL_STATES):
                out[o + i] = d8[i]
    if out.size > 0:
        ring_rhs_loads(yt, phis, forces, nears, weights, imass, stiff, damp, group, sign, norm, scale, basis, bnorm,
                       tp, pads, out[nw * WHEEL_STATES:])


@njit(cache=True)
def _place(x0, behind, v, t, t0, length, xs):
    """The wheels' positions on the ring [m] at ``t``: ``x0 - s_a + V (t - t0)`` mod ``ℓ``."""
    for a in range(behind.size):
        xs[a] = (x0 - behind[a] + v * (t - t0)) % length


@njit(cache=True)
def wheels_on_ring_run(y0, t0, dt, n_steps, x0, behind, p, surf, energy, every, imass, stiff, damp, group, sign, norm,
                       scale, basis, bnorm, tp, rtab, step, n_near):
    """RK4 from ``y0`` at ``t0`` [s] over ``n_steps`` of ``dt``, wheel ``a`` at
    ``x0 - behind[a] + V (t - t0)`` on the ring (``p[a]``, ``surf[a]`` its parameters and surface
    array); adds each wheel's frictional energy [J] per cell to ``energy[a]`` (empty: none) and
    records the contacts every ``every`` steps (``every <= 0``: none). Returns ``(y, records)``,
    records ``(rows, wheels, N_RECORDS)``."""
    arrays = (imass, stiff, damp, group, sign, norm, scale, basis, bnorm, tp, rtab, step)
    nw = behind.size
    nm, ns = imass.size, norm.size
    length, spacing, residual = tp[6], tp[7], tp[8]
    v = p[0, k.DW_SPEED]
    scratch = (np.empty((nw, nm)), np.empty((nw, n_near), np.int64), np.empty((nw, n_near)), np.empty(2 * ns),
               np.empty(nw))
    y8, d8 = np.zeros(8), np.zeros(8)
    n = y0.size
    y = y0.copy()
    ys = np.empty(n)
    ks = np.empty((4, n))
    n_rec = n_steps // every + 1 if every > 0 else 0
    records = np.empty((n_rec, nw, N_RECORDS))
    rec = np.empty((nw, N_RECORDS))
    none, no_rec = np.empty(0), np.empty((0, N_RECORDS))
    sweep = energy.size > 0
    guess = np.empty(nw)
    xa, pa = np.zeros(nw), np.zeros(nw)
    for a in range(nw):
        guess[a] = p[a, k.DW_STATIC_APPROACH]
    xs = np.empty(nw)
    r = 0
    for i in range(n_steps + 1):
        t = t0 + i * dt
        _place(x0, behind, v, t, t0, length, xs)
        last = i == n_steps
        _derivatives(t, y, p, surf, xs, length, spacing, residual, arrays, scratch, y8, d8, guess,
                     none if last else ks[0], rec)
        for a in range(nw):
            if sweep and i > 0:
                k.sweep(energy[a], xa[a], rec[a, 4], p[a, k.DW_PATCH_HALF_ANGLE], 0.5 * (pa[a] + rec[a, 3]) * dt)
            xa[a], pa[a] = rec[a, 4], rec[a, 3]
        if every > 0 and i % every == 0:
            for a in range(nw):
                for j in range(N_RECORDS):
                    records[r, a, j] = rec[a, j]
                records[r, a, 7] = x0 - behind[a] + v * (t - t0)
            r += 1
        if last:
            break
        for stage in range(1, 4):
            h = dt if stage == 3 else 0.5 * dt
            for j in range(n):
                ys[j] = y[j] + h * ks[stage - 1, j]
            ts = t + h
            _place(x0, behind, v, ts, t0, length, xs)
            _derivatives(ts, ys, p, surf, xs, length, spacing, residual, arrays, scratch, y8, d8, guess, ks[stage],
                         no_rec)
        for j in range(n):
            y[j] += dt / 6.0 * (ks[0, j] + 2.0 * ks[1, j] + 2.0 * ks[2, j] + ks[3, j])
    return y, records


@dataclass(frozen=True, eq=False)
class WheelsOnRing(WheelOnRing):
    """Identical disk wheels ``wheel`` (rigid rail) at ``positions`` (m behind the first: 0, then
    increasing) on ``ring``, RK4 steps of ``dt`` [s] (module docstring). State: each wheel's six,
    then the ring's. Each wheel takes its own parameters (phase) and surface array in
    :meth:`run`; one wheel at ``(0,)`` is :class:`WheelOnRing` bit for bit."""

    positions: tuple = (0.0,)

    def __post_init__(self):
        super().__post_init__()
        x = np.asarray(self.positions, float)
        if (x.ndim != 1 or not 1 <= x.size <= MAX_WHEELS or not np.all(np.isfinite(x)) or x[0] != 0.0
                or np.any(np.diff(x) <= 0)):
            raise ScenarioError(f"positions: 1 to {MAX_WHEELS} wheels' distances behind the first (m), 0 then "
                                f"increasing, got {self.positions!r}")
        ring = self.ring
        reach = ring.rtab.size * ring.step
        gaps = np.diff(np.r_[x, ring.length])
        if x.size > 1 and gaps.min() <= reach:
            raise ScenarioError(f"positions: the wheels must be more than {reach:.3g} m apart along the ring (the "
                                f"residual flexibility's reach) and round it (ring {ring.length:.4g} m), got "
                                f"{self.positions!r}")
        object.__setattr__(self, "behind", x)

    @property
    def n_wheels(self) -> int:
        return self.behind.size

    @property
    def n_states(self) -> int:
        return WHEEL_STATES * self.n_wheels + self.ring.n_states

    def wheel_positions(self, x) -> np.ndarray:
        """The wheels' positions [m] on the ring with the first at ``x``."""
        return (float(x) - self.behind) % self.ring.length

    def static_state(self, x, lift=0.0, models=None) -> np.ndarray:
        """Wheels and track at rest under the static loads, the first wheel at ``x`` [m]: the
        track's static deflection under every wheel (``RingTrack.static_loads``), each wheel and
        frame lowered with the rail under it, ``lift`` [m] (one, or one per wheel) added to the
        wheel, ``Ω`` at the steady creepage from ``models[a].initial_state()`` (default the
        wheel's own)."""
        nw, w = self.n_wheels, self.wheel
        models = [w] * nw if models is None else list(models)
        if len(models) != nw:
            raise ScenarioError(f"models: one per wheel ({nw}), got {len(models)}")
        lifts = np.broadcast_to(np.asarray(lift, float), (nw,))
        xs = self.wheel_positions(x) if nw > 1 else np.array([float(x)])
        loads = np.full(nw, w.static_load)
        y = np.zeros(self.n_states)
        y[nw * WHEEL_STATES:] = self.ring.static_loads(xs, loads)
        for a in range(nw):
            o = a * WHEEL_STATES
            y[o:o + WHEEL_STATES] = models[a].initial_state()[:WHEEL_STATES]
            down = self.rail_under(y, xs[a], loads[a])
            y[o + 2] = -down + lifts[a]
            y[o + 4] = -down
        return y

    def rail_under(self, y, x, force) -> float:
        """Rail displacement [m, down] at ``x`` [m] in the state ``y`` with ``force`` [N] at
        ``x`` (the other wheels' residual reaches no further than their spacing)."""
        return super().rail_under(np.asarray(y)[WHEEL_STATES * (self.n_wheels - 1):], x, force)

    def run(self, y, t0, n_steps, x0, params, surf, energy=None, every=0):
        """``n_steps`` RK4 steps from ``y`` at ``t0`` [s] with the first wheel at ``x0`` [m];
        ``params``, ``surf``: one row per wheel (or one for all); each wheel's frictional energy
        [J] per cell added to ``energy[a]``; records every ``every`` steps, ``(rows, wheels, 8)``
        (``t, N, ξ, π, x_c, rail under the wheel (down), z_w, x``). Returns ``(y, records)``."""
        nw = self.n_wheels
        p = np.ascontiguousarray(np.broadcast_to(np.atleast_2d(np.asarray(params, float)), (nw, k.DW_N_PARAMS)))
        sizes = {np.size(row) for row in (surf if np.ndim(surf[0]) else [surf])}
        if len(sizes) != 1:
            raise ScenarioError("surf: every wheel's surface array on one grid (DiskWheelModel.surface_for)")
        s = np.ascontiguousarray(np.broadcast_to(np.atleast_2d(np.asarray(surf, float)), (nw, sizes.pop())))
        if np.any(p[:, k.DW_SPEED] != p[0, k.DW_SPEED]):
            raise ScenarioError("params: the wheels of one vehicle run at one speed")
        energy = np.zeros((0, 0)) if energy is None else energy
        if energy.ndim == 1:
            energy = energy.reshape(1, -1)  # one wheel's cells, a view: the energy is added to it
        if energy.size and energy.shape[0] != nw:
            raise ScenarioError(f"energy: one row per wheel ({nw}), got {energy.shape}")
        return wheels_on_ring_run(np.asarray(y, float), float(t0), float(self.dt), int(n_steps), float(x0),
                                  self.behind, p, s, energy, int(every), *self.ring.arrays())


def odd_response(dyn, order, which=0, amplitude=1e-6, cells=256, transient=4, revolutions=16, x0=1.0):
    """The wheels' response to ``±amplitude cos(n x)`` [m] of ``order`` on wheel ``which`` alone
    (the others round, every wheel's surface on ``cells`` cells and at the same phase), half the
    difference of the two runs (the sleeper passing and the Hertz square cancel): ``transient``
    revolutions then ``revolutions`` recorded at every step of ``dyn`` (a :class:`WheelsOnRing`;
    ``dt`` should divide a revolution), the first wheel from ``x0`` [m]. Returns ``(force,
    energy, seconds)``: each wheel's normal force per unit filtered deviation ``ū`` [N/m, complex]
    (its component at ``e^{i n x_c}``, ``x_c`` wheel ``which``'s contact angle, over that of
    ``ū = kernels.patch_average`` of the surface at ``x_c``), the frictional energy swept onto
    each wheel's cells [J, ``(wheels, cells)``] and the recorded time [s]."""
    from dataclasses import replace

    base = dyn.wheel
    x = 2 * np.pi * np.arange(cells) / cells
    per = int(round(2 * np.pi * base.radius / (base.speed * (1 + base.steady_creepage())) / dyn.dt))
    flat = replace(base, radius_deviation=0 * x)
    rec, energy = {}, {}
    for sign in (1, -1):
        shaped = replace(base, radius_deviation=sign * amplitude * np.cos(order * x))
        ms = [shaped if a == which else flat for a in range(dyn.n_wheels)]
        p, surf = [m.params() for m in ms], [m.surface() for m in ms]
        t1 = transient * per * dyn.dt
        y, _ = dyn.run(dyn.static_state(x0, 0.0, models=ms), 0.0, transient * per, x0, p, surf)
        energy[sign] = np.zeros((dyn.n_wheels, cells))
        rec[sign] = dyn.run(y, t1, revolutions * per, x0 + base.speed * t1, p, surf, energy[sign], every=1)[1][:-1]
    force = 0.5 * (rec[1][:, :, 1] - rec[-1][:, :, 1])
    angle = rec[1][:, which, 4]
    surf = replace(base, radius_deviation=amplitude * np.cos(order * x)).surface()
    half = base.patch_half_length / base.radius
    ubar = np.array([k.patch_average(surf, cells, float(a), half) for a in angle])
    e = np.exp(-1j * order * angle)
    return ((force * e[:, None]).mean(0) / (ubar * e).mean(), 0.5 * (energy[1] - energy[-1]),
            revolutions * per * dyn.dt)


def force_transfer(dyn, order, which=0, amplitude=1e-6, cells=256, transient=4, revolutions=16, x0=1.0):
    """The wheels' normal forces per unit filtered radius deviation ``ū`` [N/m, complex] of
    ``order`` on wheel ``which`` alone (:func:`odd_response`)."""
    return odd_response(dyn, order, which, amplitude, cells, transient, revolutions, x0)[0]
