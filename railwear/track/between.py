"""The rail between the wheels: its bending modes localised between two wheel contacts.

The wheels of a bogie hold the rail down at their contacts, so the rail between them has bending
modes of its own, the span between two contacts vibrating with little motion under the wheels.
Two views of them:

- :func:`span_modes`: eigenfrequencies [Hz] of the undamped rail span of ``length`` between two
  contacts on the supports inside it (discrete: the rail seats at the offset of the first wheel;
  continuous: the support per metre), from the exact dynamic stiffness of its beam pieces
  (:func:`~railwear.track.finite.span_dynamic_stiffness`), roots of ``det K(ω)`` with the contacts
  as end conditions. ``ends="pinned"``: the contacts hold the rail's displacement only (the rail
  beyond them carries no moment); ``"clamped"``: its rotation too. Without a support they are the
  beam's ``f_n = (β_n L)² / (2π L²) sqrt(EI/m)`` with ``β_n L = nπ`` (pinned) or the roots of
  ``cos βL cosh βL = 1`` (clamped: 4.730, 7.853, 10.996).
- :func:`held_receptance` and :func:`held_modes`: on the infinite damped track, the receptance at
  a point between the wheels with the rail held at the wheel contacts, and its peaks. A unit force
  at ``x`` and contact forces ``P`` (upward on the rail) at the wheels ``x_k`` give
  ``w_k = α(x_k ← x) - Σ_j A_kj P_j = R P_k`` (``A_kj = α(x_k ← x_j)``, ``R`` the wheel and contact
  receptance, 0 for wheels that hold the rail rigidly), so

      α_held(x) = α(x ← x) - aᵀ (A + R I)⁻¹ a,   a_k = α(x_k ← x)

  (reciprocity). The rail beyond the wheels restrains the span's rotation at the contacts in part,
  so these modes lie between the span's pinned and clamped ones.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from railwear.errors import ScenarioError
from railwear.track.finite import span_dynamic_stiffness
from railwear.track.model import Support, Track
from railwear.track.receptance import load_offset, receptance

__all__ = ["localised_modes", "span_modes", "held_receptance", "held_modes", "on_pads", "undamped", "CLAMPED_ROOTS"]

CLAMPED_ROOTS = (4.730040745, 7.853204624, 10.995607838)  # β_n L of cos βL cosh βL = 1 (Blevins 1979, Table 8-1)
ENDS = ("pinned", "clamped")


def undamped(track: Track) -> Track:
    """``track`` without its loss factors and viscous dampers (the eigenproblem's)."""
    s = track.support
    support = replace(s, pad_damping=0.0, pad_loss_factor=0.0, ballast_damping=0.0, ballast_loss_factor=0.0,
                      subgrade_damping=0.0, subgrade_loss_factor=0.0)
    return replace(track, rail=replace(track.rail, loss_factor=0.0), support=support)


def _length(length) -> float:
    L = float(length)
    if not (np.isfinite(L) and 0.1 <= L <= 100.0):
        raise ScenarioError(f"length: the distance between the wheels must be 0.1-100 m, got {length!r}")
    return L


def _span_determinant(track: Track, L: float, ends: str, offset: float, omega) -> np.ndarray:
    """``det K(ω)`` of the held span (rotations scaled by ``L``: a dimensionless matrix's sign)."""
    omega = np.atleast_1d(np.asarray(omega, float))
    if track.discrete:
        seats = np.arange(1, int(np.ceil((L + offset) / track.sleeper_spacing)) + 1) * track.sleeper_spacing - offset
        seats = seats[(seats > 1e-9) & (seats < L - 1e-9)]
        foundation = None
    else:
        seats = np.zeros(0)
        foundation = track.support.stiffness(omega) * np.ones_like(omega)
    nodes = np.concatenate([[0.0], seats, [L]])
    K = np.zeros((omega.size, 2 * nodes.size, 2 * nodes.size), complex)
    for e, h in enumerate(np.diff(nodes)):
        K[:, 2 * e:2 * e + 4, 2 * e:2 * e + 4] += span_dynamic_stiffness(track, omega, h, foundation)
    if seats.size:
        ks = track.support.stiffness(omega) * np.ones_like(omega)
        idx = 2 * np.arange(1, nodes.size - 1)
        K[:, idx, idx] += ks[:, None]
    scale = np.tile([1.0, 1.0 / L], nodes.size)
    K = K * scale[None, :, None] * scale[None, None, :]
    held = [0, 2 * nodes.size - 2] + ([1, 2 * nodes.size - 1] if ends == "clamped" else [])
    keep = np.setdiff1d(np.arange(2 * nodes.size), held)
    K = K[:, keep][:, :, keep]
    return np.linalg.det(K).real


def span_modes(track: Track, length, ends="pinned", count=3, offset=0.5, max_frequency_hz=5000.0,
               step_hz=2.0) -> np.ndarray:
    """The first ``count`` eigenfrequencies [Hz] (up to ``max_frequency_hz``) of the undamped rail
    span of ``length`` [m] between two wheel contacts, ``ends`` "pinned" or "clamped" (module
    docstring); the first contact ``offset`` [m] past a rail seat of a discrete track. Roots of
    ``det K`` bracketed on a grid of ``step_hz`` and refined to 1e-10 relative; a sign change at a
    pole of ``K`` (a support's or a piece's own resonance) is not a root and is left out."""
    if ends not in ENDS:
        raise ScenarioError(f"ends: must be one of {', '.join(ENDS)}, got {ends!r}")
    L, t = _length(length), undamped(track)
    f = np.arange(step_hz, max_frequency_hz + step_hz, step_hz)

    def det(x):
        return _span_determinant(t, L, ends, float(offset), 2 * np.pi * np.atleast_1d(x))

    from scipy.optimize import brentq  # here, not at import (0.1 s)

    d = det(f)
    roots = []
    for i in np.flatnonzero(np.sign(d[:-1]) * np.sign(d[1:]) < 0):
        root = brentq(lambda x: det(x)[0], f[i], f[i + 1], xtol=1e-12, rtol=1e-12)
        if abs(det(root)[0]) <= min(abs(d[i]), abs(d[i + 1])):  # a pole ends with |det| large
            roots.append(root)
        if len(roots) == count:
            break
    return np.array(roots)


def held_receptance(track: Track, positions, frequency_hz, response, offset="midspan",
                    wheel_receptance=0.0) -> np.ndarray:
    """Receptance [m/N] at ``response`` (m from the first wheel; one or an array) of the infinite
    ``track`` held by wheels at ``positions`` (m from the first), the first at ``offset`` (past a
    sleeper: "midspan", "sleeper" or metres); ``wheel_receptance`` ``R`` [m/N] of each wheel and
    its contact (0: rigid; a number, one per frequency, or a function of the frequencies [Hz]). ``(len(f), len(response))``, complex."""
    x0 = load_offset(track, offset) if isinstance(offset, str) else float(offset)
    x = x0 + np.atleast_1d(np.asarray(positions, float))
    r = x0 + np.atleast_1d(np.asarray(response, float))
    f = np.atleast_1d(np.asarray(frequency_hz, float))
    A = np.stack([receptance(track, f, float(xk), response=x) for xk in x], axis=-1)  # A[:, j, k] = α(x_j ← x_k)
    R = wheel_receptance(f) if callable(wheel_receptance) else wheel_receptance
    A = A + np.asarray(R, complex).reshape(-1, 1, 1) * np.eye(x.size)
    out = np.empty((f.size, r.size), complex)
    for i, ri in enumerate(r):
        a = receptance(track, f, float(ri), response=x)
        out[:, i] = receptance(track, f, float(ri)) - np.einsum("fk,fk->f", a, np.linalg.solve(A, a[..., None])[..., 0])
    return out


HELD_POINTS = (0.15, 0.3, 0.5)  # response points, fractions of the span: none a node of its first three modes


def held_modes(track: Track, length, count=3, offset="midspan", wheel_receptance=0.0, low_hz=20.0,
               high_hz=3000.0, step_hz=2.0) -> np.ndarray:
    """The first ``count`` peaks [Hz] of ``Σ |α_held|`` over points at :data:`HELD_POINTS` of the
    span between two wheels ``length`` [m] apart (:func:`held_receptance`), found on a grid of
    ``step_hz`` from ``low_hz`` to ``high_hz`` and refined to 1e-3 Hz between its neighbours."""
    L = _length(length)
    points = np.asarray(HELD_POINTS) * L

    def level(f):
        return np.abs(held_receptance(track, (0.0, L), f, points, offset, wheel_receptance)).sum(axis=1)

    f = np.arange(low_hz, high_hz + step_hz, step_hz)
    y = level(f)
    peaks = np.flatnonzero((y[1:-1] > y[:-2]) & (y[1:-1] >= y[2:])) + 1
    from scipy.optimize import minimize_scalar  # here, not at import

    out = [minimize_scalar(lambda v: -level(np.array([v]))[0], bounds=(f[k - 1], f[k + 1]), method="bounded",
                           options={"xatol": 1e-3}).x for k in peaks[:count]]
    return np.array(out)


def on_pads(track: Track) -> Track:
    """``track`` with its rail on the pads on a rigid base: the support above the resonances of its
    sleepers or slab (the slab set's near 80 Hz, a ballasted sleeper's near 200 Hz), where the
    masses below the pads barely move; the span's bending modes without the roots of those masses."""
    s = track.support
    return replace(track, support=Support(pad_stiffness=s.pad_stiffness, pad_damping=s.pad_damping,
                                          pad_loss_factor=s.pad_loss_factor))


def localised_modes(track: Track, length, count=3, offset="midspan", wheel_receptance=0.0) -> dict:
    """The rail's first ``count`` bending modes between two wheels ``length`` [m] apart, [Hz]:
    ``"pinned"`` and ``"clamped"`` (:func:`span_modes` of the rail on its pads, :func:`on_pads`),
    the bounds, and ``"held"``, the peak of the held rail on the whole damped track
    (:func:`held_modes`' level) between 0.9 × pinned and 1.1 × clamped, NaN where there is none
    (the mode radiates past the wheels without a peak)."""
    x0 = load_offset(track, offset) if isinstance(offset, str) else float(offset)
    span = on_pads(track)
    pinned, clamped = (span_modes(span, length, ends, count, offset=x0) for ends in ENDS)
    L = _length(length)
    points = np.asarray(HELD_POINTS) * L

    def level(f):
        return np.abs(held_receptance(track, (0.0, L), f, points, offset, wheel_receptance)).sum(axis=1)

    from scipy.optimize import minimize_scalar  # here, not at import

    held = np.full(len(pinned), np.nan)
    for n, (lo, hi) in enumerate(zip(0.9 * pinned, 1.1 * clamped[:len(pinned)])):
        f = np.linspace(lo, hi, 201)
        y = level(f)
        k = int(np.argmax(y))
        if 0 < k < f.size - 1:
            held[n] = minimize_scalar(lambda v: -level(np.array([v]))[0], bounds=(f[k - 1], f[k + 1]),
                                      method="bounded", options={"xatol": 1e-3}).x
    return {"pinned": pinned, "clamped": clamped, "held": held}
