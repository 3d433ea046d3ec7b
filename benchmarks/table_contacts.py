"""Cost of one right-hand side of the wheelset on S1002 / UIC60 contact tables: one Hertz point
per wheel, every semi-Hertzian contact under the cubic law, and every contact by strip-wise
FASTSIM (``creep_law="strip-fastsim"``).

Run:  python benchmarks/table_contacts.py

A compiled loop evaluates the right-hand side at 1000 random states (lateral displacement within
8 mm, yaw 2 mrad, rates 0.05); best of five after a warm-up. Prints ns per right-hand side and the
ratio to the Hertz table's.
"""

import time

import numpy as np
from numba import literally, njit

from railwear.dynamics import TableWheelsetModel
from railwear.dynamics.kernels import ByLiteral, rhs_call
from railwear.geometry import contact_table, load_profile


@njit(cache=True)
def _loop(kind, ys, p, surf, out):
    literally(kind)
    acc = 0.0
    for i in range(ys.shape[0]):
        rhs_call(kind, 0.0, ys[i], p, surf, out)
        acc += out[2]
    return acc


loop = ByLiteral(_loop, "the right-hand side at every row of ys")


def best_ns(model, ys, repeats=5):
    p, surf, out = model.params(), model.surface(), np.zeros(4)
    loop(model.kind, ys, p, surf, out)
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        loop(model.kind, ys, p, surf, out)
        best = min(best, time.perf_counter() - start)
    return 1e9 * best / ys.shape[0]


def main():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    shifts = np.round(np.linspace(-0.010, 0.010, 201), 12)
    ys = np.random.default_rng(7).uniform(-1, 1, (1000, 4)) * np.array([8e-3, 2e-3, 0.05, 0.05])
    suspension = dict(speed=40.0, mass=1022.0, yaw_inertia=678.0, lateral_stiffness=1.823e6, yaw_stiffness=2e6,
                      friction_coefficient=0.3)
    hertz = contact_table(wheel, rail, y=shifts)
    semi = contact_table(wheel, rail, y=shifts, contact_model="semi-hertzian")
    cases = {"hertz, cubic": TableWheelsetModel(table=hertz, **suspension),
             "semi-hertzian, cubic": TableWheelsetModel(table=semi, **suspension),
             "semi-hertzian, strip-fastsim": TableWheelsetModel(table=semi, creep_law="strip-fastsim", **suspension)}
    base = None
    for label, model in cases.items():
        ns = best_ns(model, ys)
        base = base or ns
        print(f"{label:30s} {ns:9.0f} ns per right-hand side   x{ns / base:.1f}")


if __name__ == "__main__":
    main()
