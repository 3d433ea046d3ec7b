"""Vertical receptance of a rail on continuous or periodic discrete supports (wave methods).

The rail's state ``y = (w, θ, ·, ·)`` obeys ``y' = A(ω) y`` between loads: Euler-Bernoulli
``y = (w, w', w'', w''')`` with ``EI w'''' + (k_s' - m ω²) w = q``; Timoshenko ``y = (w, ψ, w', ψ')``
with ``κGA (w'' - ψ') + (m ω² - k_s') w = -q`` and ``EI ψ'' + κGA (w' - ψ) + ρI ω² ψ = 0``
(``k_s'`` the support per metre, zero on a discrete track between sleepers). A unit force at
``x_F`` makes the jump ``y(x_F+) - y(x_F-) = f``: ``Δw''' = 1/EI`` (Euler) or ``Δw' = -1/κGA``
(Timoshenko); a sleeper makes the same jump with the force ``-k_s w``.

Continuous support: the four eigenvectors of ``A``; the two with ``Re μ < 0`` decay to the right of
the load, the other two to the left, and their amplitudes follow from the jump (4×4, exact).
Discrete support (period L): Floquet (Bloch) waves of the cell transfer matrix
``T = P(d) S P(L - d)`` that starts at the load (``P(x) = exp(A x)`` the free span, ``S`` the sleeper
jump, ``d`` the load's distance past the last sleeper); the two with ``|λ| < 1`` carry the response
to the right, the two with ``|λ| > 1`` to the left, and the same 4×4 jump condition gives the exact
response of the infinite periodic track (Mead's periodic-structure method; no smearing, no
truncation). Everything is batched over frequency with numpy.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import expm

from railwear.errors import ScenarioError
from railwear.track.model import Track

__all__ = ["receptance", "load_offset"]


def _omega(frequency_hz) -> np.ndarray:
    f = np.asarray(frequency_hz, dtype=float)
    if f.ndim > 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ScenarioError("frequency_hz: must be a number or 1-D array of finite values >= 0 [Hz]")
    return 2.0 * np.pi * np.atleast_1d(f)


def system_matrix(track: Track, omega: np.ndarray, foundation=None) -> np.ndarray:
    """``A(ω)`` of the rail, shape (n, 4, 4); ``foundation`` the support per metre [N/m²] (complex,
    one per frequency) or None for a free span."""
    r = track.rail
    m, EI, S, J = r.mass_per_metre, r.bending_stiffness, r.shear_stiffness, r.rotary_inertia
    kf = np.zeros_like(omega, dtype=complex) if foundation is None else foundation
    A = np.zeros(omega.shape + (4, 4), dtype=complex)
    if track.beam == "euler":
        A[:, 0, 1] = A[:, 1, 2] = A[:, 2, 3] = 1.0
        A[:, 3, 0] = (m * omega**2 - kf) / EI
    else:
        A[:, 0, 2] = A[:, 1, 3] = 1.0
        A[:, 2, 0] = -(m * omega**2 - kf) / S
        A[:, 2, 3] = 1.0
        A[:, 3, 1] = (S - J * omega**2) / EI
        A[:, 3, 2] = -S / EI
    return A


def _jump_row(track: Track) -> tuple[int, complex]:
    """Index of the state component that jumps under a unit force, and the jump."""
    r = track.rail
    return (3, 1.0 / r.bending_stiffness) if track.beam == "euler" else (2, -1.0 / r.shear_stiffness)


def _sleeper_jump(track: Track, ks: np.ndarray) -> np.ndarray:
    """``S``: the state just after a sleeper from the state just before it (force ``-k_s w``)."""
    row, unit = _jump_row(track)
    S = np.broadcast_to(np.eye(4, dtype=complex), ks.shape + (4, 4)).copy()
    S[:, row, 0] = -ks * unit
    return S


def _span(A: np.ndarray, length: float) -> np.ndarray:
    """``P = exp(A x)``, (n, 4, 4): from the eigen-decomposition of ``A`` (batched), or scipy's
    ``expm`` where the waves are too long for it (``|μ| x < 0.1``: near 0 Hz on a free span)."""
    if length == 0.0:
        return np.broadcast_to(np.eye(4, dtype=complex), A.shape).copy()
    mu, V = np.linalg.eig(A)
    short = np.max(np.abs(mu), axis=-1) * abs(length) < 0.1
    P = np.empty(A.shape, dtype=complex)
    good = ~short
    P[good] = V[good] @ (np.exp(mu[good] * length)[..., None] * np.linalg.inv(V[good]))
    if np.any(short):
        P[short] = expm(A[short] * length)
    return P


def _split_waves(vectors, right_mask):
    """Columns of ``vectors`` (n, 4, 4) sorted into the two right-decaying and two left-decaying waves."""
    order = np.argsort(~right_mask, axis=-1, kind="stable")
    sorted_vecs = np.take_along_axis(vectors, order[:, None, :], axis=-1)
    return sorted_vecs[..., :2], sorted_vecs[..., 2:], order


def _amplitudes(track, right, left):
    """Amplitudes ``a`` (right waves) and ``b`` (left waves) with ``right a - left b = f``."""
    row, unit = _jump_row(track)
    M = np.concatenate([right, -left], axis=-1)
    f = np.zeros(M.shape[:-1], dtype=complex)
    f[:, row] = unit
    c = np.linalg.solve(M, f[..., None])[..., 0]
    return c[:, :2], c[:, 2:]


def load_offset(track: Track, position) -> float:
    """The load's distance past the last sleeper [m], in [0, L): "sleeper" 0, "midspan" L/2, or a
    number of metres from a sleeper (taken modulo L)."""
    if isinstance(position, str):
        if position not in ("sleeper", "midspan"):
            raise ScenarioError(f"position: must be 'midspan', 'sleeper' or metres from a sleeper, got {position!r}")
        if not track.discrete:
            return 0.0
        return 0.0 if position == "sleeper" else 0.5 * track.sleeper_spacing
    x = _finite("position", position)
    if not track.discrete:
        return x
    d = x % track.sleeper_spacing
    return 0.0 if np.isclose(d, track.sleeper_spacing, rtol=0, atol=1e-12) else d


def _coordinates(track, position, response):
    """Load and response coordinates [m] (a sleeper at 0)."""
    x_load = load_offset(track, position) if isinstance(position, str) else _finite("position", position)
    if response is None:
        return x_load, np.array([x_load])
    if isinstance(response, str):
        return x_load, np.array([load_offset(track, response)])
    try:
        resp = np.atleast_1d(np.asarray(response, dtype=float))
    except (TypeError, ValueError):
        raise ScenarioError(f"response: must be a position or 1-D array of positions [m], got {response!r}") from None
    if resp.ndim != 1 or not np.all(np.isfinite(resp)):
        raise ScenarioError("response: must be a position or 1-D array of finite positions [m]")
    return x_load, resp


def _finite(name, value) -> float:
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise ScenarioError(f"{name}: must be 'midspan', 'sleeper' or metres from a sleeper, got {value!r}") from None
    if not np.isfinite(x):
        raise ScenarioError(f"{name}: must be finite, got {value!r}")
    return x


def receptance(track: Track, frequency_hz, position="midspan", response=None) -> np.ndarray:
    """Complex vertical receptance of the rail [m/N]: displacement at ``response`` per unit harmonic
    force at ``position`` (``e^{iωt}`` convention, in phase = positive real part).

    ``position``: "midspan", "sleeper" or metres along the track, with a sleeper at 0 (on a continuous
    track only differences matter). ``response``: None for the point receptance, else a position or
    array of positions [m] in the same coordinate (transfer receptance). Returns shape (n_f,) for a
    point or scalar response, (n_f, n_response) for an array. Exact for the infinite track (module
    docstring); the discrete track needs some damping (a pad or rail loss factor or damper).
    """
    omega = _omega(frequency_hz)
    scalar_f = np.ndim(frequency_hz) == 0
    x_load, x_resp = _coordinates(track, position, response)
    if track.discrete:
        w = _discrete(track, omega, x_load, x_resp)
    else:
        w = _continuous(track, omega, x_resp - x_load)
    if response is None or isinstance(response, str) or np.ndim(response) == 0:
        w = w[:, 0]
    return w[0] if scalar_f else w


def _continuous(track: Track, omega, distance) -> np.ndarray:
    """Continuous support: eigen-waves of ``A`` with the foundation ``k_s'(ω)``; (n_f, n_x)."""
    A = system_matrix(track, omega, track.support.stiffness(omega) * np.ones_like(omega))
    mu, vecs = np.linalg.eig(A)
    right, left, order = _split_waves(vecs, mu.real < 0)
    mu = np.take_along_axis(mu, order, axis=-1)
    a, b = _amplitudes(track, right, left)
    x = np.asarray(distance, dtype=float)[None, :, None]
    out = np.where(
        x >= 0,
        np.sum(right[:, 0, None, :] * a[:, None, :] * np.exp(mu[:, None, :2] * np.maximum(x, 0)), axis=-1)[..., None],
        np.sum(left[:, 0, None, :] * b[:, None, :] * np.exp(mu[:, None, 2:] * np.minimum(x, 0)), axis=-1)[..., None],
    )
    return out[..., 0]


