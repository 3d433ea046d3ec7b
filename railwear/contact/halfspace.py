"""Frictionless normal contact of two elastic half-spaces on a grid (Kalker's normal problem).

The tangent plane carries a rectangular grid of ``nx × ns`` elements (``x`` along rolling, ``s``
across it, element centres ``x_i``, ``s_j``, sizes ``dx × ds``), each with a uniform pressure
``p_ij``. The undeformed separation ``h_ij = h(x_i, s_j)`` [m] is given at the centres; the
bodies approach by ``δ`` [m]. With the combined elastic displacement ``u = A p`` (Boussinesq and
Love: ``u(x, s) = (1 / (π E*)) ∬ p / r``, ``1/E* = (1-ν1²)/E1 + (1-ν2²)/E2``, collocated at the
centres), the deformed gap ``e = h + A p - δ`` and

    p >= 0,   e >= 0,   p e = 0,   dx ds Σ p = N   (or δ prescribed)

as CONTACT solves it (Kalker, Three-dimensional elastic bodies in rolling contact, Kluwer 1990,
ch. 3 and 5). The influence coefficient of a uniformly loaded rectangle is Love's closed form
(Johnson, Contact Mechanics 1985, eq. 3.25): ``∬ dξ dη / r`` over the element is
``Σ ± F(X ± dx/2, S ± ds/2)`` with ``F(u, v) = u asinh(v/|u|) + v asinh(u/|v|)``.

``A`` depends only on the index differences, so ``A p`` is a 2-D discrete convolution: it is done
by FFT on a grid padded to at least ``(2nx - 1) × (2ns - 1)`` with the kernel laid out in
wrap-around order (DC-FFT: Liu, Wang & Liu, Wear 243 (2000) 101), exact to round-off, with no
dense matrix. The complementarity problem is solved by Polonsky and Keer's constrained conjugate
gradients (Wear 231 (1999) 206-219): with the load prescribed, the mean gap over the contact set
plays the approach and the pressure is rescaled to the load after each step; with the approach
prescribed, the same iteration without the mean and without the rescaling.

No maintained Python library solves this problem (the codes that do are CONTACT, Fortran, and
research scripts), so it is written here on numpy and scipy.fft; the FFT dominates, so nothing
is compiled.
"""

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from railwear.contact._checks import as_float_array, non_negative, positive
from railwear.contact.hertz import effective_modulus
from railwear.errors import ScenarioError

__all__ = ["HalfSpaceContact", "HalfSpacePatch", "halfspace_contact", "influence_coefficients",
           "tangential_influence_coefficients"]


def _love(u, v):
    """``F(u, v) = u asinh(v/|u|) + v asinh(u/|v|)`` [m], ∂²F/∂u∂v = 1/sqrt(u² + v²) in every
    quadrant (``u ln(v + r) + v ln(u + r)`` less functions of one variable); 0 on the axes."""
    au, av = np.abs(u), np.abs(v)
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(au > 0.0, u * np.arcsinh(v / np.where(au > 0.0, au, 1.0)), 0.0)
        b = np.where(av > 0.0, v * np.arcsinh(u / np.where(av > 0.0, av, 1.0)), 0.0)
    return a + b


def influence_coefficients(X, S, dx, ds, estar):
    """Combined normal displacement [m/Pa] at offsets ``(X, S)`` [m] from the centre of a
    ``dx × ds`` [m] element under unit uniform pressure, contact modulus ``estar`` [Pa]
    (Love 1929; Johnson 1985, eq. 3.25)."""
    hx, hs = 0.5 * dx, 0.5 * ds
    total = _love(X + hx, S + hs) - _love(X - hx, S + hs) - _love(X + hx, S - hs) + _love(X - hx, S - hs)
    return total / (np.pi * estar)


def _rectangle(primitive, X, S, hx, hs):
    """``∬ g`` over the element ``[X - hx, X + hx] × [S - hs, S + hs]`` from a primitive with
    ``∂²F/∂u∂v = g``."""
    return primitive(X + hx, S + hs) - primitive(X - hx, S + hs) - primitive(X + hx, S - hs) + primitive(X - hx, S - hs)


