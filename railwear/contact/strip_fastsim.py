"""FASTSIM strip by strip on a patch that is not an ellipse (Kik and Piotrowski's tangential part).

A patch is a set of strips along rolling, side by side across it: strip ``j`` at the lateral
position ``s_j`` (the patch's own coordinate across rolling, in its tangent plane), of width
``w_j``, reaching from ``x = +L_j`` (leading edge, where material enters, as in
:mod:`railwear.contact.fastsim`) to ``-L_j``. Along every strip Kalker's FASTSIM runs as it does
on the strips of an ellipse: the traction grows from zero at the leading edge by the elastic
increments ``Δpx = -(ξ_j/L1 - φ s_j/L3) Δx``, ``Δpy = -(η/L2 + φ x/L3) Δx`` and is cut back to
the traction bound ``μ p`` (slip), then released to zero at the trailing edge
(:func:`railwear.contact.fastsim.increment`, the same increment and the same frictional-power
bookkeeping as ``fastsim``). Each strip may have its own longitudinal creepage ``ξ_j``: on a wide
patch across a coned or curved profile the rolling radius changes across it, and with the axle's
one angular speed each strip has ``ξ_j = 1 - Ω r_j / V``.

**Pressure along a strip: semi-elliptic**, ``p(x, s_j) = P sqrt(L_j² - x²)`` with one ``P`` for
the patch (Kik & Piotrowski 1996; Piotrowski & Kik, Vehicle System Dynamics 46 (2008) 27-48).
That is the pressure of railwear's semi-Hertzian normal solution
(:mod:`railwear.contact.semi_hertz`), so the traction bound is the normal problem's own; on the
strips of a Hertz ellipse (``L_j = a sqrt(1 - s_j²/b²)``) it is Hertz's pressure, and the result
is ``fastsim``'s with its default elliptic bound. ``P`` is set by the normal force,
``N = P Σ_j w_j π L_j² / 2``, so the strips carry exactly ``N``. (Kalker's parabolic bound is an
improvement of FASTSIM's creep curve on the ellipse, fitted there; on another patch it has no
normal solution behind it, so it is not offered.)

**Flexibilities.** FASTSIM's ``L1 = 8a/(3 C11 G)``, ``L2 = 8a/(3 C22 G)``,
``L3 = π a sqrt(a/b)/(4 C23 G)`` (:func:`railwear.contact.fastsim.flexibilities`) with Kalker's
coefficients of the patch's *equivalent ellipse* ``a × b``, as FASTSIM takes them for its ellipse
and Kik and Piotrowski for their patch; railwear's semi-Hertzian tables give that ellipse as the
one of the same area and width (``b`` half the width, ``a = area / (π b)``). In the linear limit
(no slip) the forces are then the flexibilities' own, ``Fx = -Σ_j 2 L_j² w_j ξ_j / L1``,
``Fy = -Σ_j 2 L_j² w_j (η / L2) + φ Σ_j 2 L_j² w_j s_j / L3``..., which equal Kalker's for an
ellipse and differ from the equivalent ellipse's for another shape (that is the point: the patch's
own length along rolling decides how much traction builds up).

Outputs (Kalker's sign convention, as ``fastsim``): Fx, Fy [N], Mz [N m] about ``s = 0, x = 0``,
the frictional power ``power_local`` [W] (the dissipation of the increments, FASTSIM's local
power) and its distribution over the strips ``strip_power`` [W], the rigid slip work
``power_global = -V (Σ_j ξ_j Fx_j + η Fy + φ Mz)``, and the slip area fraction.

:func:`strip_fastsim_grid` runs the same march on the columns of a grid with a tabulated pressure
(e.g. the elastic half-space's, :func:`railwear.contact.halfspace_contact`), for comparisons with
:func:`railwear.contact.rolling_contact` on the same grid.
"""

from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.contact.fastsim import _TAIL_STEPS, _scalar, _slip_flexibilities, flexibilities, increment
from railwear.errors import ScenarioError

__all__ = ["StripFastsimResult", "GridFastsimResult", "ellipse_strips", "strip_fastsim", "strip_fastsim_grid",
           "STRIP_CELLS"]

STRIP_CELLS = 16  # cells along each strip by default (the compiled dynamics use the same)


