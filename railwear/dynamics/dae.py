"""Constrained multibody systems as index-2 DAEs (Gear-Gupta-Leimkuhler form), solved with IDA.

Paper eq. (1), ``M(q) v' = f(t, q, v) - G(q)^T lam``, ``0 = g(q)``, has index 3. The GGL
stabilisation adds the velocity constraint and a second multiplier ``mu``:

    q' = v - G(q)^T mu
    M(q) v' = f(t, q, v) - G(q)^T lam
    0 = g(q)
    0 = G(q) v

(Gear, Gupta & Leimkuhler 1985), an index-2 system in which both the position and the velocity
constraints hold; ``mu`` vanishes on exact solutions. SUNDIALS IDA (through scikit-sundae) solves
it with the multipliers left out of the error test (a very large absolute tolerance on them).
Two generalisations serve the rolling wheel: the constraint forces may act along ``H(q)^T lam``
instead of ``G^T lam`` (a model that lets the normal force act vertically only), and applied
forces may depend on the multipliers (creep forces limited by the normal force).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railwear.errors import NumericalInstabilityError, ScenarioError

__all__ = [
    "GGLProblem",
    "GGLSolution",
    "bogie_ggl_problem",
    "disk_wheel_dae_outputs",
    "disk_wheel_ggl_problem",
    "planar_pendulum",
    "solve_ggl",
    "wheelset_ggl_problem",
]


@dataclass(frozen=True)
class GGLProblem:
    """A constrained system: ``mass(q)`` (n x n), ``force(t, q, v)`` (n), ``constraint(t, q)``
    (m), ``constraint_jacobian(t, q)`` (m x n, ``G = dg/dq``) and, for constraints that move
    with time (a rotating out-of-round wheel), ``constraint_rate(t, q)`` = ``dg/dt`` (m; ``None``:
    zero). Optional: ``reaction_jacobian(t, q)`` (m x n), the directions ``H`` of the constraint
    forces ``-H^T lam`` (``None``: ``G``; ``G M^-1 H^T`` must be invertible), and
    ``multiplier_force(t, q, v, lam)`` (n), applied forces that depend on the multipliers.
    Callables take and return NumPy arrays, SI units."""

    n_coordinates: int
    n_constraints: int
    mass: object
    force: object
    constraint: object
    constraint_jacobian: object
    constraint_rate: object = None
    reaction_jacobian: object = None
    multiplier_force: object = None

    def _rate(self, t, q):
        return np.zeros(self.n_constraints) if self.constraint_rate is None else self.constraint_rate(t, q)

    def _reaction(self, t, q, jac):
        return jac if self.reaction_jacobian is None else self.reaction_jacobian(t, q)

    def _force(self, t, q, v, lam):
        force = self.force(t, q, v)
        return force if self.multiplier_force is None else force + self.multiplier_force(t, q, v, lam)

    def residual(self, t, y, yp, res):
        """GGL residual for ``y = [q, v, lam, mu]`` (IDA's ``resfn``)."""
        n, m = self.n_coordinates, self.n_constraints
        q, v, lam, mu = y[:n], y[n:2 * n], y[2 * n:2 * n + m], y[2 * n + m:]
        jac = self.constraint_jacobian(t, q)
        res[:n] = yp[:n] - v + jac.T @ mu
        res[n:2 * n] = self.mass(q) @ yp[n:2 * n] - self._force(t, q, v, lam) + self._reaction(t, q, jac).T @ lam
        res[2 * n:2 * n + m] = self.constraint(t, q)
        res[2 * n + m:] = jac @ v + self._rate(t, q)

    def consistent_start(self, t0, q0, v0):
        """``(y0, yp0)`` with the multiplier ``lam`` from the acceleration-level constraint
        ``G a + d/dt(G) v + d/dt(g_t) = 0`` (the total derivatives along the motion by central
        differences) and ``mu = 0``; ``q0, v0`` must satisfy both constraints. Forces that depend
        on ``lam`` are iterated to a fixed point."""
        n, m = self.n_coordinates, self.n_constraints
        q0, v0 = np.asarray(q0, dtype=float), np.asarray(v0, dtype=float)
        scale = max(1.0, float(np.max(np.abs(q0))))
        if np.max(np.abs(self.constraint(t0, q0))) > 1e-10 * scale:
            raise ScenarioError("initial_state: the positions violate the constraints g(q) = 0")
        jac = self.constraint_jacobian(t0, q0)

        def velocity_constraint(t, q):
            return self.constraint_jacobian(t, q) @ v0 + self._rate(t, q)

        if np.max(np.abs(velocity_constraint(t0, q0))) > 1e-10 * max(1.0, float(np.max(np.abs(v0)))):
            raise ScenarioError("initial_state: the velocities violate the constraints G(q) v + g_t = 0")
        h = 1e-6
        drift = (velocity_constraint(t0 + h, q0 + h * v0) - velocity_constraint(t0 - h, q0 - h * v0)) / (2 * h)
        system = np.zeros((n + m, n + m))
        system[:n, :n] = self.mass(q0)
        system[:n, n:] = self._reaction(t0, q0, jac).T
        system[n:, :n] = jac
        lam = np.zeros(m)
        for _ in range(50):
            sol = np.linalg.solve(system, np.concatenate([self._force(t0, q0, v0, lam), -drift]))
            converged = np.max(np.abs(sol[n:] - lam)) <= 1e-13 * max(1.0, float(np.max(np.abs(sol[n:]))))
            lam = sol[n:]
            if self.multiplier_force is None or converged:
                break
        else:
            raise NumericalInstabilityError("consistent start: the multipliers did not converge")
        y0 = np.concatenate([q0, v0, sol[n:], np.zeros(m)])
        yp0 = np.concatenate([v0, sol[:n], np.zeros(2 * m)])
        return y0, yp0


@dataclass(frozen=True)
class GGLSolution:
    """Times [s], coordinates, velocities, multipliers ``lam`` and ``mu`` (rows per time) and the
    largest position-constraint violation over the run."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    lam: np.ndarray
    mu: np.ndarray
    constraint_drift: float


def solve_ggl(problem, t_eval, q0, v0, rtol=1e-8, atol=1e-10, multiplier_atol=1e10, max_num_steps=100_000):
    """Integrate the GGL form of ``problem`` with IDA (BDF, variable order), output at ``t_eval``.

    The multipliers are algebraic variables excluded from the error test through
    ``multiplier_atol``. Raises ``NumericalInstabilityError`` if IDA fails."""
    from sksundae.ida import IDA

    n, m = problem.n_coordinates, problem.n_constraints
    t_eval = np.asarray(t_eval, dtype=float)
    if t_eval.ndim != 1 or t_eval.size < 2 or np.any(np.diff(t_eval) <= 0.0):
        raise ScenarioError("t_eval: must be a strictly increasing array of at least two times [s]")
    if not (1e-14 <= rtol < 1.0) or not atol > 0.0:
        raise ScenarioError(f"rtol: tolerances cannot be met (rtol={rtol!r}, atol={atol!r})")
    y0, yp0 = problem.consistent_start(t_eval[0], q0, v0)
    atol_vec = np.concatenate([np.full(2 * n, atol), np.full(2 * m, multiplier_atol)])
    solver = IDA(problem.residual, algebraic_idx=list(range(2 * n, 2 * n + 2 * m)), rtol=rtol, atol=atol_vec,
                 max_num_steps=max_num_steps)
    result = solver.solve(t_eval, y0, yp0)
    if not result.success or result.y.shape[0] != t_eval.size:
        raise NumericalInstabilityError(f"IDA failed: {result.message}")
    y = result.y
    drift = max(float(np.max(np.abs(problem.constraint(t, row[:n])))) for t, row in zip(result.t, y))
    return GGLSolution(result.t, y[:, :n], y[:, n:2 * n], y[:, 2 * n:2 * n + m], y[:, 2 * n + m:], drift)


def planar_pendulum(mass=1.0, length=1.0, gravity=9.81) -> GGLProblem:
    """Point mass on a massless rod in Cartesian coordinates ``(x, y)``, ``y`` up:
    ``g(q) = (x^2 + y^2 - L^2) / 2``; ``lam`` is the rod tension over the length."""
    mass_matrix = np.eye(2) * mass
    weight = np.array([0.0, -mass * gravity])
    return GGLProblem(
        n_coordinates=2,
        n_constraints=1,
        mass=lambda q: mass_matrix,
        force=lambda t, q, v: weight,
        constraint=lambda t, q: np.array([0.5 * (q[0] ** 2 + q[1] ** 2 - length**2)]),
        constraint_jacobian=lambda t, q: q.reshape(1, 2),
    )


def _fixed_linear_constraints(mass_matrix, force, jac) -> GGLProblem:
    """A problem with a constant mass matrix and constant linear constraints ``jac @ q = 0``."""
    return GGLProblem(
        n_coordinates=jac.shape[1],
        n_constraints=jac.shape[0],
        mass=lambda q: mass_matrix,
        force=force,
        constraint=lambda t, q: jac @ q,
        constraint_jacobian=lambda t, q: jac,
    )


def wheelset_ggl_problem(model, roll_inertia, gravity=9.81) -> GGLProblem:
    """The suspended wheelset of ``model`` (a ``WheelsetModel``) with vertical motion and roll
    restricted by the contact constraints of conical wheels on knife-edge rails.

    Coordinates ``q = [y, z, phi, psi]`` (lateral, vertical from nominal, roll, yaw); the wheel
    over each rail touches it: ``g_left = z + e phi - lam y``, ``g_right = z - e phi + lam y``
    (contact geometry linearised in ``y`` and ``phi``). The multipliers are minus the normal
    forces, ``N_left + N_right = m g`` in the mean. Creep, suspension and flange forces come from
    the compiled wheelset kernel. Eliminating ``z`` and ``phi = lam y / e`` gives the minimal
    ODE with the lateral mass ``m + I_x (lam / e)^2``.
    """
    from railwear.dynamics import kernels as k

    e, lam = model.half_gauge, model.conicity
    mass_matrix = np.diag([model.mass, model.mass, roll_inertia, model.yaw_inertia])
    p = model.params()
    p[k.WS_MASS] = 1.0  # the kernel then returns forces and moments
    p[k.WS_YAW_INERTIA] = 1.0
    surf = np.zeros(0)
    jac = np.array([[-lam, 1.0, e, 0.0], [lam, 1.0, -e, 0.0]])
    out = np.empty(4)
    rhs = k.rhs.bind(k.KIND_WHEELSET, 0.0, np.zeros(4), p, surf, out)  # the entry point: no look-up per residual

    def force(t, q, v):
        rhs(k.KIND_WHEELSET, t, np.array([q[0], q[3], v[0], v[3]]), p, surf, out)
        return np.array([out[2], -model.mass * gravity, 0.0, out[3]])

    return _fixed_linear_constraints(mass_matrix, force, jac)


def disk_wheel_ggl_problem(model, rotation=False, initial_spin=None):
    """The disk wheel of ``model`` (a ``DiskWheelModel``) with rigid contact: the wheel follows
    the rail and the filtered radius deviation, ``g(t, q) = z_w - z_r - u_bar(x_c)``,
    ``x_c = x0 + V t / R0 + phi``.

    Coordinates ``q = [(phi), z_w, (z_s), (z_r)]``: the sprung mass and the rail mass where the
    model has them. Without ``rotation`` the wheel turns at ``V / R0`` and there is no creep.
    With it, ``phi`` is the wheel angle beyond ``V t / R0`` (as in the ODE), ``J phi'' = T -
    (R0 + u_bar) Fx`` with the creep force of the ODE model at the creepage ``(Omega (R0 +
    u_bar) - V) / V`` and the rigid-contact normal force; as in the ODE the normal force acts
    vertically only (no moment from the slope of ``u``). The normal force is ``N = W - lam``.
    Needs a patch (``patch_half_length > 0``) so that ``u_bar`` is smooth enough for the
    index-2 form. Returns ``(problem, q0, v0)``: the wheel on the deviation under it, at rest
    vertically relative to it, spinning at ``initial_spin`` [rad/s] (``None``: the model's
    initial spin, steady creepage).
    """
    from railwear.dynamics import kernels as k

    if not model.patch_half_length > 0.0:
        raise ScenarioError("patch_half_length: the DAE form needs a finite contact patch (a smooth u_bar)")
    surf, n_cells = model.surface(), model.n_cells()
    half = model.patch_half_length / model.radius
    rate = model.speed / model.radius
    x0 = model.initial_angle
    sprung = model.sprung_mass is not None
    rail = model.rail_mass is not None
    i_w = 1 if rotation else 0
    n = i_w + 1 + sprung + rail
    i_s, i_r = (i_w + 1 if sprung else None), (n - 1 if rail else None)
    masses = ([model.wheel_inertia] if rotation else []) + [model.wheel_mass]
    masses += ([model.sprung_mass] if sprung else []) + ([model.rail_mass] if rail else [])
    mass_matrix = np.diag(masses)
    vertical = np.zeros((1, n))
    vertical[0, i_w] = 1.0
    if rail:
        vertical[0, i_r] = -1.0

    def angle(t, q):
        return x0 + rate * t + (q[0] if rotation else 0.0)

    def u_bar(x):
        return k.patch_average(surf, n_cells, x, half)

    def u_bar_slope(x):
        if n_cells == 0:  # a round wheel
            return 0.0
        return (k.surface_value(surf, n_cells, x + half) - k.surface_value(surf, n_cells, x - half)) / (2.0 * half)

    def jacobian(t, q):
        if not rotation:
            return vertical
        jac = vertical.copy()
        jac[0, 0] = -u_bar_slope(angle(t, q))
        return jac

    def force(t, q, v):
        f = np.zeros(n)
        z_s, v_s = (q[i_s], v[i_s]) if sprung else (0.0, 0.0)
        primary = model.primary_stiffness * (q[i_w] - z_s) + model.primary_damping * (v[i_w] - v_s)
        f[i_w] = -primary
        if sprung:
            f[i_s] = primary
        if rail:
            f[i_r] = -model.pad_stiffness * q[i_r] - model.pad_damping * v[i_r]
        return f

    state = _disk_wheel_ode_state(model)
    p, dydt = model.params(), np.empty(model.n_states)
    rhs = []  # the entry point for the first residual's argument types: no look-up per residual after it

    def creep(t, q, v, lam):
        y = state(t, q, v, lam)
        if not rhs:
            rhs.append(k.rhs.bind(k.KIND_DISK_WHEEL, t, y, p, surf, dydt))
        rhs[0](k.KIND_DISK_WHEEL, t, y, p, surf, dydt)
        f = np.zeros(n)
        f[0] = model.wheel_inertia * dydt[1]  # the traction torque and the creep force's moment
        return f

    problem = GGLProblem(
        n_coordinates=n,
        n_constraints=1,
        mass=lambda q: mass_matrix,
        force=force,
        constraint=lambda t, q: np.array([q[i_w] - (q[i_r] if rail else 0.0) - u_bar(angle(t, q))]),
        constraint_jacobian=jacobian,
        constraint_rate=lambda t, q: np.array([-rate * u_bar_slope(angle(t, q))]),
        reaction_jacobian=(lambda t, q: vertical) if rotation else None,
        multiplier_force=creep if rotation else None,
    )
    spin = model.initial_state()[1] if initial_spin is None else float(initial_spin)
    q0 = np.zeros(n)
    q0[i_w] = u_bar(x0)
    if sprung:
        q0[i_s] = q0[i_w]  # the primary spring at its static length
    v0 = np.zeros(n)
    v0[i_w] = (spin if rotation else rate) * u_bar_slope(x0)
    if rotation:
        v0[0] = spin - rate
    return problem, q0, v0


def _disk_wheel_ode_state(model):
    """``state(t, q, v, lam)``: the ODE state of the disk wheel (``[phi, Omega, z_w, z_w', z_s,
    z_s', z_r, z_r']``) whose Hertz contact carries the rigid-contact normal force ``W - lam``, so
    that the compiled kernel gives the creepage and creep force of a rotating rigid-contact DAE
    state (``q = [phi, z_w, ...]``)."""
    from railwear.dynamics import kernels as k

    surf, n_cells, half = model.surface(), model.n_cells(), model.patch_half_length / model.radius
    y = np.zeros(model.n_states)

    def state(t, q, v, lam):
        normal = max(model.static_load - lam[0], 0.0)
        y[0] = q[0]
        y[1] = model.speed / model.radius + v[0]
        # the approach delta_0 + z_r - z_w + u_bar with z_w = 0 equals (N / k_H)^(2/3)
        x = model.initial_angle + model.speed / model.radius * t + q[0]
        y[6] = (normal / model.hertz_constant) ** (2.0 / 3.0) - model.static_approach - k.patch_average(
            surf, n_cells, x, half)
        return y

    return state


def disk_wheel_dae_outputs(model, solution):
    """Normal force, creepage, creep force and frictional power (SI, one row per time, the
    columns of ``kernels.disk_wheel_outputs``) of a rotating rigid-contact disk-wheel solution
    (``disk_wheel_ggl_problem(model, rotation=True)`` solved by ``solve_ggl``)."""
    from railwear.dynamics import kernels as k

    state = _disk_wheel_ode_state(model)
    ys = np.array([state(t, q, v, lam).copy() for t, q, v, lam in zip(solution.t, solution.q, solution.v,
                                                                      solution.lam)])
    out = k.outputs(k.KIND_DISK_WHEEL, np.asarray(solution.t, dtype=float), ys, model.params(), model.surface(),
                    k.DW_N_OUTPUTS)
    return out[:, :4]


def bogie_ggl_problem(model, roll_inertia, gravity=9.81) -> GGLProblem:
    """The bogie of ``model`` (a ``BogieModel``) with each wheelset's vertical motion and roll
    restricted by the conical knife-edge contact constraints, as in ``wheelset_ggl_problem``.

    Coordinates ``q = [y1, z1, phi1, psi1, y2, z2, phi2, psi2, y_f, psi_f]``; four constraints
    ``z_i +- e phi_i -+ lam y_i = 0``. Forces from the compiled bogie kernel. The ODE twin is the
    bogie with the wheelset mass ``m + I_x (lam / e)^2``.
    """
    from railwear.dynamics import kernels as k

    e, lam = model.half_gauge, model.conicity
    masses = [model.wheelset_mass, model.wheelset_mass, roll_inertia, model.wheelset_yaw_inertia] * 2
    mass_matrix = np.diag(masses + [model.frame_mass, model.frame_yaw_inertia])
    p = model.params()
    for index in (k.BG_WHEELSET_MASS, k.BG_WHEELSET_YAW_INERTIA, k.BG_FRAME_MASS, k.BG_FRAME_YAW_INERTIA):
        p[index] = 1.0  # the kernel then returns forces and moments
    surf = np.zeros(0)
    jac = np.zeros((4, 10))
    for i in range(2):
        jac[2 * i, 4 * i:4 * i + 3] = (-lam, 1.0, e)
        jac[2 * i + 1, 4 * i:4 * i + 3] = (lam, 1.0, -e)
    minimal = [0, 3, 4, 7, 8, 9]  # y1, psi1, y2, psi2, y_f, psi_f in q
    out = np.empty(12)
    rhs = k.rhs.bind(k.KIND_BOGIE, 0.0, np.zeros(12), p, surf, out)  # the entry point: no look-up per residual

    def force(t, q, v):
        rhs(k.KIND_BOGIE, t, np.concatenate([q[minimal], v[minimal]]), p, surf, out)
        f = np.zeros(10)
        f[minimal] = out[6:]
        f[[1, 5]] = -model.wheelset_mass * gravity
        return f

    return _fixed_linear_constraints(mass_matrix, force, jac)
