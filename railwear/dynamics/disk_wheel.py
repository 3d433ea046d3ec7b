"""The disk wheel of paper Fig. 5 over a worn radius ``u(x)`` (``DiskWheelModel``)."""

from __future__ import annotations

import math
import types
from dataclasses import dataclass

import numpy as np

from railwear.contact.creep_tables import fastsim_creep_curve
from railwear.dynamics import kernels as k
from railwear.dynamics._fields import check, number
from railwear.dynamics.creep_law import check_creep_law
from railwear.errors import ScenarioError

__all__ = ["DiskWheelModel"]


_INTERPRETED = {}  # compiled kernel -> its interpreted form


def _interpreted(kernel):
    """The compiled ``kernel``'s own source run by the interpreter, with every compiled function
    it calls interpreted too. The same operations in the same order give the same floating-point
    numbers (no fast-math in the kernels); a few calls from Python then need neither numba's
    registries nor a cache load (0.3-0.4 s of CPU in a fresh process)."""
    if kernel not in _INTERPRETED:
        source = kernel.py_func
        names = dict(source.__globals__)
        _INTERPRETED[kernel] = types.FunctionType(source.__code__, names, source.__name__, source.__defaults__)
        for name in source.__code__.co_names:
            if hasattr(names.get(name), "py_func"):  # a compiled callee
                names[name] = _interpreted(names[name])
    return _INTERPRETED[kernel]


def _bracketed_root(f, a, b, xtol, rtol, maxiter=100):
    """A root of ``f`` in ``[a, b]`` (``f(a)``, ``f(b)`` of opposite signs) by Brent's method:
    inverse quadratic or secant steps, a bisection where they would not shrink the bracket fast
    enough, to ``|x - root| <= xtol + rtol |x|``. Written out so that a steady creepage does not
    import scipy.optimize (0.07-0.16 s of a command's start) for one root; its steps are those of
    ``scipy.optimize.brentq``, so the root is the same bit for bit (tests/dynamics/test_disk_wheel_interpreted.py)."""
    x_old, x = a, b
    f_old, fx = f(x_old), f(x)
    if f_old == 0.0:
        return x_old
    if fx == 0.0:
        return x
    if math.copysign(1.0, f_old) == math.copysign(1.0, fx):
        raise ValueError("the bracket's ends must give values of opposite signs")
    far = f_far = step = last_step = 0.0
    for _ in range(maxiter):
        if f_old != 0.0 and fx != 0.0 and math.copysign(1.0, f_old) != math.copysign(1.0, fx):
            far, f_far = x_old, f_old  # the root lies between x and far
            step = last_step = x - x_old
        if abs(f_far) < abs(fx):  # keep the smaller value at x
            x_old, x, far = x, far, x
            f_old, fx, f_far = fx, f_far, fx
        tol = (xtol + rtol * abs(x)) / 2
        half = (far - x) / 2
        if fx == 0.0 or abs(half) < tol:
            return x
        if abs(last_step) > tol and abs(fx) < abs(f_old):
            if x_old == far:  # secant through x_old and x
                trial = -fx * (x - x_old) / (fx - f_old)
            else:  # inverse quadratic through x_old, x and far
                slope_old = (f_old - fx) / (x_old - x)
                slope_far = (f_far - fx) / (far - x)
                trial = -fx * (f_far * slope_far - f_old * slope_old) / (slope_far * slope_old * (f_far - f_old))
            if 2 * abs(trial) < min(abs(last_step), 3 * abs(half) - tol):
                last_step, step = step, trial
            else:
                last_step = step = half
        else:
            last_step = step = half
        x_old, f_old = x, fx
        x += step if abs(step) > tol else (tol if half > 0 else -tol)
        fx = f(x)
    raise RuntimeError(f"no root within {maxiter} steps")


