"""Non-steady (transient) rolling contact, linearised about steady rolling, per harmonic.

A polygon of order ``n`` passes the patch (half-length ``a``, half-width ``b``) at the wavenumber
``k = n / R0``; everything below depends on ``κ = k a = n a / R0`` (and ``a / b``), not on the
speed: the material crosses the patch in ``2a / V`` while the wave passes at ``ω = k V``. ``x``
runs along rolling, material enters at ``x = +a(y)`` and leaves at ``x = -a(y)``,
``a(y) = a sqrt(1 - y²/b²)``. Two creepage inputs, both time-harmonic (``e^{iωt}``):

* uniform, ``ξ̂_u`` over the whole patch (the wheel's spin following the creep force: Knothe &
  Gross-Thebing, Vehicle System Dynamics 15 (1986) 133, and Gross-Thebing, VSD 18 (1989) 359,
  frequency-dependent creep coefficients);
* material, ``ξ̂_m e^{ikx}``: the rolling-radius creepage ``Ω0 u / V`` belongs to the wheel's
  material points (a higher spot rolls with more creepage) and travels through the patch with
  them; its value at the patch centre is ``ξ̂_m``.

For each, relative to the steady value of the same amplitude (all ``1`` at ``κ = 0``):
``force_*`` the creep force, ``dissipation_*`` the frictional power, and ``wear_*`` the
frictional power as the energy law lays it on the wheel's material (order-``n`` component of the
deposit, phase referred to the patch centre). In the linear theory (creep force well below
``μN``) the tangential traction sticks over the patch and slips only at the trailing edge, so the
power is dissipated there and worn off the material leaving the patch: the deposit of the strip
at ``y`` carries ``e^{+iκ(y)}``, ``κ(y) = k a(y)``. The quasi-steady model of
:mod:`railwear.longterm.fourier` instead spreads every perturbation evenly over the patch
(``sinc κ`` in, ``sinc κ`` out).

Two theories:

``"simplified"``: Kalker's simplified theory (the elastic layer of FASTSIM: traction
``p = δ / L`` from the local displacement ``δ``, one flexibility ``L``) run non-steadily, strip by
strip, in closed form (Kalker, Three-dimensional elastic bodies in rolling contact, 1990, ch. 3;
the transient form as in Alonso & Giménez, VSD 46 (2008) 179). A bristle entering at ``a_s``
accumulates ``δ = ∫ V ξ dt`` along its path; with ``ζ = (a_s - x) / a_s``, ``κ_s = k a_s``:

    force_uniform  = (1/2) ∫_0^2 (1 - e^{-iκ_s ζ}) / (iκ_s) dζ / 1
                   = [1 - (1 - e^{-2iκ_s}) / (2iκ_s)] / (iκ_s)
    force_material = (1/2) ∫_0^2 ζ e^{iκ_s (1 - ζ)} dζ
    dissipation    = (trailing-edge bristle) uniform (1 - e^{-2iκ_s}) / (2iκ_s), material e^{-iκ_s}
    wear           = dissipation e^{iκ_s}:  uniform sin κ_s / κ_s,  material 1 (no filter at all)

averaged over the strips with the steady weight ``a_s² ∝ 1 - y²/b²`` (force and power per strip).

``"halfspace"``: Kalker's exact linear theory on the half-space grid of
:mod:`railwear.contact.rolling` (Cerruti's influence of both quasi-identical bodies), run
non-steadily: with the time step ``dx / V`` of Kalker's transient scheme the slip of element
``i`` is ``ŝ_i = ŵ_i + (û_i - e^{-ik dx} û_{i+1}) / dx`` (``û = A p̂``, ``i + 1`` the element
upstream, inside or outside the patch), and full adhesion ``ŝ = 0`` on the patch gives ``p̂``.
The dissipation follows from the energy balance ``D = -V ∫ p·w - dE/dt``, ``E = ½ ∫ p·A p``
(``∫ p ∂(A p)/∂x = 0`` for the continuum), and it is laid on the material leaving each strip's
trailing edge in proportion to the strip's energy release ``p_te² `` (the square of the trailing
element's traction, the stress-intensity's); the two estimates of the total (global balance and
``Σ 2 p0_te p̂_te``) agree within 2 % in amplitude and 6° in phase up to ``κ = 1.5`` (tests). Tabulated on ``κ = 0, 0.1, ...`` and
interpolated (cubic, complex).

Sources of the numbers: none of the published curves (Knothe & Gross-Thebing's magnitude and
phase of ``C11(ω)``) were at hand; the half-space theory is computed here, checked in its steady
limit against Kalker's ``C11`` and in its energy balance, and the simplified theory is closed form.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from railwear.contact.halfspace import tangential_influence_coefficients
from railwear.errors import ScenarioError

__all__ = ["TransientContact", "simplified_transfer", "halfspace_transfer", "FACTORS"]

FACTORS = ("force_uniform", "force_material", "dissipation_uniform", "dissipation_material", "wear_uniform",
           "wear_material")
_LEG = np.polynomial.legendre.leggauss(48)


def _kappa(kappa):
    k = np.asarray(kappa, float)
    if not np.all(np.isfinite(k)) or np.any(k < 0):
        raise ScenarioError("kappa: the wavenumber times the patch half-length must be finite and >= 0")
    return k


def _strip_mean(f, kappa):
    """``∫_{-1}^{1} (1 - η²) f(κ sqrt(1 - η²)) dη / (4/3)`` for each ``κ`` (Gauss-Legendre, 48)."""
    eta, w = _LEG
    root = np.sqrt(1.0 - eta**2)
    vals = f(np.multiply.outer(np.atleast_1d(kappa), root))
    return (vals * (w * root**2)).sum(-1) * 0.75


def _strip_simplified(ks):
    """Closed forms of the simplified theory on one strip at ``κ_s`` (module docstring)."""
    ks = np.asarray(ks, float)
    small = ks < 1e-4
    z = 1j * np.where(small, 1.0, ks)
    e2 = np.exp(-2 * z)
    relax = np.where(small, 1 - 1j * ks - 2 * ks**2 / 3, (1 - e2) / (2 * z))  # (1 - e^{-2iκ})/(2iκ)
    fu = np.where(small, 1 - 2j * ks / 3, (1 - relax) / z)
    # (1/2) ∫_0^2 ζ e^{iκ(1-ζ)} dζ, by parts; the series where κ is small
    fm = np.where(small, 1 - 1j * ks / 3,
                  0.5 * np.exp(z) * ((1 - e2 * (1 + 2 * z)) / z**2))
    return {"force_uniform": fu, "force_material": fm, "dissipation_uniform": relax,
            "dissipation_material": np.exp(-1j * ks), "wear_uniform": relax * np.exp(1j * ks),
            "wear_material": np.ones_like(relax)}


def simplified_transfer(kappa) -> dict:
    """Kalker's simplified theory, non-steady, over an elliptical patch: the :data:`FACTORS` at
    ``kappa`` (``k a``), complex, 1 at ``κ = 0``; independent of ``a / b`` (module docstring)."""
    k = _kappa(kappa)
    out = {name: _strip_mean(lambda x, name=name: _strip_simplified(x)[name], k) for name in FACTORS}
    return {name: (v if np.ndim(kappa) else v[0]) for name, v in out.items()}


@lru_cache(maxsize=8)
def _halfspace_grid(aspect, nx, poisson):
    """The patch of half-length 1 and half-width ``1/aspect`` on ``nx`` elements along rolling:
    centres, the influence rows at each element and at its upstream neighbour, trailing elements."""
    a, b = 1.0, 1.0 / aspect
    dx = 2 * a / nx
    ns = max(4, int(round(2 * b / dx)))
    ds = 2 * b / ns
    x = -a + dx * (np.arange(nx) + 0.5)
    s = -b + ds * (np.arange(ns) + 0.5)
    on = (x[:, None] / a) ** 2 + (s[None, :] / b) ** 2 < 1.0
    ii, jj = np.nonzero(on)
    m = ii.size
    xe = np.concatenate([x[ii], x[ii] + dx])
    se = np.concatenate([s[jj], s[jj]])
    axx, axy, ayy = tangential_influence_coefficients(xe[:, None] - x[ii][None, :], se[:, None] - s[jj][None, :],
                                                       dx, ds, 1.0, poisson)
    own = np.block([[axx[:m], axy[:m]], [axy[:m], ayy[:m]]])
    upstream = np.block([[axx[m:], axy[m:]], [axy[m:], ayy[m:]]])
    strips = np.unique(jj)
    trailing = np.array([np.flatnonzero(jj == j)[np.argmin(ii[jj == j])] for j in strips])
    half = np.sqrt(np.maximum(0.0, 1.0 - (s[strips] / b) ** 2))  # a(y)/a of each strip
    return dx, dx * ds, x[ii], own, upstream, trailing, half


def halfspace_transfer(kappa, aspect=1.0, nx=16, poisson=0.28) -> dict:
    """Kalker's exact linear theory, non-steady, on the half-space grid (module docstring): the
    :data:`FACTORS` at each ``kappa`` (``k a``) for a patch of ``aspect`` ``a / b`` on ``nx``
    elements along rolling, plus ``"c11"`` (Kalker's ``C11`` of the grid's steady
    solution, ``-F / (G a b ξ)``) and ``"dissipation_local"``
    (the material dissipation from the trailing elements, ``Σ 2 p0 p̂ / Σ 2 p0²``)."""
    if not (np.isfinite(aspect) and 0.05 <= aspect <= 20):
        raise ScenarioError(f"aspect: the patch's a/b must lie in [0.05, 20], got {aspect!r}")
    if not (isinstance(nx, (int, np.integer)) and 4 <= nx <= 64):
        raise ScenarioError(f"nx: elements along the patch must be an integer in [4, 64], got {nx!r}")
    ks = np.atleast_1d(_kappa(kappa))
    dx, area, x, own, upstream, trailing, half = _halfspace_grid(float(aspect), int(nx), float(poisson))
    m = x.size
    steady = np.linalg.solve((own - upstream) / dx, -np.concatenate([np.ones(m), np.zeros(m)]))
    force0 = steady[:m].sum() * area
    p0te = steady[trailing]
    out = {name: np.empty(ks.size, complex) for name in FACTORS + ("dissipation_local",)}
    for i, k in enumerate(ks):
        wm = np.exp(1j * k * x)
        rhs = -np.column_stack([np.concatenate([np.ones(m), np.zeros(m)]), np.concatenate([wm, np.zeros(m)])])
        p = np.linalg.solve((own - np.exp(-1j * k * dx) * upstream) / dx, rhs.astype(complex))
        energy = steady @ (own @ p)  # Σ p0 · A p̂ (A symmetric), per element area
        for j, (name, w) in enumerate((("uniform", np.ones(m)), ("material", wm))):
            force = p[:m, j].sum() * area / force0
            diss = (-(steady[:m] @ w + p[:m, j].sum()) * area - 1j * k * energy[j] * area) / (-2 * force0)
            release = p0te * p[trailing, j]
            deposit = (release * np.exp(1j * k * half)).sum() / release.sum()
            out[f"force_{name}"][i] = force
            out[f"dissipation_{name}"][i] = diss
            out[f"wear_{name}"][i] = diss * deposit
            if name == "material":
                out["dissipation_local"][i] = release.sum() / (p0te**2).sum()
    out["c11"] = -force0 * aspect  # F = -G a b C11 ξ with a = G = ξ = 1, b = 1/aspect
    return {k: (v if np.ndim(kappa) or k == "c11" else v[0]) for k, v in out.items()}


@lru_cache(maxsize=16)
def _table(aspect, nx, poisson, top):
    """The half-space factors on ``κ = 0, 0.1, ..., top / 10`` and their cubic splines."""
    from scipy.interpolate import CubicSpline

    grid = np.arange(top + 1) / 10.0
    values = halfspace_transfer(grid, aspect, nx, poisson)
    return {name: CubicSpline(grid, values[name]) for name in FACTORS}


@dataclass(frozen=True)
class TransientContact:
    """The non-steady contact of a patch of ``aspect`` ``a / b`` (module docstring): ``theory``
    ``"halfspace"`` (Kalker's exact linear theory on ``nx`` elements along rolling, tabulated) or
    ``"simplified"`` (closed form). :meth:`factors` gives the :data:`FACTORS` at ``κ = n a / R0``."""

    aspect: float = 1.0
    theory: str = "halfspace"
    nx: int = 16
    poisson: float = 0.28

    THEORIES = ("halfspace", "simplified")

    def __post_init__(self):
        if self.theory not in self.THEORIES:
            raise ScenarioError(f"contact.theory: must be one of {self.THEORIES}, got {self.theory!r}")
        if not (isinstance(self.aspect, (int, float)) and math.isfinite(self.aspect) and 0.05 <= self.aspect <= 20):
            raise ScenarioError(f"contact.aspect: the patch's a/b must lie in [0.05, 20], got {self.aspect!r}")
        if not (isinstance(self.nx, int) and 4 <= self.nx <= 64):
            raise ScenarioError(f"contact.nx: must be an integer in [4, 64], got {self.nx!r}")
        if not (0 <= self.poisson < 0.5):
            raise ScenarioError(f"contact.poisson: must lie in [0, 0.5), got {self.poisson!r}")

    def factors(self, kappa) -> dict:
        """The :data:`FACTORS` (complex, 1 at ``κ = 0``) at ``kappa`` = ``k a``."""
        k = _kappa(kappa)
        if self.theory == "simplified":
            return simplified_transfer(k)
        top = max(10, int(math.ceil(10 * float(np.max(k, initial=0.0)))) + 2)
        top = 10 * int(math.ceil(top / 10))  # a few tables serve every range
        splines = _table(round(float(self.aspect), 4), int(self.nx), float(self.poisson), top)
        return {name: spline(k) for name, spline in splines.items()}
