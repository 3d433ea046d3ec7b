"""Kalker's exact steady-state rolling contact: the tangential problem on the half-space grid.

The grid is :mod:`railwear.contact.halfspace`'s: ``nx × ns`` elements of ``dx × ds`` in the
tangent plane, ``x`` along rolling, ``s`` across it, a uniform traction ``(px, py)`` on each.
The bodies are quasi-identical (same elastic constants, or Kalker's combined ``G`` and ``ν``),
so the normal and tangential problems uncouple: the normal pressure ``pn`` is given (e.g. by
:func:`railwear.contact.halfspace_contact`) and stays fixed. Rolling is in Kalker's and
FASTSIM's sense here: material enters the patch at the largest ``x`` and leaves at the
smallest. With the rigid slip (creepage) ``w = (ξ - φ s, η + φ x)`` (ξ may vary across rolling,
one value per strip) and the displacement difference ``u = A p`` (Cerruti's half-space
influence of both bodies, :func:`~railwear.contact.halfspace.tangential_influence_coefficients`),
the slip per unit rolling distance is, in steady state,

    s = w - ∂u/∂x,   discretised upwind along rolling: s_i = w_i - (u_{i+1} - u_i) / dx

(Kalker, *Three-dimensional elastic bodies in rolling contact*, Kluwer 1990, ch. 5: the
transient problem with the time step ``dx / V`` at its steady state), and the conditions are

    adhesion: s = 0, |p| <= μ pn;     slip: p = -μ pn s / |s|.

The conditions are written as one equation per element, ``F = p - Π(p - c s) = 0`` with Π the
projection on the disk ``|q| <= μ pn`` and ``c = 1/b̄`` (Alart and Curnier's augmented form,
Comput. Methods Appl. Mech. Eng. 92 (1991) 353-375; its root satisfies both the adhesion and the
slip conditions), and solved by a semismooth Newton iteration with a backtracking line search on
``|F|`` (the slip/adhesion split and the slip directions updated at every step, as in Kalker's
active-set algorithm). Each Newton step is a GMRES solve (Saad and Schultz
1986) of the generalised Jacobian, applied matrix-free: ``∂(A p)/∂x`` by the zero-padded FFT of
:class:`railwear.contact.halfspace._Convolution` with the tangential kernels (exact to
round-off, no matrix). GMRES is preconditioned by the same Jacobian with the elasticity cut to
its strip-wise upwind part, ``(M d)_i ≈ B (d_up - d_i)``, ``B = (A(0) - A(dx)) / dx`` (the
element's own coefficient and the upstream neighbour's, which are equal and opposite): that is
lower block-bidiagonal in the order leading edge first, and one march from the leading edge
inverts it (FASTSIM's structure with the half-space's own flexibility). Kalker's and
Vollebregt's Gauss-Seidel sweeps (ConvexGS; Vollebregt, J. Optim. Theory Appl. 87 (1995) 47-67)
were tried first: on the steady-state matrix ``A - A_shifted`` a plain sweep from the leading
edge diverges (the upstream coupling sums to more than the diagonal), so they are not used. The
iteration stops when ``max |F| <= tol · max μ pn`` (``tol · c max |w|`` in full adhesion).

Outputs (SI): Fx, Fy [N], Mz [N m] about the grid's origin (``Mz = Σ (x py - s px) dA``), the
traction and slip fields, the slip velocity ``V s`` [m/s], the frictional power density
``V |p| |s|`` [W/m²] on the slip elements (zero in adhesion) and its sum ``power_local =
Σ V |p| |s| dA`` [W], and for comparison ``power_global = -V Σ p · w dA`` (``-V (ξ Fx + η Fy +
φ Mz)`` for uniform ξ), the rigid slip work. For the exact continuous solution the two are
equal (``Σ p · ∂(A p)/∂x`` vanishes because ``∂A/∂x`` is odd); Kalker's upwind difference adds
``(dx/2) Σ p · ∂²(A p)/∂x²``, so on the grid they differ at first order in dx.

No maintained Python library solves Kalker's rolling problem (CONTACT is Fortran), so this is
written here: numba for the element loops, scipy's FFT and GMRES for the rest.
"""

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from railwear.contact._checks import as_float_array, non_negative, poisson_ratio, positive
from railwear.contact.halfspace import _axis, _Convolution, tangential_influence_coefficients
from railwear.errors import ScenarioError