def _love_xx(u, v):
    """Primitive of ``u² / r³``: ``v asinh(u/|v|)`` (0 on ``v = 0``)."""
    av = np.abs(v)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(av > 0.0, v * np.arcsinh(u / np.where(av > 0.0, av, 1.0)), 0.0)


def _love_xy(u, v):
    """Primitive of ``u v / r³``: ``-r``."""
    return -np.hypot(u, v)


def tangential_influence_coefficients(X, S, dx, ds, shear_modulus, poisson):
    """Combined tangential displacement differences (Axx, Axy, Ayy) [m/Pa] at offsets ``(X, S)``
    [m] from the centre of a ``dx × ds`` [m] element under unit uniform shear traction, for
    quasi-identical bodies of combined shear modulus ``G`` [Pa] and Poisson ratio ``ν``.

    Cerruti's point-load solution for both bodies together, ``u_x = (1/(πG)) ((1-ν)/r + ν X²/r³)
    Q_x + (ν/(πG)) X S/r³ Q_y`` and ``u_y`` likewise with X and S exchanged (Johnson 1985,
    eq. 3.86a; Kalker 1990, ch. 1-3, as CONTACT's documentation gives them), integrated over the
    element in closed form: ``∬ X²/r³`` has the primitive ``S asinh(X/|S|)``, ``∬ X S/r³`` the
    primitive ``-r``, and their sum with the one of ``S²/r³`` is Love's ``∬ 1/r``. The
    coupling to the normal problem (the ``(1-2ν)`` terms) vanishes for quasi-identical bodies.
    """
    hx, hs = 0.5 * dx, 0.5 * ds
    ixx = _rectangle(_love_xx, X, S, hx, hs)
    iyy = _rectangle(lambda u, v: _love_xx(v, u), X, S, hx, hs)
    ixy = _rectangle(_love_xy, X, S, hx, hs)
    scale = 1.0 / (np.pi * shear_modulus)
    return ((ixx + (1.0 - poisson) * iyy) * scale, poisson * ixy * scale, ((1.0 - poisson) * ixx + iyy) * scale)


def _wrapped_offsets(nx, ns, dx, ds):
    """Offsets [m] of the padded grid in wrap-around order and that grid's shape."""
    from scipy import fft as sfft  # scipy.fft here and below, not at import (0.1-0.4 s)

    Lx, Ls = sfft.next_fast_len(2 * nx - 1, real=True), sfft.next_fast_len(2 * ns - 1, real=True)
    ix = np.arange(Lx)
    js = np.arange(Ls)
    X = np.where(ix < nx, ix, ix - Lx) * dx
    S = np.where(js < ns, js, js - Ls) * ds
    unused = ((ix >= nx) & (ix <= Lx - nx))[:, None] | ((js >= ns) & (js <= Ls - ns))[None, :]
    return X[:, None], S[None, :], unused, (Lx, Ls)


@lru_cache(maxsize=16)
def _kernel(nx, ns, dx, ds, modulus, component="zz", poisson=0.0):
    """FFT of the wrap-around kernel on the padded grid, and that grid's shape. ``component``
    "zz": the normal kernel (``modulus`` E*); "xx", "xy", "yy": the tangential ones (``modulus``
    G, with ``poisson``)."""
    X, S, unused, padded = _wrapped_offsets(nx, ns, dx, ds)
    if component == "zz":
        K = influence_coefficients(X, S, dx, ds, modulus)
    else:
        K = tangential_influence_coefficients(X, S, dx, ds, modulus, poisson)[("xx", "xy", "yy").index(component)]
    K = np.where(unused, 0.0, K)  # offsets no element pair has
    from scipy import fft as sfft

    return sfft.rfft2(K), padded


class _Convolution:
    """``u = A p`` on an ``nx × ns`` grid by zero-padded FFT (DC-FFT); ``component`` and
    ``poisson`` choose the kernel as in :func:`_kernel` (default the normal one, ``estar`` E*)."""

    def __init__(self, nx, ns, dx, ds, estar, component="zz", poisson=0.0):
        self.shape = (nx, ns)
        self.khat, self.padded = _kernel(nx, ns, float(dx), float(ds), float(estar), component, float(poisson))

    def __call__(self, p):
        from scipy import fft as sfft

        out = sfft.irfft2(sfft.rfft2(p, s=self.padded) * self.khat, s=self.padded)
        return out[: self.shape[0], : self.shape[1]]


