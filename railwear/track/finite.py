"""A finite track of exact beam spans (dynamic stiffness method): the cross-check of the periodic
receptance and its convergence in length.

Each span between nodes (sleepers, the load, response points) is represented by its exact dynamic
stiffness, obtained from the span's transfer matrix ``P = exp(A h)`` (``railwear.track.receptance``):
with nodal displacements ``u = (w, θ)`` and the remaining state ``r``, ``u_b = P_uu u_a + P_ur r_a``
and ``r_b = P_ru u_a + P_rr r_a``, and the end forces ``g_b = G u_b + H r_b``, ``g_a = -(G u_a + H r_a)``
(Euler: ``g = (-EI w''', EI w'')``; Timoshenko: ``g = (κGA (w' - ψ), EI ψ')``). The rail ends at the
first and last sleeper, free. No mesh: the only approximation is the finite length.
"""

from __future__ import annotations

import numpy as np

from railwear.errors import ScenarioError
from railwear.track.model import Track
from railwear.track.receptance import _coordinates, _omega, _span, system_matrix

__all__ = ["finite_track_receptance", "span_dynamic_stiffness"]


def _end_force_maps(track: Track):
    r = track.rail
    EI, S = r.bending_stiffness, r.shear_stiffness
    if track.beam == "euler":
        return np.zeros((2, 2), dtype=complex), np.array([[0.0, -EI], [EI, 0.0]], dtype=complex)
    return np.array([[0.0, -S], [0.0, 0.0]], dtype=complex), np.array([[S, 0.0], [0.0, EI]], dtype=complex)


def span_dynamic_stiffness(track: Track, omega, length: float, foundation=None) -> np.ndarray:
    """Exact dynamic stiffness (n, 4, 4) of a rail span of ``length`` [m], free or on a
    ``foundation`` per metre [N/m², one per frequency]: end forces ``(Q_a, M_a, Q_b, M_b)`` from
    end displacements ``(w_a, θ_a, w_b, θ_b)``."""
    P = _span(system_matrix(track, np.asarray(omega, dtype=float), foundation), length)
    G, H = _end_force_maps(track)
    Puu, Pur, Pru, Prr = P[:, :2, :2], P[:, :2, 2:], P[:, 2:, :2], P[:, 2:, 2:]
    X = np.linalg.inv(Pur)
    K = np.empty(P.shape, dtype=complex)
    K[:, :2, :2] = -G + H @ X @ Puu
    K[:, :2, 2:] = -H @ X
    K[:, 2:, :2] = H @ (Pru - Prr @ X @ Puu)
    K[:, 2:, 2:] = G + H @ Prr @ X
    return K


def finite_track_receptance(track: Track, frequency_hz, position="midspan", response=None, n_sleepers=81):
    """Receptance [m/N] of a finite discrete track of ``n_sleepers`` (the rail free at the outer
    ones), load at ``position`` in the middle bay, ``response`` as in ``receptance`` (positions
    relative to the same sleeper, which is the middle one). Converges to ``receptance`` as the track
    grows (the waves die out along a damped track); costs a dense solve per frequency."""
    if not track.discrete:
        raise ScenarioError("sleeper_spacing: the finite track needs discrete supports")
    if int(n_sleepers) != n_sleepers or n_sleepers < 3:
        raise ScenarioError(f"n_sleepers: must be an integer >= 3, got {n_sleepers!r}")
    omega = _omega(frequency_hz)
    L, n = track.sleeper_spacing, int(n_sleepers)
    middle = (n // 2) * L
    x_load, resp = _coordinates(track, position, response)
    x_load, resp = x_load + middle, resp + middle
    sleepers = np.arange(n) * L
    if np.any((resp < 0) | (resp > sleepers[-1])) or not 0 <= x_load <= sleepers[-1]:
        raise ScenarioError("response: positions must lie on the finite track")
    nodes = np.unique(np.round(np.concatenate([sleepers, [x_load], resp]), 12))
    lengths = np.diff(nodes)
    dof = 2 * nodes.size
    K = np.zeros((omega.size, dof, dof), dtype=complex)
    cache = {}
    for e, h in enumerate(lengths):
        key = round(h, 12)
        if key not in cache:
            cache[key] = span_dynamic_stiffness(track, omega, h)
        K[:, 2 * e:2 * e + 4, 2 * e:2 * e + 4] += cache[key]
    ks = track.support.stiffness(omega) * np.ones_like(omega)
    at_sleeper = np.searchsorted(nodes, np.round(sleepers, 12))
    K[:, 2 * at_sleeper, 2 * at_sleeper] += ks[:, None]
    F = np.zeros((omega.size, dof), dtype=complex)
    F[:, 2 * np.searchsorted(nodes, round(x_load, 12))] = 1.0
    u = np.linalg.solve(K, F[..., None])[..., 0]
    w = u[:, 2 * np.searchsorted(nodes, np.round(resp, 12))]
    if response is None or isinstance(response, str) or np.ndim(response) == 0:
        w = w[:, 0]
    return w[0] if np.ndim(frequency_hz) == 0 else w