__all__ = ["RollingContact", "rolling_contact"]


@njit(cache=True)
def _project(px, py, sx, sy, g, c, fx, fy, theta, ex, ey):
    """Per element: ``z = p - c s``, its projection on the disk ``|q| <= g`` and the residual
    ``F = p - Π(z)`` (into fx, fy); theta = g/|z| where z lies outside (slip), else 1 (adhesion
    flag theta >= 1 means inside); (ex, ey) the unit vector of z. Returns max |F|."""
    worst = 0.0
    for k in range(px.size):
        zx = px[k] - c * sx[k]
        zy = py[k] - c * sy[k]
        r = math.sqrt(zx * zx + zy * zy)
        if r > g[k]:
            th = g[k] / r
            qx, qy = th * zx, th * zy
            ex[k], ey[k] = zx / r, zy / r
        else:
            th = 1.0 + 1.0  # inside
            qx, qy = zx, zy
            ex[k], ey[k] = 0.0, 0.0
        theta[k] = th
        fx[k] = px[k] - qx
        fy[k] = py[k] - qy
        worst = max(worst, math.sqrt(fx[k] * fx[k] + fy[k] * fy[k]))
    return worst


@njit(cache=True)
def _jacobian(dx_, dy_, vx, vy, c, theta, ex, ey, outx, outy):
    """``J d = d - DΠ(z) (d + c M d)`` per element, with ``M d`` = (vx, vy) the difference field
    of d (so ``∂s/∂p = -M``); DΠ = I inside the disk, ``θ (I - e eᵀ)`` outside."""
    for k in range(dx_.size):
        zx = dx_[k] + c * vx[k]
        zy = dy_[k] + c * vy[k]
        if theta[k] > 1.0:
            outx[k] = dx_[k] - zx
            outy[k] = dy_[k] - zy
        else:
            dot = ex[k] * zx + ey[k] * zy
            outx[k] = dx_[k] - theta[k] * (zx - dot * ex[k])
            outy[k] = dy_[k] - theta[k] * (zy - dot * ey[k])


@njit(cache=True)
def _precondition(rx, ry, up, c, bx, by, theta, ex, ey, outx, outy):
    """Solve ``P y = r`` with P the Jacobian in which M keeps only its strip-wise upwind part
    (``(M d)_i ≈ -B d_i + B d_up``, exact coefficients of the element itself and of the one
    upstream of it): lower block-bidiagonal in the order leading edge first, so one march
    from the leading edge solves it (FASTSIM's structure with the half-space's own ``B``)."""
    cbx, cby = c * bx, c * by
    for k in range(rx.size):
        u = up[k]
        yux = outx[u] if u >= 0 else 0.0
        yuy = outy[u] if u >= 0 else 0.0
        if theta[k] > 1.0:  # -c (-B y + B y_up) = r
            outx[k] = rx[k] / cbx + yux
            outy[k] = ry[k] / cby + yuy
        else:  # y - θ (I - e eᵀ) ((1 - cB) y + cB y_up) = r
            th, e1, e2 = theta[k], ex[k], ey[k]
            # right-hand side: r + θ (I - e eᵀ) cB y_up
            hx, hy = cbx * yux, cby * yuy
            dot = e1 * hx + e2 * hy
            bxr = rx[k] + th * (hx - dot * e1)
            byr = ry[k] + th * (hy - dot * e2)
            # matrix I - θ (I - e eᵀ) diag(1 - cbx, 1 - cby)
            m11 = 1.0 - th * (1.0 - e1 * e1) * (1.0 - cbx)
            m12 = th * e1 * e2 * (1.0 - cby)
            m21 = th * e1 * e2 * (1.0 - cbx)
            m22 = 1.0 - th * (1.0 - e2 * e2) * (1.0 - cby)
            det = m11 * m22 - m12 * m21
            outx[k] = (m22 * bxr - m12 * byr) / det
            outy[k] = (m11 * byr - m21 * bxr) / det