def _discrete(track: Track, omega, d_load, x_resp) -> np.ndarray:
    """Discrete supports at spacing L: Floquet waves of the cell that starts at the load; (n_f, n_x)."""
    L = track.sleeper_spacing
    d = load_offset(track, d_load)
    A = system_matrix(track, omega)
    S = _sleeper_jump(track, track.support.stiffness(omega) * np.ones_like(omega))
    first = _span(A, L - d)  # load to the next sleeper
    T = _span(A, d) @ S @ first
    lam, vecs = np.linalg.eig(T)
    right, left, order = _split_waves(vecs, np.abs(lam) < 1.0)
    lam = np.take_along_axis(lam, order, axis=-1)
    a, b = _amplitudes(track, right, left)
    out = np.empty((omega.size, x_resp.size), dtype=complex)
    for j, x in enumerate(x_resp):
        s = x - d_load  # distance from the load
        n = int(np.floor(s / L + 1e-12))
        delta = max(s - n * L, 0.0)
        if n >= 0:
            start = np.einsum("fij,fj->fi", right, a * lam[:, :2] ** n)
        else:
            start = np.einsum("fij,fj->fi", left, b * lam[:, 2:] ** n)
        if delta <= L - d:
            C = _span(A, delta)
        else:
            C = _span(A, delta - (L - d)) @ S @ first
        out[:, j] = np.einsum("fj,fj->f", C[:, 0, :], start)
    return out