@njit(cache=True, inline="always")
def strip_march(s, L, pmax, xi, eta, phi, L1, L2, L3, c, nx):
    """FASTSIM along one strip at lateral position ``s`` of half-length ``L`` with the traction
    bound ``pmax sqrt(1 - x²/L²)`` (``pmax = μ P L``), ``nx`` cells with traction points at their
    centres, a last half cell releasing the traction to zero. Returns ``(Fx, Fy, Mz, power,
    slip length)`` per unit strip width and unit speed (Mz about ``x = 0, s = 0``)."""
    Lx, Ly = _slip_flexibilities(c, c, xi, eta, phi, L1, L2, L3)
    dx = 2.0 * L / nx
    rx = xi / L1 - phi * s / L3
    px = 0.0
    py = 0.0
    fx = 0.0
    fy = 0.0
    mz = 0.0
    power = 0.0
    slip = 0.0
    x_prev = L
    for i in range(nx):
        x = L - (i + 0.5) * dx
        r = x / L
        bound = pmax * np.sqrt(max(0.0, 1.0 - r * r))
        px, py, slipping, diss = increment(px, py, x_prev - x, 0.5 * (x + x_prev), rx, eta, phi, L2, L3, bound,
                                           Lx, Ly)
        power += diss
        fx += px * dx
        fy += py * dx
        mz += (x * py - s * px) * dx
        if slipping:
            slip += dx
        x_prev = x
    sub = 0.5 * dx / _TAIL_STEPS
    for k in range(1, _TAIL_STEPS + 1):
        x = x_prev - sub
        if k == _TAIL_STEPS:
            bound = 0.0
        else:
            r = x / L
            bound = pmax * np.sqrt(max(0.0, 1.0 - r * r))
        px, py, _, diss = increment(px, py, sub, x + 0.5 * sub, rx, eta, phi, L2, L3, bound, Lx, Ly)
        power += diss
        x_prev = x
    return fx, fy, mz, power, slip


@njit(cache=True)
def strip_kernel(s, width, L, xi, normal, eta, phi, mu, L1, L2, L3, c, nx, strip_power):
    """A patch of strips (module docstring): ``s``, ``width``, ``L``, ``xi`` arrays over the
    strips, semi-elliptic pressure carrying ``normal`` [N]. Fills ``strip_power`` [W per m/s];
    returns ``(Fx, Fy, Mz, power per m/s, slip area fraction, Σ ξ_j Fx_j)``."""
    shape = 0.0
    area = 0.0
    for j in range(s.shape[0]):
        shape += 0.5 * np.pi * L[j] * L[j] * width[j]
        area += 2.0 * L[j] * width[j]
    P = normal / shape if shape > 0.0 else 0.0
    Fx = 0.0
    Fy = 0.0
    Mz = 0.0
    power = 0.0
    slip = 0.0
    work = 0.0
    for j in range(s.shape[0]):
        strip_power[j] = 0.0
        if not L[j] > 0.0:
            continue
        fx, fy, mz, pw, sl = strip_march(s[j], L[j], mu * P * L[j], xi[j], eta, phi, L1, L2, L3, c, nx)
        w = width[j]
        Fx += fx * w
        Fy += fy * w
        Mz += mz * w
        strip_power[j] = pw * w
        power += pw * w
        slip += sl * w
        work += xi[j] * fx * w
    return Fx, Fy, Mz, power, slip / area if area > 0.0 else 0.0, work


@njit(cache=True)
def _grid_kernel(x, s, pressure, xi, eta, phi, mu, L1, L2, L3, c, px, py, pd, slip):
    """FASTSIM down every column of a grid (``x`` ascending, uniform; material enters at the
    largest ``x``) with the bound ``μ pressure``: fills the traction, the power density per unit
    speed and the slip flags; the traction starts at zero half a cell beyond the last row and is
    released to zero half a cell beyond the first."""
    dx = x[1] - x[0]
    nx = x.shape[0]
    for j in range(s.shape[0]):
        Lx, Ly = _slip_flexibilities(c, c, xi[j], eta, phi, L1, L2, L3)
        rx = xi[j] / L1 - phi * s[j] / L3
        qx = 0.0
        qy = 0.0
        for i in range(nx - 1, -1, -1):
            step = 0.5 * dx if i == nx - 1 else dx
            qx, qy, slipping, diss = increment(qx, qy, step, x[i] + 0.5 * step, rx, eta, phi, L2, L3,
                                               mu * pressure[i, j], Lx, Ly)
            px[i, j] = qx
            py[i, j] = qy
            pd[i, j] = diss / dx
            slip[i, j] = slipping and pressure[i, j] > 0.0
        _, _, _, diss = increment(qx, qy, 0.5 * dx, x[0] - 0.25 * dx, rx, eta, phi, L2, L3, 0.0, Lx, Ly)
        pd[0, j] += diss / dx


