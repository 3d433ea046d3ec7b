"""Semi-Hertzian normal contact of one patch: Kik-Piotrowski's scheme with a Hertz-matched
virtual penetration.

The patch lies in the tangent plane at the point of largest interpenetration (``s = 0``, the
lateral coordinate ``s`` across rolling, ``x`` along rolling). The undeformed separation across
the patch is ``f(s)`` (``f(0) = 0``, sampled on a uniform grid with a node at ``s = 0``) and along
rolling ``A x²`` (``A = cos δ / (2 r)`` of the wheel). Under the mutual approach ``δ`` (Kik &
Piotrowski 1996; Piotrowski & Kik, VSD 46 (2008) 27):

1. the patch is the interpenetration region at a *virtual* penetration ``ε δ``: strip ``s`` has
   the half-length ``L(s) = sqrt((ε δ - f(s)) / A')``;
2. the pressure is semi-elliptic along rolling on every strip,
   ``p(x, s) = P sqrt(L(s)² - x²)`` (so ``p(0, s) ∝ L(s)``);
3. ``P`` follows from the elastic displacement at the point of largest interpenetration being the
   approach, ``δ = (1 / (π E*)) ∬ p / sqrt(x² + s²) dx ds`` (Boussinesq), hence
   ``N = P ∫ π L² / 2 ds``, no iteration.

Kik and Piotrowski take ``ε = 0.55`` and ``A' = A`` for every patch, which reproduces Hertz's
circle only roughly (``ε = 0.5`` would be exact for it) and not the ellipse's aspect ratio.
railwear takes ``ε`` and ``A'`` from Hertz's solution of the curvatures ``A`` and ``B_eff`` as
STRIPES does (Ayasse & Chollet, VSD 43 (2005) 161: local Hertz quantities correct the
interpenetration region), so that a quadric separation ``f = B s²`` gives Hertz's ellipse and
pressure exactly: ``ε = b_H² B / δ = g_b² / (r (1 + A/B))`` and ``A' = ε δ / a_H² = B (g_b / g_a)²``
(``g_a, g_b`` the Hertz semi-axes along ``x`` and ``s`` over ``[3N / (4E*(A+B))]^(1/3)``, ``r`` the
approach coefficient; the circle gives ``ε = 1/2``, ``A' = A``). The lateral curvature is the
interpenetration region's own, ``B_eff = δ / w²`` with ``w`` the half-width of ``{f < δ}``
(``B`` itself for a quadric; positive for a conformal, flat or hollow gap, where Hertz has none).

The inner integral along rolling is closed-form,
``∫ sqrt(L² - x²) / sqrt(x² + y²) dx = 2 sqrt(L² + y²) (K(m) - E(m))``, ``m = L² / (L² + y²)``
(complete elliptic integrals, arithmetic-geometric mean); its logarithmic singularity at
``y = 0`` is integrated analytically on the two intervals next to it.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.contact._checks import non_negative, positive
from railwear.contact.hertz import _mnr_from_ratio, effective_modulus
from railwear.errors import ScenarioError

__all__ = ["SemiHertzContact", "semi_hertz_contact", "hertz_matched_factors", "patch_strips", "STRIPS"]

STRIPS = 32  # strips per patch that the contact tables store (patch_strips)

_Q_MAX = 1e5  # tabulated range of A / B_eff: [1/_Q_MAX, _Q_MAX]
_Q_NODES = 4001


def _factor_table():
    """ε and A'/B over u = ln(A/B) on a uniform grid (Hertz's m, n, r)."""
    u = np.linspace(-np.log(_Q_MAX), np.log(_Q_MAX), _Q_NODES)
    q = np.exp(u)
    m, n, r = _mnr_from_ratio(np.minimum(q, 1.0 / q))
    ga = np.where(q <= 1.0, m, n)  # semi-axis along the curvature A (rolling)
    gb = np.where(q <= 1.0, n, m)
    return u, gb**2 / (r * (1.0 + q)), (gb / ga) ** 2


_TABLE = []  # (u, ε, A'/B) once a contact needs it: 4001 Hertz solutions cost 0.1-0.25 s at import


def factor_table():
    """The table of :func:`_factor_table`, computed on first use."""
    if not _TABLE:
        _TABLE.extend(_factor_table())
    return tuple(_TABLE)


def __getattr__(name):  # the table's arrays by their former names (_U, _EPS, _APRIME), computed on first use
    if name in ("_U", "_EPS", "_APRIME"):
        return factor_table()[("_U", "_EPS", "_APRIME").index(name)]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


@njit(cache=True)
def _factors(A, B, u, eps_t, ap_t):
    """(ε, A') for the curvatures A, B > 0 by linear interpolation in ln(A/B) (clamped)."""
    x = np.log(A / B)
    return np.interp(x, u, eps_t), B * np.interp(x, u, ap_t)


def hertz_matched_factors(A, B):
    """Virtual-penetration ratio ε [-] and corrected rolling curvature A' [1/m] for the
    curvatures A, B [1/m] (module docstring; 0.5 and A for the circle)."""
    A, B = positive(A, "A"), positive(B, "B")
    A, B = np.broadcast_arrays(A, B)
    table = factor_table()
    out = np.array([_factors(a, b, *table) for a, b in zip(A.ravel(), B.ravel())]).reshape(A.shape + (2,))
    return out[..., 0], out[..., 1]


@njit(cache=True, inline="always")
def _k_minus_e(m):
    """K(m) - E(m) of parameter m in [0, 1) (arithmetic-geometric mean)."""
    a = 1.0
    b = np.sqrt(1.0 - m)
    c2 = m
    total = 0.5 * c2
    power = 0.5
    for _ in range(40):
        an = 0.5 * (a + b)
        c = 0.5 * (a - b)
        b = np.sqrt(a * b)
        a = an
        power *= 2.0
        total += power * c * c
        if c * c < 1e-17 * a * a:
            break
    K = 0.5 * np.pi / a
    return K * total


@njit(cache=True, inline="always")
def _strip(L, y):
    """``∫_{-L}^{L} sqrt(L² - x²) / sqrt(x² + y²) dx`` [m] for y != 0."""
    if L <= 0.0:
        return 0.0
    rho2 = L * L + y * y
    return 2.0 * np.sqrt(rho2) * _k_minus_e(L * L / rho2)


_G1 = 0.5 - 0.5 / np.sqrt(3.0)  # two-point Gauss-Legendre nodes on [0, 1]
_G2 = 0.5 + 0.5 / np.sqrt(3.0)
_LOG_NODES = np.array([0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970262])
_LOG_WEIGHTS = np.array([0.1739274225687269, 0.3260725774312731, 0.3260725774312731, 0.1739274225687269])


@njit(cache=True)
def _side_integrals(q, h, sign, j_end, t_end):
    """Integrals over one side (``sign`` +1 right of s = 0, -1 left) of the virtual region:
    (∫ q ds, ∫ s q ds, ∫ 2 sqrt(q) ds, ∫ I(sqrt q, s) ds) with ``q = L²`` at the nodes
    ``0, sign, 2 sign ... j_end`` and zero at ``t_end`` (the crossing, ``j_end < t_end <= j_end + 1``
    in nodes). The interval next to s = 0 takes out ``2 L ln(1/|s|)`` analytically."""
    load = 0.0
    moment = 0.0
    area = 0.0
    disp = 0.0
    for j in range(j_end + 1):
        q0 = q[j]
        if j < j_end:
            q1 = q[j + 1]
            width = h
        else:
            q1 = 0.0
            width = (t_end - j_end) * h
        if width <= 0.0:
            continue
        s0 = j * h
        load += 0.5 * width * (q0 + q1)
        moment += sign * width * (q0 * (s0 + width / 3.0) + q1 * (s0 + 2.0 * width / 3.0)) * 0.5
        # ∫ sqrt(q) over the interval, q linear: exact
        if q0 + q1 > 0.0:
            area += 2.0 * width * (2.0 / 3.0) * (q0 * np.sqrt(q0) - q1 * np.sqrt(q1)) / (q0 - q1) if abs(q0 - q1) > 1e-14 * (q0 + q1) else 2.0 * width * np.sqrt(q0)
        if j == 0:
            # I(L, s) = 2 L ln(1/s) + R(L, s), R bounded; L linear in s on the interval
            L0 = np.sqrt(q0)
            L1 = np.sqrt(q1)
            lw = np.log(width)
            disp += 2.0 * (L0 * width * (1.0 - lw) + (L1 - L0) * width * (0.25 - 0.5 * lw))
            for k in range(4):
                t = _LOG_NODES[k]
                s = t * width
                L = np.sqrt(q0 + (q1 - q0) * t)
                linear = L0 + (L1 - L0) * t
                disp += _LOG_WEIGHTS[k] * width * (_strip(L, s) - 2.0 * linear * np.log(1.0 / s))
        else:
            for t in (_G1, _G2):
                s = s0 + t * width
                disp += 0.5 * width * _strip(np.sqrt(max(q0 + (q1 - q0) * t, 0.0)), s)
    return load, moment, area, disp


@njit(cache=True)
def _crossing(f, level, j, sign, start):
    """Fractional node count from ``start`` (f[start] = 0) to where f rises to ``level`` on one
    side, marching by ``sign``; ``j`` nodes available. Returns (last node below, crossing)."""
    k = 0
    while k < j and f[start + sign * (k + 1)] < level:
        k += 1
    if k >= j:
        return k, float(k)
    fa = f[start + sign * k]
    fb = f[start + sign * (k + 1)]
    return k, k + (level - fa) / (fb - fa)


@njit(cache=True)
def patch_kernel(f, start, h, A, approach, estar, u, eps_t, ap_t, q, jl=-1, jr=-1):
    """One semi-Hertzian patch for the approach ``approach`` [m] (module docstring): separation
    ``f`` [m] on nodes of spacing ``h`` [m], node ``start`` at s = 0 (f = 0); ``q`` a work array of
    f's size; ``jl``, ``jr`` the nodes available left and right of ``start`` (the patch is cut
    there, at the watershed to a neighbouring contact; -1: to the ends of ``f``). Returns (N [N], p0 [Pa], largest half-length [m], lateral lower and upper edge
    s [m], area [m²], load centroid s [m], ε, B_eff [1/m])."""
    n = f.shape[0]
    if approach <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    if jr < 0:
        jr = n - 1 - start
    if jl < 0:
        jl = start
    _, cr = _crossing(f, approach, jr, 1, start)
    _, cl = _crossing(f, approach, jl, -1, start)
    half = 0.5 * (cr + cl) * h
    B = approach / (half * half)
    eps, Ap = _factors(A, B, u, eps_t, ap_t)
    level = eps * approach
    kr, tr = _crossing(f, level, jr, 1, start)
    kl, tl = _crossing(f, level, jl, -1, start)
    for k in range(kr + 1):
        q[k] = (level - f[start + k]) / Ap
    lr, mr, ar, dr = _side_integrals(q, h, 1.0, kr, tr)
    for k in range(kl + 1):
        q[k] = (level - f[start - k]) / Ap
    ll, ml, al, dl = _side_integrals(q, h, -1.0, kl, tl)
    load_shape = 0.5 * np.pi * (lr + ll)
    P = np.pi * estar * approach / (dr + dl)
    N = P * load_shape
    L0 = np.sqrt(level / Ap)
    Lmax = L0
    for k in range(kr + 1):
        Lmax = max(Lmax, np.sqrt(max((level - f[start + k]) / Ap, 0.0)))
    for k in range(kl + 1):
        Lmax = max(Lmax, np.sqrt(max((level - f[start - k]) / Ap, 0.0)))
    centroid = (mr + ml) / (lr + ll)
    return N, P * L0, Lmax, -tl * h, tr * h, ar + al, centroid, eps, B


@njit(cache=True)
def patch_strips(f, start, h, A, approach, epsilon, curvature, s_min, s_max, u, eps_t, ap_t, L):
    """The patch of ``patch_kernel`` (same ``f``, ``start``, ``h``, ``A``, ``approach``; its
    ``ε``, ``B_eff`` and lateral edges ``s_min``, ``s_max``) resampled as ``L.size`` strips of
    equal width across it: fills ``L`` with the half-lengths ``sqrt((ε δ - f(s)) / A')`` at the
    strip centres ``s_min + (k + 1/2) (s_max - s_min) / L.size`` (``f`` linear between its
    nodes). Returns the strip width [m]."""
    ns = L.shape[0]
    width = (s_max - s_min) / ns
    _, Ap = _factors(A, curvature, u, eps_t, ap_t)
    level = epsilon * approach
    n = f.shape[0]
    for k in range(ns):
        pos = start + (s_min + (k + 0.5) * width) / h
        j = min(max(int(np.floor(pos)), 0), n - 2)
        w = pos - j
        fs = (1.0 - w) * f[j] + w * f[j + 1]
        L[k] = np.sqrt(max(level - fs, 0.0) / Ap)
    return width


@dataclass(frozen=True)
class SemiHertzContact:
    """One semi-Hertzian patch, SI units: normal_force [N], approach δ [m], p0 pressure at
    s = 0 [Pa], half_length the largest strip half-length along rolling [m], s_min, s_max its
    lateral edges [m], area [m²], centroid the load centroid s [m], epsilon the virtual
    penetration ratio [-], curvature B_eff [1/m]; ``a``, ``b`` the equivalent ellipse (b half the
    width, a = area / (π b))."""

    normal_force: float
    approach: float
    p0: float
    half_length: float
    s_min: float
    s_max: float
    area: float
    centroid: float
    epsilon: float
    curvature: float

    @property
    def b(self):
        return 0.5 * (self.s_max - self.s_min)

    @property
    def a(self):
        return self.area / (np.pi * self.b)


def _prepare(s, f):
    s = np.asarray(s, dtype=float)
    f = np.asarray(f, dtype=float)
    if s.ndim != 1 or s.shape != f.shape or s.size < 5 or not np.all(np.isfinite(f)):
        raise ScenarioError("s and f must be 1-D arrays of the same size (at least 5), f finite")
    h = np.diff(s)
    if np.any(h <= 0) or not np.allclose(h, h[0], rtol=1e-9, atol=0.0):
        raise ScenarioError("s must be equally spaced and increasing")
    start = int(np.argmin(f))
    return np.ascontiguousarray(f - f[start]), start, float(h[0])


def semi_hertz_contact(s, f, A, normal_force, youngs_modulus, poisson, youngs_modulus_2=None, poisson_2=None,
                       approach=None):
    """Semi-Hertzian patch (module docstring) of the separation ``f`` [m] across rolling, sampled
    at the equally spaced lateral positions ``s`` [m] (the patch centred at the smallest sample;
    let a node lie at the minimum), the rolling curvature ``A`` [1/m] and the normal force [N]
    (or, instead, a given ``approach`` [m]). The approach for a force is found by the secant
    method on ``N^(2/3)`` (nearly linear in δ), to 1e-12 relative."""
    f, start, h = _prepare(s, f)
    A = float(positive(A, "A"))
    estar = float(effective_modulus(youngs_modulus, poisson, youngs_modulus_2, poisson_2))
    q = np.empty(f.size)

    def evaluate(d):
        return patch_kernel(f, start, h, A, d, estar, *factor_table(), q)

    if approach is None:
        load = float(non_negative(normal_force, "normal_force"))
        d = _solve_approach(evaluate, load, np.percentile(f[f > 0], 5) if np.any(f > 0) else h)
    else:
        d = float(positive(approach, "approach"))
    out = evaluate(d)
    return SemiHertzContact(out[0], d, out[1], out[2], out[3], out[4], out[5], out[6], out[7], out[8])


def _solve_approach(evaluate, load, guess):
    """δ with N(δ) = load: secant on N^(2/3) - load^(2/3), bracketed."""
    if load == 0.0:
        return 0.0
    target = load ** (2.0 / 3.0)
    d0, d1 = guess, 2.0 * guess
    g0 = evaluate(d0)[0] ** (2.0 / 3.0) - target
    g1 = evaluate(d1)[0] ** (2.0 / 3.0) - target
    for _ in range(100):
        if g1 == g0:
            break
        d2 = d1 - g1 * (d1 - d0) / (g1 - g0)
        if d2 <= 0.0:
            d2 = 0.5 * d1
        d0, g0 = d1, g1
        d1 = d2
        g1 = evaluate(d1)[0] ** (2.0 / 3.0) - target
        if abs(d1 - d0) <= 1e-12 * d1:
            break
    return d1