@dataclass(frozen=True)
class RollingContact:
    """Solution of the steady-state rolling tangential problem (module docstring), SI units,
    Kalker's sign convention (forces on the body whose creepages are given).

    x (nx,), s (ns,): element centres [m]; pressure, px, py (nx, ns): normal pressure and
    tangential traction [Pa]; slip_x, slip_y (nx, ns): slip per unit rolling distance [-]
    (zero in adhesion and outside the contact); adhesion (nx, ns): True where the element sticks
    (contact elements only); power_density [W/m²] = V |p| |s|; Fx, Fy [N], Mz [N m] about the
    grid origin; normal_force [N]; power_local [W] = Σ V |p| |s| dA; power_global [W] =
    -V Σ p · w dA; adhesion_area, slip_area [m²]; speed V [m/s]; iterations (Newton steps),
    krylov_iterations (GMRES steps, all together), residual (``max |F|`` over its scale, see the
    module docstring); adhesion_residual: the largest |s| left in the adhesion area, relative
    to the largest slip (or to the largest creepage in full adhesion)."""

    x: np.ndarray
    s: np.ndarray
    pressure: np.ndarray
    px: np.ndarray
    py: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    adhesion: np.ndarray
    power_density: np.ndarray
    Fx: float
    Fy: float
    Mz: float
    normal_force: float
    power_local: float
    power_global: float
    adhesion_area: float
    slip_area: float
    speed: float
    iterations: int
    krylov_iterations: int
    residual: float
    adhesion_residual: float

    @property
    def traction(self):
        """|p| [Pa] (nx, ns)."""
        return np.hypot(self.px, self.py)

    @property
    def slip_fraction(self):
        """Slip area over contact area [-]."""
        total = self.adhesion_area + self.slip_area
        return self.slip_area / total if total > 0 else 0.0


def _scalar(value, name):
    v = as_float_array(value, name)
    if v.ndim != 0:
        raise ScenarioError(f"{name} must be a single number")
    return float(v)