@dataclass(frozen=True)
class StripFastsimResult:
    """Strip-wise FASTSIM of one patch (SI, Kalker's signs): Fx, Fy [N], Mz [N m] about
    ``s = 0``; power_local [W] and its share per strip ``strip_power`` [W]; power_global [W] the
    rigid slip work; slip_fraction [-]; pressure_scale ``P`` [Pa/m] of ``p = P sqrt(L² - x²)``;
    L1, L2, L3 [m/Pa] the flexibilities."""

    Fx: float
    Fy: float
    Mz: float
    power_local: float
    power_global: float
    strip_power: np.ndarray
    slip_fraction: float
    pressure_scale: float
    L1: float
    L2: float
    L3: float


@dataclass(frozen=True)
class GridFastsimResult:
    """Strip-wise FASTSIM on a grid: traction px, py [Pa] and power_density [W/m²] (nx, ns), slip
    flags, Fx, Fy [N], Mz [N m] about the grid's origin, power_local [W], power_global [W]."""

    px: np.ndarray
    py: np.ndarray
    power_density: np.ndarray
    slip: np.ndarray
    Fx: float
    Fy: float
    Mz: float
    power_local: float
    power_global: float


def ellipse_strips(a, b, n):
    """The ``n`` strips of FASTSIM's ellipse ``a × b`` [m]: ``(s, width, L)`` arrays [m]."""
    a, b = _scalar(a, "a", 0.0, strict=True), _scalar(b, "b", 0.0, strict=True)
    if int(n) != n or n < 1:
        raise ScenarioError(f"n must be a positive integer, got {n}")
    w = 2.0 * b / int(n)
    s = -b + (np.arange(int(n)) + 0.5) * w
    return s, np.full(int(n), w), a * np.sqrt(1.0 - (s / b) ** 2)


def _per_strip(value, size, name):
    """``value`` as one float per strip (a number is repeated)."""
    try:
        return np.broadcast_to(np.asarray(value, dtype=float), (size,)).copy()
    except ValueError:
        raise ScenarioError(f"{name} must be a number or one value per strip ({size})") from None


def _common(xi, size, eta, phi, mu, shear_modulus, poisson, a, b, speed):
    xi = _per_strip(xi, size, "xi")
    if not np.all(np.isfinite(xi)):
        raise ScenarioError("xi must be finite")
    eta, phi = _scalar(eta, "eta"), _scalar(phi, "phi")
    mu = float(mu) if np.isposinf(mu) else _scalar(mu, "mu", 0.0)
    G = _scalar(shear_modulus, "shear_modulus", 0.0, strict=True)
    nu = _scalar(poisson, "poisson", 0.0)
    if nu >= 0.5:
        raise ScenarioError(f"poisson must lie in [0, 0.5), got {nu:g}")
    a, b = _scalar(a, "a", 0.0, strict=True), _scalar(b, "b", 0.0, strict=True)
    speed = _scalar(speed, "speed", 0.0)
    L1, L2, L3 = (float(v) for v in flexibilities(a, b, G, nu))
    return xi, eta, phi, mu, L1, L2, L3, float(np.sqrt(a * b)), speed


