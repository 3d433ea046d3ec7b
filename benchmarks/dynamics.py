"""Benchmark of railwear's compiled integrators against scipy.integrate.solve_ivp.

The same wheelset hunting case (1.2 times the linear critical speed, flange dead band and
saturation, 10 s) to the same tolerances with:

- railwear's compiled Dormand-Prince 5(4) and Rosenbrock 2(3) (integrator loop and right-hand side
  compiled together);
- ``solve_ivp`` with RK45 and LSODA calling the same compiled right-hand side from Python.

Then one wheel revolution of the disk wheel with a 512-cell radius deviation. Prints times, right-
hand-side evaluations per second and the ratios. Run: ``python benchmarks/dynamics.py``.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.integrate import solve_ivp

from railwear.dynamics import DiskWheelModel, WheelsetModel, linear_critical_speed
from railwear.dynamics import integrators as integ
from railwear.dynamics import kernels

RTOL, ATOL = 1e-8, 1e-10
T_END = 10.0
WHEELSET = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6,
                f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)


def best_of(n, fn):
    """Smallest wall time of ``n`` runs and the last result."""
    best, result = np.inf, None
    for _ in range(n):
        t0 = time.perf_counter()
        result = fn()
        best = min(best, time.perf_counter() - t0)
    return best, result


def wheelset_case():
    vc = linear_critical_speed(**WHEELSET)
    model = WheelsetModel(speed=1.2 * vc, **WHEELSET, flange_clearance=5e-3, flange_stiffness=1.5e7,
                          friction_coefficient=0.3, wheel_load=50e3, initial_lateral_displacement=1e-3)
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    t_eval = np.linspace(0.0, T_END, 2001)
    rows = []

    def compiled(method):
        out = integ.integrate(model.kind, p, surf, y0, 0.0, T_END, RTOL, ATOL, method, 0.0, np.inf, 10**8, t_eval, 1,
                              False, 1e6, np.zeros(0))
        return out[1][: out[2]], int(out[6][integ.STAT_NFEV])

    t0 = time.perf_counter()
    compiled(integ.METHOD_DOPRI5)
    compiled(integ.METHOD_ROSENBROCK)
    first_call = time.perf_counter() - t0

    for name, method in (("railwear dopri5", integ.METHOD_DOPRI5), ("railwear rosenbrock", integ.METHOD_ROSENBROCK)):
        wall, (ys, nfev) = best_of(5, lambda: compiled(method))
        rows.append((name, wall, nfev, ys))

    def rhs(t, y):
        out = np.empty(4)
        kernels.rhs(model.kind, t, y, p, surf, out)
        return out

    for method in ("RK45", "LSODA"):
        wall, sol = best_of(2, lambda: solve_ivp(rhs, (0.0, T_END), y0, method=method, t_eval=t_eval, rtol=RTOL,
                                                 atol=ATOL))
        rows.append((f"solve_ivp {method}", wall, int(sol.nfev), sol.y.T))

    reference = rows[0][3]
    print(f"Wheelset hunting at {model.speed:.1f} m/s (1.2 Vc), {T_END:g} s, rtol {RTOL:g}, atol {ATOL:g}")
    print(f"(first calls incl. loading the compiled cache or compiling: {first_call:.2f} s)")
    print(f"{'solver':<22}{'time [s]':>11}{'RHS evals':>11}{'evals/s':>12}{'time / dopri5':>15}{'max |dy| [m]':>14}")
    for name, wall, nfev, ys in rows:
        dev = np.max(np.abs(ys[:, 0] - reference[:, 0]))
        print(f"{name:<22}{wall:>11.4f}{nfev:>11d}{nfev / wall:>12.3e}{wall / rows[0][1]:>15.1f}{dev:>14.2e}")
    dae_case(model, t_eval, rows[0][1])
    return rows


def dae_case(model, t_eval, reference_time, roll_inertia=700.0):
    """The same case as a GGL DAE with roll and vertical motion (IDA, Python residual). Its ODE
    twin has the lateral mass ``m + I_x (lam/e)^2``; the deviation is measured against that twin."""
    import dataclasses

    from railwear.dynamics.dae import solve_ggl, wheelset_ggl_problem

    problem = wheelset_ggl_problem(model, roll_inertia)
    calls = [0]
    force = problem.force

    def counted_force(t, q, v):  # called once per residual evaluation
        calls[0] += 1
        return force(t, q, v)

    problem = dataclasses.replace(problem, force=counted_force)
    y0 = model.initial_lateral_displacement
    q0 = np.array([y0, 0.0, model.conicity * y0 / model.half_gauge, 0.0])
    t0 = time.perf_counter()
    sol = solve_ggl(problem, t_eval, q0, np.zeros(4), rtol=RTOL, atol=ATOL)
    wall = time.perf_counter() - t0
    twin = dataclasses.replace(model, mass=model.mass + roll_inertia * (model.conicity / model.half_gauge) ** 2)
    out = integ.integrate(twin.kind, twin.params(), twin.surface(), twin.initial_state(), 0.0, T_END, RTOL, ATOL,
                          integ.METHOD_DOPRI5, 0.0, np.inf, 10**8, t_eval, 1, False, 1e6, np.zeros(0))
    dev = np.max(np.abs(sol.q[:, 0] - out[1][: out[2], 0]))
    print(f"{'GGL DAE, IDA':<22}{wall:>11.4f}{calls[0]:>11d}{calls[0] / wall:>12.3e}{wall / reference_time:>15.1f}"
          f"{dev:>14.2e}  (against its ODE twin; constraint drift {sol.constraint_drift:.1e} m)")


def disk_wheel_case():
    rng = np.random.default_rng(1)
    n_cells = 512
    x = 2 * np.pi * np.arange(n_cells) / n_cells
    u = sum(1e-6 * rng.standard_normal() * np.cos(k * x + rng.uniform(0, 2 * np.pi)) for k in range(1, 21))
    model = DiskWheelModel(speed=30.0, radius=0.46, wheel_mass=600.0, wheel_inertia=60.0, static_load=70e3,
                           hertz_constant=1.05e11, primary_stiffness=1e6, primary_damping=4e4, sprung_mass=5000.0,
                           rail_mass=150.0, pad_stiffness=1e8, pad_damping=5e4, f11=1.15e7,
                           friction_coefficient=0.3, traction_torque=5e3, patch_half_length=6e-3,
                           radius_deviation=u)
    revolutions = 50
    t_end = revolutions * 2 * np.pi * model.radius / model.speed
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    print(f"\nDisk wheel, 512-cell radius deviation, P2 track, {model.speed:g} m/s, {revolutions} revolutions")
    print(f"{'rtol':>8}{'cell energy':>12}{'time/rev [ms]':>15}{'steps/rev':>11}{'RHS evals/s':>13}")
    for rtol, energy in ((1e-6, False), (1e-8, False), (1e-6, True)):
        def run():
            cells = np.zeros(n_cells if energy else 0)
            return integ.integrate(model.kind, p, surf, y0, 0.0, t_end, rtol, 1e-13, integ.METHOD_DOPRI5, 0.0,
                                   np.inf, 10**8, np.zeros(0), 100, True, 1e6, cells)

        run()
        wall, out = best_of(3, run)
        stats = out[6]
        print(f"{rtol:>8.0e}{'yes' if energy else 'no':>12}{1e3 * wall / revolutions:>15.3f}"
              f"{stats[integ.STAT_NACCEPT] / revolutions:>11.0f}{stats[integ.STAT_NFEV] / wall:>13.3e}")


if __name__ == "__main__":
    wheelset_case()
    disk_wheel_case()