def rolling_contact(x, s, pressure, xi, eta, phi, mu, shear_modulus, poisson, speed=1.0, tol=1e-8,
                    max_iterations=500):
    """Steady-state rolling contact of quasi-identical elastic half-spaces (module docstring).

    x, s: element centres along and across rolling [m] (equally spaced, as
    :func:`railwear.contact.halfspace_contact` takes them); pressure: the normal pressure at
    the elements [Pa], shape (x.size, s.size), zero outside the contact (e.g. ``.pressure`` of a
    :class:`~railwear.contact.HalfSpaceContact`); xi [-] (a number, or one value per strip,
    shape (s.size,)), eta [-], phi [1/m]: the creepages, rigid slip ``(ξ - φ s, η + φ x)``;
    mu [-]: friction coefficient (``inf`` for no slip, Kalker's linear theory); shear_modulus
    [Pa], poisson [-]: the combined constants of the pair; speed [m/s] scales the powers and
    slip velocities (the default 1 m/s gives them per unit speed); tol: stop when
    ``max |F| <= tol · max μ pn`` (module docstring); max_iterations: Newton steps at most.
    Returns a :class:`RollingContact`.
    """
    x, dx = _axis(x, "x")
    s, ds = _axis(s, "s")
    pn = non_negative(pressure, "pressure")
    if pn.shape != (x.size, s.size):
        raise ScenarioError(f"pressure must have shape (x.size, s.size) = {(x.size, s.size)}, got {pn.shape}")
    xi = as_float_array(xi, "xi")
    if xi.ndim == 0:
        xi = np.full(s.size, float(xi))
    elif xi.shape != (s.size,):
        raise ScenarioError(f"xi must be a number or have shape (s.size,) = ({s.size},), got {xi.shape}")
    eta, phi = _scalar(eta, "eta"), _scalar(phi, "phi")
    try:
        mu = float(mu)
    except (TypeError, ValueError):
        raise ScenarioError("mu must be a number") from None
    if not (mu >= 0.0):  # also NaN
        raise ScenarioError(f"mu must be >= 0 (inf for no slip), got {mu:g}")
    G = float(positive(_scalar(shear_modulus, "shear_modulus"), "shear_modulus"))
    nu = float(poisson_ratio(_scalar(poisson, "poisson"), "poisson"))
    speed = float(non_negative(_scalar(speed, "speed"), "speed"))
    tol = float(positive(_scalar(tol, "tol"), "tol"))
    if not (isinstance(max_iterations, (int, np.integer)) and max_iterations >= 1):
        raise ScenarioError(f"max_iterations must be a positive integer, got {max_iterations!r}")

    from scipy.sparse import linalg as sla  # only here: keeps ``import railwear.contact`` light

    on = pn > 0.0
    px, py = np.zeros(pn.shape), np.zeros(pn.shape)
    slip_x, slip_y = np.zeros(pn.shape), np.zeros(pn.shape)
    adhesion = np.zeros(pn.shape, dtype=bool)
    wx_full = xi[None, :] - phi * s[None, :] + 0.0 * x[:, None]
    wy_full = eta + phi * x[:, None] + 0.0 * s[None, :]
    iterations, krylov, change, residual_s = 0, 0, 0.0, 0.0
    if on.any() and mu > 0.0:
        ii, jj = np.nonzero(on)
        i0, i1, j0, j1 = ii.min(), ii.max() + 1, jj.min(), jj.max() + 1
        nbx, nbs = i1 - i0, j1 - j0
        order = np.lexsort((jj, -ii))  # leading edge (largest x) first, then across
        ci, cj = (ii[order] - i0).astype(np.int64), (jj[order] - j0).astype(np.int64)
        g = mu * pn[ii[order], jj[order]]
        wx = np.ascontiguousarray(wx_full[ii[order], jj[order]])
        wy = np.ascontiguousarray(wy_full[ii[order], jj[order]])
        kxx, _, kyy = tangential_influence_coefficients(np.array([0.0, dx]), 0.0, dx, ds, G, nu)
        bx, by = float(kxx[0] - kxx[1]) / dx, float(kyy[0] - kyy[1]) / dx  # B = (A(0) - A(dx)) / dx
        # the box and one row upstream of it, for the upwind difference
        conv = {c: _Convolution(nbx + 1, nbs, dx, ds, G, c, nu) for c in ("xx", "xy", "yy")}
        bpx, bpy = np.zeros((nbx + 1, nbs)), np.zeros((nbx + 1, nbs))

        def field(qx, qy):
            bpx[ci, cj], bpy[ci, cj] = qx, qy
            ux = conv["xx"](bpx) + conv["xy"](bpy)
            uy = conv["xy"](bpx) + conv["yy"](bpy)
            vx = (ux[1:] - ux[:-1]) / dx
            vy = (uy[1:] - uy[:-1]) / dx
            return np.ascontiguousarray(vx[ci, cj]), np.ascontiguousarray(vy[ci, cj])

        n = ci.size
        index = -np.ones((nbx + 1, nbs), dtype=np.int64)
        index[ci, cj] = np.arange(n)
        up = np.ascontiguousarray(index[ci + 1, cj])  # the element upstream in the strip, or -1
        c = 2.0 / (bx + by)
        q = np.zeros(2 * n)
        fx, fy, theta, ex, ey = (np.zeros(n) for _ in range(5))
        finite = np.isfinite(mu)
        scale = float(g.max()) if finite else c * float(np.max(np.hypot(wx, wy)))

        def residual(q):
            vx, vy = field(q[:n], q[n:])
            worst = _project(q[:n], q[n:], wx - vx, wy - vy, g, c, fx, fy, theta, ex, ey)
            return np.concatenate((fx, fy)), worst

        def jac(d):
            d = np.ascontiguousarray(d)
            vx, vy = field(d[:n], d[n:])
            ox, oy = np.empty(n), np.empty(n)
            _jacobian(d[:n], d[n:], vx, vy, c, theta, ex, ey, ox, oy)
            return np.concatenate((ox, oy))

        def prec(r):
            r = np.ascontiguousarray(r)
            ox, oy = np.zeros(n), np.zeros(n)
            _precondition(r[:n], r[n:], up, c, bx, by, theta, ex, ey, ox, oy)
            return np.concatenate((ox, oy))

        J = sla.LinearOperator((2 * n, 2 * n), matvec=jac, dtype=float)
        P = sla.LinearOperator((2 * n, 2 * n), matvec=prec, dtype=float)
        F, worst = residual(q)
        norm = float(np.linalg.norm(F))
        krylov = 0
        for iterations in range(1, max_iterations + 1):
            if worst <= tol * scale:
                break
            counter = [0]
            step, _ = sla.gmres(J, -F, M=P, rtol=min(1e-3, max(1e-10, 0.1 * worst / scale)), atol=0.0,
                                restart=60, maxiter=20, callback=lambda _: counter.__setitem__(0, counter[0] + 1),
                                callback_type="pr_norm")
            krylov += counter[0]
            alpha = 1.0
            for _ in range(30):  # backtracking on |F|
                trial = q + alpha * step
                F_t, worst_t = residual(trial)
                norm_t = float(np.linalg.norm(F_t))
                if norm_t <= (1.0 - 1e-4 * alpha) * norm:
                    break
                alpha *= 0.5
            q, F, worst, norm = trial, F_t, worst_t, norm_t
        change = worst / scale if scale > 0 else 0.0
        qx, qy = q[:n].copy(), q[n:].copy()
        vx, vy = field(qx, qy)
        residual(q)
        slipping = theta <= 1.0
        sx, sy = wx - vx, wy - vy
        left_x, left_y = sx[~slipping], sy[~slipping]
        sx[~slipping], sy[~slipping] = 0.0, 0.0
        ref = float(np.max(np.hypot(sx, sy))) if slipping.any() else float(np.max(np.hypot(wx, wy)))
        residual_s = float(np.max(np.hypot(left_x, left_y)) / ref) if left_x.size and ref > 0 else 0.0
        sel = (ii[order], jj[order])
        px[sel], py[sel], slip_x[sel], slip_y[sel] = qx, qy, sx, sy
        adhesion[sel] = ~slipping
    elif on.any():  # frictionless: no traction, the rigid slip everywhere
        slip_x[on], slip_y[on] = wx_full[on], wy_full[on]
    cell = dx * ds
    power_density = speed * np.hypot(px, py) * np.hypot(slip_x, slip_y)
    Fx, Fy = float(px.sum() * cell), float(py.sum() * cell)
    Mz = float(np.sum(x[:, None] * py - s[None, :] * px) * cell)
    return RollingContact(
        x=x, s=s, pressure=pn, px=px, py=py, slip_x=slip_x, slip_y=slip_y, adhesion=adhesion,
        power_density=power_density, Fx=Fx, Fy=Fy, Mz=Mz, normal_force=float(pn.sum() * cell),
        power_local=float(power_density.sum() * cell),
        power_global=float(-speed * np.sum(px * wx_full + py * wy_full) * cell),
        adhesion_area=float(adhesion.sum() * cell), slip_area=float((on & ~adhesion).sum() * cell),
        speed=speed, iterations=int(iterations), krylov_iterations=int(krylov), residual=float(change),
        adhesion_residual=residual_s)