def strip_fastsim(s, width, half_length, normal_force, xi, eta, phi, mu, shear_modulus, poisson, a, b,
                  nx=STRIP_CELLS, speed=1.0):
    """Strip-wise FASTSIM (module docstring). ``s`` [m] strip positions across rolling (spin
    about ``s = 0``), ``width`` [m] (scalar or per strip), ``half_length`` [m] per strip (0: empty),
    ``normal_force`` [N] on the patch, ``xi`` [-] scalar or per strip, ``eta`` [-], ``phi`` [1/m],
    ``mu`` [-] (``inf``: no slip), ``shear_modulus`` [Pa], ``poisson`` [-], ``a``, ``b`` [m] the
    equivalent ellipse giving the flexibilities, ``nx`` cells per strip, ``speed`` [m/s] scales
    the powers. Returns a :class:`StripFastsimResult`."""
    s = np.ascontiguousarray(s, dtype=float)
    if s.ndim != 1 or s.size < 1 or not np.all(np.isfinite(s)):
        raise ScenarioError("s must be a finite 1-D array of strip positions")
    width = _per_strip(width, s.size, "width")
    L = _per_strip(half_length, s.size, "half_length")
    if np.any(~np.isfinite(width) | (width <= 0)) or np.any(~np.isfinite(L) | (L < 0)):
        raise ScenarioError("strip widths must be > 0 and half-lengths >= 0, finite")
    N = _scalar(normal_force, "normal_force", 0.0)
    if int(nx) != nx or nx < 1:
        raise ScenarioError(f"nx must be a positive integer, got {nx}")
    xi, eta, phi, mu, L1, L2, L3, c, speed = _common(xi, s.size, eta, phi, mu, shear_modulus, poisson, a, b, speed)
    strip_power = np.zeros(s.size)
    Fx, Fy, Mz, power, slip, work = strip_kernel(s, width, L, xi, N, eta, phi, mu, L1, L2, L3, c, int(nx),
                                                 strip_power)
    shape = float(np.sum(0.5 * np.pi * L**2 * width))
    return StripFastsimResult(Fx=Fx, Fy=Fy, Mz=Mz, power_local=speed * power,
                              power_global=-speed * (work + eta * Fy + phi * Mz), strip_power=speed * strip_power,
                              slip_fraction=slip, pressure_scale=N / shape if shape > 0 else 0.0, L1=L1, L2=L2, L3=L3)


def strip_fastsim_grid(x, s, pressure, xi, eta, phi, mu, shear_modulus, poisson, a, b, speed=1.0):
    """Strip-wise FASTSIM on the columns of a grid (element centres ``x`` along rolling,
    ascending and uniform, ``s`` across; ``pressure`` [Pa] of shape (x, s), zero outside the
    patch) with the bound ``μ pressure``; ``xi`` scalar or one per column; the rest as
    :func:`strip_fastsim`. Returns a :class:`GridFastsimResult` (Mz about the grid's origin)."""
    x = np.ascontiguousarray(x, dtype=float)
    s = np.ascontiguousarray(s, dtype=float)
    p = np.ascontiguousarray(pressure, dtype=float)
    if x.ndim != 1 or s.ndim != 1 or x.size < 2 or p.shape != (x.size, s.size) or np.any(~np.isfinite(p) | (p < 0)):
        raise ScenarioError("pressure must be a finite, non-negative (x, s) grid")
    dx = np.diff(x)
    if np.any(dx <= 0) or not np.allclose(dx, dx[0], rtol=1e-9, atol=0.0):
        raise ScenarioError("x must be equally spaced and increasing")
    xi, eta, phi, mu, L1, L2, L3, c, speed = _common(xi, s.size, eta, phi, mu, shear_modulus, poisson, a, b, speed)
    px, py, pd = np.zeros(p.shape), np.zeros(p.shape), np.zeros(p.shape)
    slip = np.zeros(p.shape, dtype=np.bool_)
    _grid_kernel(x, s, p, xi, eta, phi, mu, L1, L2, L3, c, px, py, pd, slip)
    cell = dx[0] * (s[1] - s[0] if s.size > 1 else 1.0)
    Fx, Fy = float(px.sum() * cell), float(py.sum() * cell)
    Mz = float(np.sum(x[:, None] * py - s[None, :] * px) * cell)
    work = float(np.sum(xi[None, :] * px) * cell)
    return GridFastsimResult(px=px, py=py, power_density=speed * pd, slip=slip, Fx=Fx, Fy=Fy, Mz=Mz,
                             power_local=speed * float(pd.sum() * cell),
                             power_global=-speed * (work + eta * Fy + phi * Mz))
