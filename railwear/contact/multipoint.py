"""Several contacts of one wheel sharing its load: Hertz points or semi-Hertzian patches.

The wheel carries the vertical load ``Q`` [N] and sinks by the vertical approach ``δ`` [m]
(common to all its contacts, the rigid-body approach). Contact ``i`` has the vertical gap
``g_i >= 0`` before loading and the contact angle ``γ_i``; its normal penetration is
``(δ - g_i) cos γ_i`` and its normal force ``N_i`` pushes up by ``N_i cos γ_i``. ``δ`` solves

    Σ_i N_i((δ - g_i) cos γ_i) cos γ_i = Q                                  (1)

- multi-Hertz: ``N_i = K_i d^(3/2)`` with Hertz's stiffness of the local curvatures,
  ``K = (4 E* / 3) / (r^(3/2) sqrt(A + B))`` (from ``δ = r [(3N/(4E*))² (A+B)]^(1/3)``); (1) is
  convex and increasing in δ, solved by Newton's method from above (monotone convergence).
- semi-Hertzian: ``N_i`` from :mod:`railwear.contact.semi_hertz` on the separation around
  contact ``i``; contacts whose interpenetration regions ``{g < δ}`` join are one patch, centred
  at the deeper one. (1) is solved by the secant method on its ``2/3`` power inside a bracket.
"""

import numpy as np
from numba import njit

from railwear.contact._checks import as_float_array, non_negative, positive
from railwear.contact.hertz import _mnr_from_ratio, effective_modulus
from railwear.contact.semi_hertz import _crossing, factor_table, patch_kernel
from railwear.errors import ScenarioError

__all__ = ["hertz_stiffness", "share_load", "semi_hertz_share", "SEMI_FIELDS"]

# per-contact outputs of the semi-Hertzian solver (_semi_wheel), in this order
SEMI_FIELDS = ("normal_force", "p0", "half_length", "s_min", "s_max", "area", "centroid", "epsilon", "curvature")


def hertz_stiffness(A, B, youngs_modulus, poisson, youngs_modulus_2=None, poisson_2=None):
    """Hertz's ``K`` [N/m^1.5] with ``N = K d^(3/2)`` (d the normal approach) for the curvatures
    ``A, B`` [1/m] > 0 (module docstring)."""
    A, B = np.broadcast_arrays(positive(A, "A"), positive(B, "B"))
    e_star = effective_modulus(youngs_modulus, poisson, youngs_modulus_2, poisson_2)
    _, _, r = _mnr_from_ratio(np.minimum(A, B) / np.maximum(A, B))
    return (4.0 * e_star / 3.0) / (r**1.5 * np.sqrt(A + B))


@njit(cache=True)
def _share_one(g, K, c, Q):
    """Vertical approach δ [m] of one wheel with contacts (g, K, cos γ) under Q (eq. 1)."""
    n = g.shape[0]
    first = -1
    for i in range(n):
        if np.isfinite(g[i]) and K[i] > 0.0 and (first < 0 or g[i] < g[first]):
            first = i
    if first < 0 or Q <= 0.0:
        return np.nan if Q > 0.0 else 0.0
    # alone, the first contact needs d = (Q / (K c^(5/2)))^(2/3): every other one only adds force
    d = g[first] + (Q / (K[first] * c[first] ** 2.5)) ** (2.0 / 3.0)
    for _ in range(100):
        F = -Q
        dF = 0.0
        for i in range(n):
            if np.isfinite(g[i]) and d > g[i]:
                p = (d - g[i]) * c[i]
                F += K[i] * c[i] * p * np.sqrt(p)
                dF += 1.5 * K[i] * c[i] * c[i] * np.sqrt(p)
        step = F / dF
        d -= step
        if abs(step) <= 1e-15 * d:
            break
    return d


@njit(cache=True)
def _share_many(g, K, c, Q, d):
    for k in range(g.shape[0]):
        d[k] = _share_one(g[k], K[k], c[k], Q[k])


