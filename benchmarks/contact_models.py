"""Speed of the contact table with one Hertz point, shared multi-Hertz points and
semi-Hertzian patches per wheel.

Run:  python benchmarks/contact_models.py

A contact table of 2001 lateral shifts (-10 ... 10 mm) for S1002 / UIC60 1:40 with each
``contact_model``; the first call of each compiles (numba caches on disk), so every model is
timed as the best of three calls after one warm-up. Prints the wall times and the ratio to the
single-point Hertz table, and checks that every wheel's vertical forces sum to its load.
"""

import time

import numpy as np

from railwear.geometry import contact_table, load_profile


def timed(model, shifts, wheel, rail, repeats=3):
    contact_table(wheel, rail, y=shifts[:11], contact_model=model)  # compile / load the cache
    best = np.inf
    for _ in range(repeats):
        start = time.perf_counter()
        table = contact_table(wheel, rail, y=shifts, contact_model=model)
        best = min(best, time.perf_counter() - start)
    return best, table


def main():
    wheel, rail = load_profile("S1002"), load_profile("UIC60")
    shifts = np.round(np.linspace(-0.010, 0.010, 2001), 12)
    base, _ = timed("hertz", shifts, wheel, rail)
    print(f"contact table, 2001 shifts, hertz          : {base:6.2f} s")
    for model in ("multi-hertz", "semi-hertzian"):
        wall, table = timed(model, shifts, wheel, rail)
        vertical = (table.point_normal_force * np.cos(table.point_contact_angle.fillna(0.0))).sum("point")
        error = float(np.abs(vertical / (0.5 * table.attrs["axle_load"]) - 1).max())
        shared = int((table.contact_count > 1).sum())
        print(f"contact table, 2001 shifts, {model:14s} : {wall:6.2f} s  ratio {wall / base:5.2f}  "
              f"(load error {error:.1e}, {shared} wheels with more than one contact)")


if __name__ == "__main__":
    main()