@dataclass(frozen=True, eq=False)
class DiskWheelModel:
    """Disk wheel of paper Fig. 5: vertical and rotational motion of a wheel rolling at ``speed``.

    The wheel (``wheel_mass``, polar ``wheel_inertia``) hangs from a primary spring-damper under a
    ``sprung_mass`` (``None``: a rigid frame). The rail is rigid (``rail_mass=None``) or a mass on
    a pad-sleeper spring-damper (the P2 resonance). Hertzian contact ``N = k_H delta^(3/2)``
    (``hertz_constant`` [N/m^1.5]) carrying ``static_load`` [N] at rest, no tension (N >= 0).
    ``f11`` [N] is Kalker's longitudinal coefficient at the static load; it scales with
    ``(N/W)^(2/3)``. ``traction_torque`` [N m] sets the creepage. ``radius_deviation`` holds
    ``u`` [m] at the angles ``2 pi j / n`` (``None``: round wheel); the contact reads its mean
    over ``+- patch_half_length / radius`` about the contact angle. ``creep_law``: ``"cubic"``
    (Johnson-Vermeulen saturation of Kalker's linear force) or ``"fastsim"`` (FASTSIM's creep
    curve for pure longitudinal creepage, from ``railwear.contact.fastsim``).
    """

    speed: float
    radius: float
    wheel_mass: float
    wheel_inertia: float
    static_load: float
    hertz_constant: float
    primary_stiffness: float
    f11: float
    primary_damping: float = 0.0
    sprung_mass: float | None = None
    rail_mass: float | None = None
    pad_stiffness: float = 0.0
    pad_damping: float = 0.0
    friction_coefficient: float = math.inf
    traction_torque: float = 0.0
    patch_half_length: float = 0.0
    radius_deviation: np.ndarray | None = None
    initial_angle: float = 0.0
    initial_lift: float = 0.0
    initial_vertical_velocity: float = 0.0
    creep_law: str = "cubic"

    kind = k.KIND_DISK_WHEEL
    CREEP_LAWS = ("cubic", "fastsim")
    n_states = 8
    default_atol = 1e-13

    def __post_init__(self):
        positive = ["speed", "radius", "wheel_mass", "wheel_inertia", "static_load", "hertz_constant"]
        if self.sprung_mass is not None:
            positive.append("sprung_mass")
        if self.rail_mass is not None:
            positive += ["rail_mass", "pad_stiffness"]
        check(
            self,
            positive=positive,
            nonnegative=("primary_stiffness", "primary_damping", "pad_damping", "f11", "patch_half_length"),
            finite=(
                "primary_stiffness", "primary_damping", "pad_damping", "f11", "traction_torque", "patch_half_length",
                "initial_angle", "initial_lift", "initial_vertical_velocity",
            ),
        )
        if not number(self, "friction_coefficient") > 0.0:
            raise ScenarioError(
                f"friction_coefficient: must be positive (inf for no saturation), got {self.friction_coefficient!r}"
            )
        check_creep_law(self)
        object.__setattr__(self, "_creep_curve", fastsim_creep_curve() if self.creep_law == "fastsim" else np.zeros(0))
        if self.radius_deviation is not None:
            u = np.array(self.radius_deviation, dtype=float)
            if u.ndim != 1 or u.size < 2 or not np.all(np.isfinite(u)):
                raise ScenarioError("radius_deviation: must be a 1-D array of at least 2 finite values [m]")
            if np.max(np.abs(u)) >= 0.1 * self.radius:
                raise ScenarioError("radius_deviation: deviations must stay below 10 % of the radius")
            u.setflags(write=False)
            object.__setattr__(self, "radius_deviation", u)
        if self.patch_half_length >= 0.5 * self.radius:
            raise ScenarioError(f"patch_half_length: must be well below the radius, got {self.patch_half_length!r}")
        approach = self.initial_approach()
        if approach <= 0.0:
            raise ScenarioError(
                f"initial_lift: the wheel starts above the rail (approach {approach:.3g} m from lift "
                f"{self.initial_lift!r} m and the radius deviation under the contact)"
            )
        self.steady_creepage()  # validates the traction torque

    @property
    def static_approach(self) -> float:
        """Hertzian approach under the static load, ``(W / k_H)^(2/3)`` [m]."""
        return (self.static_load / self.hertz_constant) ** (2.0 / 3.0)

    @property
    def contact_stiffness(self) -> float:
        """Linearised contact stiffness ``dN/d delta = 3 W / (2 delta_0)`` [N/m]."""
        return 1.5 * self.static_load / self.static_approach

    def surface(self) -> np.ndarray:
        """The kernel's surface array for the model's own ``radius_deviation``."""
        if self.radius_deviation is None:
            return self._creep_curve.copy()
        return self.surface_for(self.radius_deviation)

    def surface_for(self, u) -> np.ndarray:
        """The kernel's surface array for another radius deviation ``u`` [m] on the model's grid
        (a wear step changes ``u`` but not the model): ``u`` at the nodes, its cumulative
        trapezoidal integral, then the FASTSIM creep curve if that law is chosen. Use it with
        ``params()``, whose offsets assume this layout."""
        u = np.asarray(u, dtype=float)
        if u.shape != (self.n_cells(),):
            raise ScenarioError(f"radius_deviation: expected {self.n_cells()} values on the model's grid, got {u.shape}")
        dx = 2.0 * math.pi / u.size
        cum = np.concatenate([[0.0], np.cumsum(0.5 * dx * (u + np.roll(u, -1)))])
        return np.concatenate([u, cum, self._creep_curve])

    def n_cells(self) -> int:
        return 0 if self.radius_deviation is None else int(self.radius_deviation.size)

    def filtered_deviation(self, angle) -> float:
        """The contact filter at ``angle`` [rad]: ``u`` averaged over the patch [m]."""
        return float(k.patch_average(self.surface(), self.n_cells(), float(angle), self.patch_half_length / self.radius))

    def initial_approach(self) -> float:
        """Approach ``delta`` at the start [m]; must be positive (wheel in contact)."""
        ubar = 0.0 if self.radius_deviation is None else self.filtered_deviation(self.initial_angle)
        return self.static_approach - self.initial_lift + ubar

    def steady_creepage(self) -> float:
        """Creepage at which the creep force at the static load balances the torque, ``F = T / R0``."""
        demand = self.traction_torque / self.radius
        if demand == 0.0:
            return 0.0
        limit = self.friction_coefficient * self.static_load
        if abs(demand) >= limit:
            raise ScenarioError(
                f"traction_torque: {self.traction_torque!r} N m needs more than the adhesion limit "
                f"mu W R0 = {limit * self.radius:.6g} N m"
            )
        if self.f11 <= 0.0:
            raise ScenarioError("f11: must be positive when a traction_torque is applied")

        def residual(xi):
            force = self.f11 * xi
            if self.creep_law == "fastsim":
                curve, s = self._creep_curve, abs(force) / limit
                ratio = np.interp(s / (1.0 + s), np.linspace(0.0, 1.0, curve.size), curve)
                return math.copysign(limit * ratio, force) - demand
            return force * _interpreted(k.saturation_factor)(abs(force), limit) - demand

        xi_lin = demand / self.f11
        if not math.isfinite(limit):
            return xi_lin
        upper = 3.0 * xi_lin
        while residual(upper) * np.sign(demand) < 0.0:  # FASTSIM approaches full slip slowly
            upper *= 2.0
        return _bracketed_root(residual, 0.0, upper, xtol=1e-16, rtol=1e-14)

    def params(self) -> np.ndarray:
        p = np.zeros(k.DW_N_PARAMS)
        p[k.DW_SPEED] = self.speed
        p[k.DW_RADIUS] = self.radius
        p[k.DW_WHEEL_MASS] = self.wheel_mass
        p[k.DW_WHEEL_INERTIA] = self.wheel_inertia
        p[k.DW_SPRUNG_MASS] = 0.0 if self.sprung_mass is None else self.sprung_mass
        p[k.DW_PRIMARY_STIFFNESS] = self.primary_stiffness
        p[k.DW_PRIMARY_DAMPING] = self.primary_damping
        p[k.DW_RAIL_MASS] = 0.0 if self.rail_mass is None else self.rail_mass
        p[k.DW_PAD_STIFFNESS] = self.pad_stiffness
        p[k.DW_PAD_DAMPING] = self.pad_damping
        p[k.DW_HERTZ_CONSTANT] = self.hertz_constant
        p[k.DW_STATIC_LOAD] = self.static_load
        p[k.DW_STATIC_APPROACH] = self.static_approach
        p[k.DW_F11] = self.f11
        p[k.DW_FRICTION] = self.friction_coefficient
        p[k.DW_TORQUE] = self.traction_torque
        p[k.DW_PATCH_HALF_ANGLE] = self.patch_half_length / self.radius
        p[k.DW_INITIAL_ANGLE] = self.initial_angle
        p[k.DW_N_CELLS] = self.n_cells()
        p[k.DW_CREEP_LAW] = self.CREEP_LAWS.index(self.creep_law)
        p[k.DW_CREEP_TABLE_OFFSET] = 0 if self.radius_deviation is None else 2 * self.n_cells() + 1
        p[k.DW_CREEP_TABLE_POINTS] = self._creep_curve.size
        return p

    def initial_state(self) -> np.ndarray:
        """``[phi, Omega, z_w, z_w', z_s, z_s', z_r, z_r']`` at the start: steady rolling at the
        steady creepage, the wheel lifted by ``initial_lift`` from static equilibrium."""
        y = np.zeros(self.n_states)
        ubar = 0.0 if self.radius_deviation is None else self.filtered_deviation(self.initial_angle)
        y[1] = self.speed * (1.0 + self.steady_creepage()) / (self.radius + ubar)
        y[2] = self.initial_lift
        y[3] = self.initial_vertical_velocity
        return y

    def vertical_matrices(self):
        """Mass, damping and stiffness matrices of the vertical motion linearised about static
        equilibrium, DOFs ``[z_w, z_s?, z_r?]``, with the forcing vector of ``u_bar`` [N/m]."""
        kc = self.contact_stiffness
        dofs = ["wheel"]
        dofs += ["sprung"] if self.sprung_mass is not None else []
        dofs += ["rail"] if self.rail_mass is not None else []
        n = len(dofs)
        m, c, kk, f = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
        m[0, 0] = self.wheel_mass
        kk[0, 0] += self.primary_stiffness + kc
        c[0, 0] += self.primary_damping
        f[0] = kc
        if "sprung" in dofs:
            i = dofs.index("sprung")
            m[i, i] = self.sprung_mass
            kk[i, i] += self.primary_stiffness
            c[i, i] += self.primary_damping
            kk[0, i] = kk[i, 0] = -self.primary_stiffness
            c[0, i] = c[i, 0] = -self.primary_damping
        if "rail" in dofs:
            i = dofs.index("rail")
            m[i, i] = self.rail_mass
            kk[i, i] += self.pad_stiffness + kc
            c[i, i] += self.pad_damping
            kk[0, i] = kk[i, 0] = -kc
            f[i] = -kc
        return dofs, m, c, kk, f

    LINEAR_OUTPUTS = ("normal_force", "creepage", "creep_force", "frictional_power")

    def linearisation(self):
        """``(A, B, C, D)`` of steady rolling (at the steady creepage of the torque) with the
        filtered radius deviation ``u_bar`` as input: ``x' = A x + B u_bar``,
        ``[N, xi, Fx, power] = C x + D u_bar`` (deviations from steady rolling), by central
        differences of the kernel (its source interpreted: the compiled kernel's numbers). The
        rotation angle ``phi`` only drifts and does not act on the rest (a uniform ``u`` makes
        ``x_c`` irrelevant)."""
        p = self.params()
        p[k.DW_N_CELLS] = 2
        p[k.DW_CREEP_TABLE_OFFSET] = 5  # after the uniform surface's 2 nodes and 3 cumulative values
        y0 = self.initial_state()
        n = self.n_states
        omega_c = math.sqrt(self.contact_stiffness / self.wheel_mass)
        d0 = self.static_approach
        steps = np.array([1e-6, 1e-7 * y0[1], 1e-4 * d0, 1e-4 * d0 * omega_c, 1e-4 * d0, 1e-4 * d0 * omega_c,
                          1e-4 * d0, 1e-4 * d0 * omega_c])
        du = 1e-4 * d0

        # the kernels' source interpreted: 36 calls, bit for bit the compiled ones' numbers; on lists
        # of Python floats (the same double arithmetic, read faster than numpy's scalars)
        rhs, outputs = _interpreted(k.disk_wheel_rhs), _interpreted(k.disk_wheel_outputs)
        p, curve = p.tolist(), self._creep_curve.tolist()

        def evaluate(y, u):
            f, g = [0.0] * n, [0.0] * k.DW_N_OUTPUTS
            surf = [u, u, 0.0, u * math.pi, 2.0 * u * math.pi] + curve  # a uniform u, its primitive, the curve
            y = y.tolist()
            rhs(0.0, y, p, surf, f)
            outputs(0.0, y, p, surf, g)
            return np.array(f), np.array(g[:4])

        a, c = np.zeros((n, n)), np.zeros((4, n))
        for j in range(n):
            yp, ym = y0.copy(), y0.copy()
            yp[j] += steps[j]
            ym[j] -= steps[j]
            (fp, gp), (fm, gm) = evaluate(yp, 0.0), evaluate(ym, 0.0)
            a[:, j] = (fp - fm) / (2 * steps[j])
            c[:, j] = (gp - gm) / (2 * steps[j])
        (fp, gp), (fm, gm) = evaluate(y0, du), evaluate(y0, -du)
        return a, (fp - fm) / (2 * du), c, (gp - gm) / (2 * du)

    def transfer(self, angular_frequency, output="frictional_power") -> np.ndarray:
        """Linear transfer function from ``u_bar`` to ``output`` (one of ``LINEAR_OUTPUTS``) at
        ``angular_frequency`` [rad/s]: ``C (i w - A)^-1 B + D`` (complex, ``exp(i w t)``).
        A harmonic ``u`` of order ``n`` excites ``w = n Omega`` with ``Omega`` the wheel's
        angular velocity (``V (1 + xi) / R0`` under traction)."""
        if output not in self.LINEAR_OUTPUTS:
            raise ScenarioError(f"output: must be one of {self.LINEAR_OUTPUTS}, got {output!r}")
        a, b, c, d = self.linearisation()
        row = self.LINEAR_OUTPUTS.index(output)
        omega = np.atleast_1d(np.asarray(angular_frequency, dtype=float))
        # one batched solve over the frequencies (a Python loop of 4x4 solves cost 15 us each)
        x = np.linalg.solve(1j * omega[:, None, None] * np.eye(self.n_states) - a,
                            np.broadcast_to(b.astype(complex)[:, None], omega.shape + (b.size, 1)))
        out = (c[row] @ x)[..., 0] + d[row]
        return out if np.ndim(angular_frequency) else out[0]

    def contact_force_transfer(self, angular_frequency) -> np.ndarray:
        """Linear transfer function ``N_hat / u_hat`` [N/m] from the filtered radius deviation to
        the dynamic normal force at ``angular_frequency`` [rad/s] (complex, ``exp(i w t)``)."""
        dofs, m, c, kk, f = self.vertical_matrices()
        omega = np.atleast_1d(np.asarray(angular_frequency, dtype=float))
        rail = dofs.index("rail") if "rail" in dofs else None
        w = omega[:, None, None]
        z = np.linalg.solve(-w * w * m + 1j * w * c + kk, np.broadcast_to(f.astype(complex)[:, None],
                                                                            omega.shape + (f.size, 1)))[..., 0]
        relative = (z[:, rail] if rail is not None else 0.0) - z[:, 0]
        out = self.contact_stiffness * (relative + 1.0)
        return out if np.ndim(angular_frequency) else out[0]