@dataclass(frozen=True)
class HalfSpacePatch:
    """One connected patch of the contact set: normal_force [N], area [m²], peak pressure p0
    [Pa], load centroid (x, s) [m], edges x_min .. s_max [m] (outer element edges) and the
    half-lengths along rolling and across it [m]."""

    normal_force: float
    area: float
    p0: float
    centroid_x: float
    centroid_s: float
    x_min: float
    x_max: float
    s_min: float
    s_max: float

    @property
    def half_length(self):
        """Half the extent along rolling [m]."""
        return 0.5 * (self.x_max - self.x_min)

    @property
    def half_width(self):
        """Half the extent across rolling [m]."""
        return 0.5 * (self.s_max - self.s_min)


@dataclass(frozen=True)
class HalfSpaceContact:
    """Solution of the normal problem (module docstring), SI units: element centres ``x`` (nx,)
    and ``s`` (ns,) [m], ``pressure`` (nx, ns) [Pa], deformed ``gap`` (nx, ns) [m], approach δ
    [m], normal_force [N], contact area [m²], peak pressure p0 [Pa], load centroid (x, s) [m],
    ``half_length`` / ``half_width`` half the extent of the whole contact set along / across
    rolling [m] (outer element edges), CG iterations and the last relative pressure change."""

    x: np.ndarray
    s: np.ndarray
    pressure: np.ndarray
    gap: np.ndarray
    approach: float
    normal_force: float
    area: float
    p0: float
    centroid_x: float
    centroid_s: float
    half_length: float
    half_width: float
    iterations: int
    residual: float

    @property
    def contact(self):
        """Boolean map of the elements in contact (p > 0)."""
        return self.pressure > 0.0

    def patches(self):
        """The connected patches (4-neighbour), heaviest first: list of :class:`HalfSpacePatch`."""
        from scipy import ndimage  # only here: keeps ``import railwear.contact`` light

        labels, count = ndimage.label(self.contact)
        return sorted((_patch(self, labels == k) for k in range(1, count + 1)), key=lambda q: -q.normal_force)


def _patch(res, mask):
    dx, ds = res.x[1] - res.x[0], res.s[1] - res.s[0]
    p = np.where(mask, res.pressure, 0.0)
    load = p.sum() * dx * ds
    ii, jj = np.nonzero(mask)
    return HalfSpacePatch(
        normal_force=float(load), area=float(mask.sum() * dx * ds), p0=float(p.max()),
        centroid_x=float((p.sum(1) @ res.x) * dx * ds / load), centroid_s=float((p.sum(0) @ res.s) * dx * ds / load),
        x_min=float(res.x[ii.min()] - 0.5 * dx), x_max=float(res.x[ii.max()] + 0.5 * dx),
        s_min=float(res.s[jj.min()] - 0.5 * ds), s_max=float(res.s[jj.max()] + 0.5 * ds))


def _axis(v, name):
    v = as_float_array(v, name)
    if v.ndim != 1 or v.size < 3:
        raise ScenarioError(f"{name} must be a 1-D array of at least 3 element centres")
    d = np.diff(v)
    if np.any(d <= 0) or not np.allclose(d, d[0], rtol=1e-9, atol=0.0):
        raise ScenarioError(f"{name} must be equally spaced and increasing")
    return v, float(d[0])


