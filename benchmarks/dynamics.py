"""Benchmark of railwear's compiled integrators against scipy.integrate.solve_ivp.

The same wheelset hunting case (1.2 times the linear critical speed, flange dead band and
saturation, 10 s) to the same tolerances with:

- railwear's compiled Dormand-Prince 5(4), Dormand-Prince 8(5,3) and Rosenbrock 2(3) (integrator
  loop and right-hand side compiled together; rejected steps across a flange switch are cut at
  it, and a table shows the explicit pairs with and without that);
- ``solve_ivp`` with RK45, DOP853 and LSODA calling the same compiled right-hand side from Python
  (the most favourable case for scipy);
- ``solve_ivp`` with RK45, DOP853 and LSODA calling ``plain_wheelset_rhs``, the wheelset written
  as a plain Python function from the equations of ``docs/dynamics.md``: what a user without
  railwear writes. It is an independent implementation on purpose (it calls nothing of railwear);
  ``tests/dynamics/test_benchmark_alternative.py`` checks that it equals the compiled kernel.

Every solver's error is the largest deviation of the lateral displacement from a reference run at
rtol 1e-13 (compiled DOP853, checked against ``solve_ivp`` DOP853). Besides the table at equal
tolerance, a tolerance sweep gives each solver's time against its error, and the times at equal
error (interpolated in log-log) give the fair ratio: the time to reach the same accuracy.

Then one wheel revolution of the disk wheel with a 512-cell radius deviation. Prints times, right-
hand-side evaluations per second and the ratios. Run: ``python benchmarks/dynamics.py``.
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.integrate import solve_ivp

from railwear.dynamics import DiskWheelModel, WheelsetModel, linear_critical_speed
from railwear.dynamics import integrators as integ
from railwear.dynamics import kernels

RTOL, ATOL = 1e-8, 1e-10
T_END = 10.0
SWEEP_RTOLS = (1e-6, 1e-7, 1e-8, 1e-9, 1e-10)  # atol = rtol / 100
TARGET_ERRORS = (1e-6, 1e-7, 1e-8)  # [m]
COMPILED = (("railwear dopri5", integ.METHOD_DOPRI5), ("railwear dop853", integ.METHOD_DOP853),
            ("railwear rosenbrock", integ.METHOD_ROSENBROCK))
WHEELSET = dict(mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2.0e6, f11=6.4e6,
                f22=5.9e6, half_gauge=0.7163, rolling_radius=0.4572, conicity=0.05)


def plain_wheelset_rhs(speed, mass, yaw_inertia, lateral_stiffness, yaw_stiffness, f11, f22, half_gauge,
                       rolling_radius, conicity, f23=0.0, f33=0.0, lateral_damping=0.0, yaw_damping=0.0,
                       wheel_load=50e3, friction_coefficient=math.inf, flange_clearance=math.inf,
                       flange_stiffness=0.0):
    """The suspended conical wheelset's right-hand side ``f(t, [y, psi, y', psi'])`` as a plain
    Python function for ``solve_ivp`` (returned): the alternative a user without railwear writes
    (SI units: m, rad, N, kg, m/s).

    Deliberately independent of railwear (written from the equations of ``docs/dynamics.md``, no
    railwear call), so the benchmark compares railwear with what a user would otherwise run.
    Per wheel (``s`` = +1 left at ``+e``, -1 right): ``xi = -s (e psi'/V + lam y/r0)``,
    ``eta = y'/V - psi``, ``phi = psi'/V - s lam/r0``; Kalker ``Fx = -f11 xi``,
    ``Fy = -f22 eta - f23 phi``, ``Mz = f23 eta - f33 phi``, scaled by the Johnson-Vermeulen cubic
    saturation of ``|(Fx, Fy)|`` at ``mu Q``. Flange: linear spring outside ``|y| <= clearance``.
    ``m y'' = Fy_L + Fy_R + F_flange - k_y y - c_y y'``,
    ``I psi'' = e (Fx_R - Fx_L) + Mz_L + Mz_R - k_psi psi - c_psi psi'``.
    """
    v, e, r0, lam = speed, half_gauge, rolling_radius, conicity
    limit = friction_coefficient * wheel_load

    def saturated(fx, fy, mz):
        """Johnson-Vermeulen: ``r = |F| / (mu Q)``, factor ``1 - r/3 + r^2/27`` below 3, ``1/r`` above."""
        r = math.hypot(fx, fy) / limit
        c = 1.0 - r / 3.0 + r * r / 27.0 if r < 3.0 else 1.0 / r
        return c * fx, c * fy, c * mz

    def rhs(t, state):
        y, psi, vy, vpsi = state
        eta = vy / v - psi
        longitudinal = e * vpsi / v + lam * y / r0
        fx_l, fy_l, mz_l = saturated(f11 * longitudinal, -f22 * eta - f23 * (vpsi / v - lam / r0),
                                     f23 * eta - f33 * (vpsi / v - lam / r0))
        fx_r, fy_r, mz_r = saturated(-f11 * longitudinal, -f22 * eta - f23 * (vpsi / v + lam / r0),
                                     f23 * eta - f33 * (vpsi / v + lam / r0))
        flange = 0.0
        if y > flange_clearance:
            flange = -flange_stiffness * (y - flange_clearance)
        elif y < -flange_clearance:
            flange = -flange_stiffness * (y + flange_clearance)
        force = fy_l + fy_r + flange - lateral_stiffness * y - lateral_damping * vy
        moment = e * (fx_r - fx_l) + mz_l + mz_r - yaw_stiffness * psi - yaw_damping * vpsi
        return np.array([vy, vpsi, force / mass, moment / yaw_inertia])

    return rhs


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
    case = dict(WHEELSET, speed=1.2 * vc, flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3,
                wheel_load=50e3)
    model = WheelsetModel(**case, initial_lateral_displacement=1e-3)
    plain_rhs = plain_wheelset_rhs(**case)
    p, surf, y0 = model.params(), model.surface(), model.initial_state()
    t_eval = np.linspace(0.0, T_END, 2001)

    def compiled(method, rtol, atol, cut=True, stats=False):
        out = integ.integrate(model.kind, p, surf, y0, 0.0, T_END, rtol, atol, method, 0.0, np.inf, 10**8, t_eval, 1,
                              False, 1e6, np.zeros(0), cut)
        return out[1][: out[2]], (out[6] if stats else int(out[6][integ.STAT_NFEV]))

    entry = kernels.rhs.bind(model.kind, 0.0, y0.copy(), p, surf, np.empty(4))  # the compiled entry point

    def rhs(t, y):
        out = np.empty(4)
        entry(model.kind, t, y, p, surf, out)
        return out

    def scipy_run(method, rtol, atol, fun=rhs):
        sol = solve_ivp(fun, (0.0, T_END), y0, method=method, t_eval=t_eval, rtol=rtol, atol=atol)
        return sol.y.T, int(sol.nfev)

    solvers = [(name, lambda r, a, m=method: compiled(m, r, a), 5) for name, method in COMPILED]
    solvers += [(f"scipy {m}, compiled", lambda r, a, m=m: scipy_run(m, r, a), 2) for m in ("RK45", "DOP853", "LSODA")]
    solvers += [(f"scipy {m}, plain", lambda r, a, m=m: scipy_run(m, r, a, plain_rhs), 2)
                for m in ("RK45", "DOP853", "LSODA")]

    t0 = time.perf_counter()
    for _, method in COMPILED:
        compiled(method, RTOL, ATOL)
    first_call = time.perf_counter() - t0
    reference = compiled(integ.METHOD_DOP853, 1e-13, 1e-15)[0][:, 0]
    check = np.max(np.abs(scipy_run("DOP853", 1e-13, 1e-15)[0][:, 0] - reference))
    plain_check = np.max(np.abs(scipy_run("DOP853", 1e-13, 1e-15, plain_rhs)[0][:, 0] - reference))

    def measure(run, repeats, rtol, atol):
        wall, (ys, nfev) = best_of(repeats, lambda: run(rtol, atol))
        return wall, nfev, float(np.max(np.abs(ys[:, 0] - reference)))

    print(f"Wheelset hunting at {model.speed:.1f} m/s (1.2 Vc), {T_END:g} s, output at {t_eval.size} times")
    print(f"(first calls incl. loading the compiled cache or compiling: {first_call:.2f} s; reference: compiled "
          f"DOP853 at rtol 1e-13, {check:.1e} m from solve_ivp DOP853 at rtol 1e-13)")
    print(f"The plain Python RHS reproduces railwear's trajectory: solve_ivp DOP853 with it at rtol 1e-13 is "
          f"{plain_check:.1e} m from the reference over {T_END:g} s (largest |y| {np.max(np.abs(reference)):.2e} m)")
    print("'scipy X, compiled': solve_ivp calling railwear's compiled RHS through a Python wrapper (favourable to "
          "scipy);\n'scipy X, plain': solve_ivp calling a plain numpy RHS, what a user without railwear writes.")
    print(f"\nEqual tolerance, rtol {RTOL:g}, atol {ATOL:g}:")
    print(f"{'solver':<26}{'time [s]':>11}{'RHS evals':>11}{'evals/s':>12}{'time / dopri5':>15}{'max |dy| [m]':>14}")
    rows = [(name, *measure(run, repeats, RTOL, ATOL)) for name, run, repeats in solvers]
    for name, wall, nfev, dev in rows:
        print(f"{name:<26}{wall:>11.4f}{nfev:>11d}{nfev / wall:>12.3e}{wall / rows[0][1]:>15.1f}{dev:>14.2e}")
    dae_case(model, t_eval, rows[0][1])
    switch_cuts(compiled, reference)
    equal_accuracy([(name, run, repeats) for name, run, repeats in solvers if "rosenbrock" not in name], measure)
    return rows


def switch_cuts(compiled, reference):
    """The compiled explicit pairs with and without cutting rejected steps at the flange switches
    (``integrate(..., cut_at_switches)``) at ``RTOL``: time, evaluations, steps, deviation."""
    print(f"\nSteps cut at the flange switches, rtol {RTOL:g}, atol {ATOL:g} (railwear's default is on):")
    print(f"{'solver':<26}{'cuts':>6}{'time [s]':>11}{'RHS evals':>11}{'accepted':>10}{'rejected':>10}"
          f"{'max |dy| [m]':>14}")
    for name, method in COMPILED[:2]:
        for cut in (False, True):
            wall, (ys, stats) = best_of(5, lambda: compiled(method, RTOL, ATOL, cut, True))
            print(f"{name:<26}{'on' if cut else 'off':>6}{wall:>11.4f}{stats[integ.STAT_NFEV]:>11d}"
                  f"{stats[integ.STAT_NACCEPT]:>10d}{stats[integ.STAT_NREJECT]:>10d}"
                  f"{np.max(np.abs(ys[:, 0] - reference)):>14.2e}")


def equal_accuracy(solvers, measure):
    """Tolerance sweep (``SWEEP_RTOLS``) of each solver; times at the ``TARGET_ERRORS`` by log-log
    interpolation of time against error (where the sweep brackets the target)."""
    print(f"\nTolerance sweep, atol = rtol / 100: time [s] / max |dy| [m]")
    print(f"{'solver':<26}" + "".join(f"{f'rtol {r:g}':>20}" for r in SWEEP_RTOLS))
    at_target = {}
    for name, run, repeats in solvers:
        sweep = [measure(run, repeats, rtol, rtol / 100.0) for rtol in SWEEP_RTOLS]
        print(f"{name:<26}" + "".join(f"{f'{w:.4f} / {e:.1e}':>20}" for w, _, e in sweep))
        errors = np.array([e for _, _, e in sweep])
        walls = np.array([w for w, _, _ in sweep])
        order = np.argsort(errors)
        at_target[name] = [float(np.exp(np.interp(np.log(target), np.log(errors[order]), np.log(walls[order]),
                                                  left=np.nan, right=np.nan))) for target in TARGET_ERRORS]
    print("\nTime [s] to reach the same error (interpolated; - where the sweep does not reach it), and the ratio "
          "to the fastest compiled solver:")
    print(f"{'solver':<26}" + "".join(f"{f'error {e:g} m':>22}" for e in TARGET_ERRORS))
    best = np.nanmin([at_target[name] for name in at_target if name.startswith("railwear")], axis=0)
    for name, times in at_target.items():
        cells = [f"{'-':>22}" if np.isnan(w) else f"{f'{w:.4f} ({w / b:.1f}x)':>22}" for w, b in zip(times, best)]
        print(f"{name:<26}" + "".join(cells))


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
    print(f"{'GGL DAE, IDA':<26}{wall:>11.4f}{calls[0]:>11d}{calls[0] / wall:>12.3e}{wall / reference_time:>15.1f}"
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
    print(f"{'method':>8}{'rtol':>8}{'cell energy':>12}{'time/rev [ms]':>15}{'steps/rev':>11}{'RHS evals/s':>13}")
    cases = [("dopri5", 1e-6, False), ("dopri5", 1e-8, False), ("dop853", 1e-6, False), ("dop853", 1e-8, False),
             ("dopri5", 1e-6, True)]
    for method, rtol, energy in cases:
        def run():
            cells = np.zeros(n_cells if energy else 0)
            return integ.integrate(model.kind, p, surf, y0, 0.0, t_end, rtol, 1e-13, integ.METHODS[method], 0.0,
                                   np.inf, 10**8, np.zeros(0), 100, True, 1e6, cells)

        run()
        wall, out = best_of(3, run)
        stats = out[6]
        print(f"{method:>8}{rtol:>8.0e}{'yes' if energy else 'no':>12}{1e3 * wall / revolutions:>15.3f}"
              f"{stats[integ.STAT_NACCEPT] / revolutions:>11.0f}{stats[integ.STAT_NFEV] / wall:>13.3e}")


if __name__ == "__main__":
    wheelset_case()
    disk_wheel_case()