def share_load(gaps, stiffness, cos_angle, load):
    """Multi-Hertz load sharing (eq. 1): ``gaps`` [m] (``inf`` for no contact), ``stiffness``
    [N/m^1.5], ``cos_angle`` [-], shape ``(..., P)``, ``load`` [N] per wheel ``(...)``. Returns
    the vertical approach ``δ`` [m] ``(...)`` and the normal forces ``N_i`` [N] ``(..., P)``;
    ``Σ N_i cos γ_i = Q`` to round-off."""
    g = np.asarray(gaps, dtype=float)
    K, c = (np.broadcast_to(np.asarray(v, dtype=float), g.shape) for v in (stiffness, cos_angle))
    Q = np.broadcast_to(np.asarray(load, dtype=float), g.shape[:-1])
    if np.any(np.isnan(g)) or np.any(g < 0) or np.any(K < 0) or np.any((c <= 0) | (c > 1)) or np.any(Q < 0):
        raise ScenarioError("gaps must be >= 0 (inf for none), stiffness >= 0, cos_angle in (0, 1], load >= 0")
    shape = g.shape
    g2, K2, c2 = (np.ascontiguousarray(v.reshape(-1, shape[-1])) for v in (g, K, c))
    d = np.empty(g2.shape[0])
    _share_many(g2, K2, c2, np.ascontiguousarray(Q.reshape(-1)), d)
    with np.errstate(invalid="ignore"):
        pen = np.clip((d[:, None] - g2) * c2, 0.0, None)
    N = np.where(np.isfinite(g2), K2 * pen**1.5, 0.0)
    return d.reshape(shape[:-1]), N.reshape(shape)


@njit(cache=True)
def _cuts(F, starts, pos, h, P, jl, jr):
    """Watershed between neighbouring contacts: for contact ``i`` (window ``F[i]``, centre node
    ``starts[i]``, lateral position ``pos[i]``, vertical-frame node spacing ``h``) the nodes
    ``jl[i]``, ``jr[i]`` it may use to the left and right: up to the largest separation between
    it and the nearest other contact on that side (-1: the window's end)."""
    n = F.shape[1]
    for i in range(P):
        jl[i] = -1
        jr[i] = -1
        right = np.inf
        left = np.inf
        for m in range(P):
            if m == i or not np.isfinite(pos[m]):
                continue
            d = (pos[m] - pos[i]) / h
            if d > 0.0:
                right = min(right, d)
            elif d < 0.0:
                left = min(left, -d)
        s0 = starts[i]
        if np.isfinite(right) and s0 + int(right) < n:
            best = 0
            for k in range(1, int(right) + 1):
                if F[i, s0 + k] > F[i, s0 + best]:
                    best = k
            jr[i] = best
        if np.isfinite(left) and s0 - int(left) >= 0:
            best = 0
            for k in range(1, int(left) + 1):
                if F[i, s0 - k] > F[i, s0 - best]:
                    best = k
            jl[i] = best


@njit(cache=True)
def _semi_forces(delta, F, starts, h, g, c, A, estar, u, eps_t, ap_t, q, out, jl, jr):
    """Semi-Hertzian patches of one wheel at the vertical approach ``delta`` (each cut at the
    watershed ``jl``, ``jr`` to its neighbours): fills ``out`` (P, SEMI_FIELDS); returns
    Σ N cos γ [N]."""
    P = g.shape[0]
    total = 0.0
    for i in range(P):
        for k in range(out.shape[1]):
            out[i, k] = 0.0
        if not (np.isfinite(g[i]) and delta > g[i]):
            continue
        res = patch_kernel(F[i], starts[i], h[i], A[i], (delta - g[i]) * c[i], estar, u, eps_t, ap_t, q,
                           jl[i], jr[i])
        for k in range(9):
            out[i, k] = res[k]
        total += res[0] * c[i]
    return total


