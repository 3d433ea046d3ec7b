"""What a Python caller pays to reach a compiled right-hand side, in one run:

- per call: ``kernels.rhs`` (the look-up by model kind and argument types, then the compiled
  entry point), ``kernels.rhs.bind(...)`` (the entry point itself, looked up once), and the plain
  numpy right-hand side of benchmarks/dynamics.py (what a user would write);
- a linearisation (the wheelset's central-difference Jacobian, 8 calls) through each;
- scipy's ``solve_ivp`` (RK45 and LSODA, rtol 1e-8) on the hunting wheelset of
  benchmarks/dynamics.py through each, with the results compared bit for bit.

    python benchmarks/dispatch.py

Times are the best of several repeats after a warm-up (numba's cache loaded).
"""

import os
import sys
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dynamics import T_END, WHEELSET, best_of, plain_wheelset_rhs  # noqa: E402

from railwear.dynamics import WheelsetModel, kernels, linear_critical_speed  # noqa: E402
from railwear.dynamics.linear import numerical_state_matrix  # noqa: E402


def per_call(fn, n=20000, repeats=7):
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        best = min(best, (time.perf_counter() - t0) / n)
    return best


def looked_up_state_matrix(kind, params, n, surf, step=1e-7):
    """numerical_state_matrix as it was: every call through the look-up."""
    jac, f_plus, f_minus = np.empty((n, n)), np.empty(n), np.empty(n)
    for j in range(n):
        y = np.zeros(n)
        y[j] = step
        kernels.rhs(kind, 0.0, y, params, surf, f_plus)
        y[j] = -step
        kernels.rhs(kind, 0.0, y, params, surf, f_minus)
        jac[:, j] = (f_plus - f_minus) / (2.0 * step)
    return jac


def main():
    vc = linear_critical_speed(**WHEELSET)
    case = dict(WHEELSET, speed=1.2 * vc, flange_clearance=5e-3, flange_stiffness=1.5e7, friction_coefficient=0.3,
                wheel_load=50e3)
    model = WheelsetModel(**case, initial_lateral_displacement=1e-3)
    plain = plain_wheelset_rhs(**case)
    p, surf, y0, kind = model.params(), model.surface(), model.initial_state(), model.kind
    out = np.empty(4)
    entry = kernels.rhs.bind(kind, 0.0, y0.copy(), p, surf, out)
    kernels.rhs(kind, 0.0, y0, p, surf, out)

    print(f"load average {os.getloadavg()[0]:.1f}; best of 7 x 20 000 calls")
    looked_up = per_call(lambda: kernels.rhs(kind, 0.5, y0, p, surf, out))
    bound = per_call(lambda: entry(kind, 0.5, y0, p, surf, out))
    numpy_rhs = per_call(lambda: plain(0.5, y0))
    print(f"per call: kernels.rhs {looked_up * 1e6:.2f} us, bound entry point {bound * 1e6:.2f} us, "
          f"plain numpy RHS {numpy_rhs * 1e6:.2f} us; look-up / bound {looked_up / bound:.1f}")

    a = looked_up_state_matrix(kind, p, 4, surf)
    b = numerical_state_matrix(kind, p, 4, surf)
    assert np.array_equal(a, b)
    t_old = per_call(lambda: looked_up_state_matrix(kind, p, 4, surf), n=2000)
    t_new = per_call(lambda: numerical_state_matrix(kind, p, 4, surf), n=2000)
    print(f"linearisation (4 states, 8 calls): through the look-up {t_old * 1e6:.1f} us, bound {t_new * 1e6:.1f} us "
          f"(ratio {t_old / t_new:.2f}); Jacobians equal bit for bit")

    def looked_up_rhs(t, y):
        f = np.empty(4)
        kernels.rhs(kind, t, y, p, surf, f)
        return f

    def bound_rhs(t, y):
        f = np.empty(4)
        entry(kind, t, y, p, surf, f)
        return f

    t_eval = np.linspace(0.0, T_END, 2001)
    for method in ("RK45", "LSODA"):
        def solve(fun):
            return solve_ivp(fun, (0.0, T_END), y0, method=method, t_eval=t_eval, rtol=1e-8, atol=1e-10)

        times = {}
        for name, fun in (("look-up", looked_up_rhs), ("bound", bound_rhs), ("plain numpy", plain)):
            times[name], sol = best_of(2, lambda: solve(fun))
            if name == "look-up":
                reference = sol
            elif name == "bound":
                assert np.array_equal(sol.y, reference.y) and sol.nfev == reference.nfev
        print(f"scipy {method}, {reference.nfev} evaluations: compiled RHS through the look-up {times['look-up']:.3f} s, "
              f"bound {times['bound']:.3f} s, plain numpy RHS {times['plain numpy']:.3f} s; plain / bound "
              f"{times['plain numpy'] / times['bound']:.2f} (bound and look-up bit for bit equal)")


if __name__ == "__main__":
    main()