def halfspace_contact(x, s, h, normal_force=None, youngs_modulus=2.1e11, poisson=0.28, youngs_modulus_2=None,
                      poisson_2=None, approach=None, tol=1e-10, max_iterations=5000, initial_pressure=None):
    """Normal contact of two elastic half-spaces (module docstring).

    x, s: element centres along and across rolling [m] (equally spaced); h: undeformed
    separation at the centres [m], shape (x.size, s.size); either ``normal_force`` [N] > 0
    (load control) or ``approach`` δ [m] (approach control); the materials as in
    :func:`railwear.contact.hertz_contact`; ``tol``: the iteration stops when the relative
    change of the pressure, ``Σ |Δp| / Σ p``, falls below it; ``initial_pressure`` [Pa] (nx, ns)
    to start from (e.g. a neighbouring solution). Returns a :class:`HalfSpaceContact`.
    """
    x, dx = _axis(x, "x")
    s, ds = _axis(s, "s")
    h = as_float_array(h, "h")
    if h.shape != (x.size, s.size):
        raise ScenarioError(f"h must have shape (x.size, s.size) = {(x.size, s.size)}, got {h.shape}")
    if (normal_force is None) == (approach is None):
        raise ScenarioError("give exactly one of normal_force and approach")
    tol = float(positive(tol, "tol"))
    if not (isinstance(max_iterations, (int, np.integer)) and max_iterations >= 1):
        raise ScenarioError(f"max_iterations must be a positive integer, got {max_iterations!r}")
    estar = float(effective_modulus(youngs_modulus, poisson, youngs_modulus_2, poisson_2))
    conv = _Convolution(x.size, s.size, dx, ds, estar)
    cell = dx * ds
    load_control = approach is None
    if load_control:
        W = float(positive(normal_force, "normal_force"))
    else:
        delta = float(as_float_array(approach, "approach"))
    if initial_pressure is not None:
        p = np.array(non_negative(initial_pressure, "initial_pressure"), dtype=float)
        if p.shape != h.shape or not np.any(p > 0):
            raise ScenarioError("initial_pressure must have h's shape and some positive values")
    else:
        # start on the region of the smallest separations (the lower tenth of the range)
        p = (h <= h.min() + 0.1 * (h.max() - h.min())).astype(float)
    if load_control:
        p *= W / (cell * p.sum())
    elif not np.any(h < delta):
        zero = np.zeros(h.shape)
        return _result(x, s, zero, h - delta, delta, 0, 0.0)
    else:
        p *= estar * max(delta - h.min(), 0.0) / (np.sqrt(cell) * p.max())
    t = np.zeros(h.shape)
    G_old = 1.0
    conjugate = False
    change = np.inf
    it = 0
    for it in range(1, max_iterations + 1):
        g = h + conv(p)
        Ic = p > 0.0
        if not np.any(Ic):  # approach control, everything lifted off: restart where h < δ
            p = np.where(h < delta, estar * (delta - h) / np.sqrt(cell), 0.0)
            conjugate = False
            continue
        g = g - (g[Ic].mean() if load_control else delta)
        G = float(np.sum(g[Ic] ** 2))
        t = np.where(Ic, g + (G / G_old) * t if conjugate else g, 0.0)
        G_old = G
        r = conv(t)
        if load_control:
            r = r - r[Ic].mean()
        denominator = float(np.sum(r[Ic] * t[Ic]))
        tau = float(np.sum(g[Ic] * t[Ic])) / denominator if denominator != 0.0 else 0.0
        p_old = p
        p = np.where(Ic, p - tau * t, 0.0)
        p[p < 0.0] = 0.0
        overlap = (p == 0.0) & (g < 0.0)
        conjugate = not np.any(overlap)
        if not conjugate:
            p[overlap] -= tau * g[overlap]
        if load_control:
            p *= W / (cell * p.sum())
        total = np.sum(p)
        change = float(np.sum(np.abs(p - p_old)) / total) if total > 0 else 0.0
        if change < tol:
            break
    u = conv(p)
    Ic = p > 0.0
    if load_control:
        delta = float(np.mean((h + u)[Ic]))
    return _result(x, s, p, h + u - delta, delta, it, change)


def _result(x, s, p, gap, delta, iterations, change):
    dx, ds = x[1] - x[0], s[1] - s[0]
    cell = dx * ds
    load = float(p.sum() * cell)
    on = p > 0.0
    if load > 0.0:
        ii, jj = np.nonzero(on)
        cx = float(p.sum(1) @ x * cell / load)
        cs = float(p.sum(0) @ s * cell / load)
        half_length = 0.5 * (x[ii.max()] - x[ii.min()] + dx)
        half_width = 0.5 * (s[jj.max()] - s[jj.min()] + ds)
    else:
        cx = cs = np.nan
        half_length = half_width = 0.0
    return HalfSpaceContact(x=x, s=s, pressure=p, gap=gap, approach=float(delta), normal_force=load,
                            area=float(on.sum() * cell), p0=float(p.max()), centroid_x=cx, centroid_s=cs,
                            half_length=float(half_length), half_width=float(half_width),
                            iterations=int(iterations), residual=float(change))
