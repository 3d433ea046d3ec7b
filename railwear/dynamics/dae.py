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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from railwear.errors import NumericalInstabilityError, ScenarioError

__all__ = ["GGLProblem", "GGLSolution", "solve_ggl", "planar_pendulum", "wheelset_ggl_problem"]


@dataclass(frozen=True)
class GGLProblem:
    """A constrained system: ``mass(q)`` (n x n), ``force(t, q, v)`` (n), ``constraint(q)`` (m),
    ``constraint_jacobian(q)`` (m x n). Callables take and return NumPy arrays, SI units."""

    n_coordinates: int
    n_constraints: int
    mass: object
    force: object
    constraint: object
    constraint_jacobian: object

    def residual(self, t, y, yp, res):
        """GGL residual for ``y = [q, v, lam, mu]`` (IDA's ``resfn``)."""
        n, m = self.n_coordinates, self.n_constraints
        q, v, lam, mu = y[:n], y[n:2 * n], y[2 * n:2 * n + m], y[2 * n + m:]
        jac = self.constraint_jacobian(q)
        res[:n] = yp[:n] - v + jac.T @ mu
        res[n:2 * n] = self.mass(q) @ yp[n:2 * n] - self.force(t, q, v) + jac.T @ lam
        res[2 * n:2 * n + m] = self.constraint(q)
        res[2 * n + m:] = jac @ v

    def consistent_start(self, t0, q0, v0):
        """``(y0, yp0)`` with the multiplier ``lam`` from the acceleration-level constraint
        ``G a + (dG/dt) v = 0`` and ``mu = 0``; ``q0, v0`` must satisfy both constraints."""
        n, m = self.n_coordinates, self.n_constraints
        q0, v0 = np.asarray(q0, dtype=float), np.asarray(v0, dtype=float)
        scale = max(1.0, float(np.max(np.abs(q0))))
        if np.max(np.abs(self.constraint(q0))) > 1e-10 * scale:
            raise ScenarioError("initial_state: the positions violate the constraints g(q) = 0")
        jac = self.constraint_jacobian(q0)
        if np.max(np.abs(jac @ v0)) > 1e-10 * max(1.0, float(np.max(np.abs(v0)))):
            raise ScenarioError("initial_state: the velocities violate the constraints G(q) v = 0")
        h = 1e-6 * scale
        jac_dot_v = (self.constraint_jacobian(q0 + h * v0) - self.constraint_jacobian(q0 - h * v0)) / (2 * h) @ v0
        system = np.zeros((n + m, n + m))
        system[:n, :n] = self.mass(q0)
        system[:n, n:] = jac.T
        system[n:, :n] = jac
        rhs = np.concatenate([self.force(t0, q0, v0), -jac_dot_v])
        sol = np.linalg.solve(system, rhs)
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
    drift = max(float(np.max(np.abs(problem.constraint(row[:n])))) for row in y)
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
        constraint=lambda q: np.array([0.5 * (q[0] ** 2 + q[1] ** 2 - length**2)]),
        constraint_jacobian=lambda q: q.reshape(1, 2),
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

    def force(t, q, v):
        k.rhs(k.KIND_WHEELSET, t, np.array([q[0], q[3], v[0], v[3]]), p, surf, out)
        return np.array([out[2], -model.mass * gravity, 0.0, out[3]])

    return GGLProblem(
        n_coordinates=4,
        n_constraints=2,
        mass=lambda q: mass_matrix,
        force=force,
        constraint=lambda q: jac @ q,
        constraint_jacobian=lambda q: jac,
    )