@njit(cache=True)
def _semi_wheel(F, starts, h, g, c, A, pos, hv, Q, estar, u, eps_t, ap_t, cap, out):
    """Solve eq. 1 for one wheel with semi-Hertzian patches (windows ``F``, normal-frame node
    spacing ``h``, vertical-frame ``hv``); returns δ [m] (NaN if ``cap`` carries less than Q)."""
    P = g.shape[0]
    q = np.empty(F.shape[1])
    jl = np.empty(P, dtype=np.int64)
    jr = np.empty(P, dtype=np.int64)
    _cuts(F, starts, pos, hv, P, jl, jr)
    gmin = np.inf
    for i in range(P):
        if np.isfinite(g[i]) and g[i] < gmin:
            gmin = g[i]
    if not np.isfinite(gmin) or Q <= 0.0:
        return np.nan
    target = Q ** (2.0 / 3.0)
    a, b = gmin, cap
    fb = _semi_forces(b, F, starts, h, g, c, A, estar, u, eps_t, ap_t, q, out, jl, jr) ** (2.0 / 3.0) - target
    if fb < 0.0:
        return np.nan
    fa = -target
    # secant steps on the 2/3 power (nearly linear in delta), kept inside the bracket [a, b]
    x0, f0 = a, fa
    x1, f1 = b, fb
    x = b
    for _ in range(200):
        x = x1 - f1 * (x1 - x0) / (f1 - f0) if f1 != f0 else 0.5 * (a + b)
        if not (a < x < b):
            x = 0.5 * (a + b)
        fx = _semi_forces(x, F, starts, h, g, c, A, estar, u, eps_t, ap_t, q, out, jl, jr) ** (2.0 / 3.0) - target
        if fx > 0.0:
            b, fb = x, fx
        else:
            a, fa = x, fx
        x0, f0 = x1, f1
        x1, f1 = x, fx
        if abs(fx) <= 1e-14 * target or b - a <= 1e-15 * b:
            break
    _semi_forces(x, F, starts, h, g, c, A, estar, u, eps_t, ap_t, q, out, jl, jr)
    return x


def semi_hertz_share(s, gap, rolling_curvature, contact_angle, load, youngs_modulus, poisson,
                     youngs_modulus_2=None, poisson_2=None, cap=None):
    """Semi-Hertzian contacts of one wheel from its vertical gap ``gap`` [m] sampled on the
    equally spaced lateral positions ``s`` [m]: every local minimum of the samples is a
    candidate contact (its node the patch centre) with its ``contact_angle`` [rad] and
    ``rolling_curvature`` A [1/m] (arrays over ``s``, read at the minima); ``load`` [N] vertical.
    Returns ``(δ, contacts)``: the vertical approach [m] and a dict of arrays over the minima
    (``index``, ``gap`` and the :data:`SEMI_FIELDS`, zero where a minimum carries nothing). Σ N cos γ = load to 1e-12 relative."""
    s = as_float_array(s, "s")
    g = as_float_array(gap, "gap")
    n = s.size
    A = np.broadcast_to(positive(rolling_curvature, "rolling_curvature"), s.shape)
    gamma = np.broadcast_to(as_float_array(contact_angle, "contact_angle"), s.shape)
    Q = float(non_negative(load, "load"))
    if s.ndim != 1 or g.shape != s.shape or n < 5 or np.any(np.abs(gamma) >= 0.5 * np.pi):
        raise ScenarioError("s and gap must be 1-D of one size (>= 5); contact angles within +-pi/2")
    h = np.diff(s)
    if np.any(h <= 0) or not np.allclose(h, h[0], rtol=1e-9, atol=0.0):
        raise ScenarioError("s must be equally spaced and increasing")
    interior = np.flatnonzero((g[1:-1] <= g[:-2]) & (g[1:-1] < g[2:])) + 1
    index = interior[np.argsort(g[interior], kind="stable")]
    g0 = g - g.min()
    c = np.cos(gamma[index])
    F = np.ascontiguousarray((g0[None, :] - g0[index, None]) * c[:, None])
    estar = float(effective_modulus(youngs_modulus, poisson, youngs_modulus_2, poisson_2))
    cap = float(10.0 * (g0.max() if cap is None else cap))
    out = np.zeros((index.size, len(SEMI_FIELDS)))
    d = _semi_wheel(F, index.astype(np.int64), np.full(index.size, h[0]) / c, g0[index], c,
                    np.ascontiguousarray(A[index], dtype=float), np.ascontiguousarray(s[index]), h[0], Q, estar,
                    *factor_table(), cap, out)
    contacts = {"index": index, "gap": g0[index]}
    contacts.update({name: out[:, k] for k, name in enumerate(SEMI_FIELDS)})
    return d, contacts
